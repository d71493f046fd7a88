//! The JSON API. Each handler checks its request against [`Limits`],
//! runs the work of `clapper-app` in a computation slot and answers JSON
//! (or SVG, HTML, WAV, NDJSON where said).

use clapper_core::Choice;
use std::convert::Infallible;
use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::rejection::QueryRejection;
use axum::extract::{Path, Query, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use axum::Json;
use clapper_app::animate::{AnimateOptions, Arrangement};
use clapper_app::chart::ChartRequest;
use clapper_app::clapper_design::{design, DesignRequest};
use clapper_app::diagnosis::{diagnose_bells, report_page, DiagnoseRequest};
use clapper_app::listening::{analyse, figure, StimulusSet, DEFAULT_RATE_HZ};
use clapper_app::simulate::{simulate_traced, SimulateRequest};
use clapper_app::strikes::Learning;
use clapper_core::chart::sweep_cells_until;
use clapper_core::listening::Answer;
use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::{ApiError, AppState, Limits};

type Body_<T> = Result<Object<T>, ApiError>;

/// The request's JSON, or a 4xx naming what is wrong with it.
fn body<T>(b: Body_<T>) -> Result<T, ApiError> {
    Ok(b?.0)
}

/// A request body that is a JSON object read as `T`. serde would also read
/// a struct from an array (`[]` gave the lab bell's default request); a
/// request is always an object of named options.
pub(crate) struct Object<T>(pub T);

impl<S: Send + Sync, T: serde::de::DeserializeOwned> axum::extract::FromRequest<S> for Object<T> {
    type Rejection = ApiError;

    async fn from_request(req: axum::extract::Request, state: &S) -> Result<Self, ApiError> {
        let json = req
            .headers()
            .get(header::CONTENT_TYPE)
            .and_then(|v| v.to_str().ok())
            .and_then(|v| v.split(';').next())
            .is_some_and(|m| {
                let m = m.trim().to_ascii_lowercase();
                m == "application/json" || (m.starts_with("application/") && m.ends_with("+json"))
            });
        if !json {
            return Err(ApiError::Limit(
                axum::http::StatusCode::UNSUPPORTED_MEDIA_TYPE,
                "Expected request with `Content-Type: application/json` (send JSON with Content-Type: application/json)"
                    .into(),
            ));
        }
        // Within the route's body limit, as every extractor of the body.
        let bytes = Bytes::from_request(req, state).await.map_err(|r| {
            let text = r.body_text().replace('\n', " ");
            crate::uploads::body_rejection(r, || format!("request body too large: {text}"))
        })?;
        if bytes.iter().find(|b| !b.is_ascii_whitespace()) != Some(&b'{') {
            return Err(ApiError::BadRequest(
                "the request body must be a JSON object of options, such as {\"preset\": \"lab\"} ({} for every default)"
                    .into(),
            ));
        }
        // Axum's reading names the field a bad value is in.
        Ok(Object(Json::<T>::from_bytes(&bytes).map_err(ApiError::from)?.0))
    }
}

/// `GET /api/health`: `{"status": "ok", "version", "max_body_bytes",
/// "max_recording_bytes"}`, the last two the largest request body and
/// recording this server takes (bytes), for a page to check a file
/// against when it is picked.
pub(crate) async fn health(State(s): State<AppState>) -> Json<serde_json::Value> {
    Json(json!({
        "status": "ok", "version": env!("CARGO_PKG_VERSION"),
        "max_body_bytes": s.limits.max_body_bytes, "max_recording_bytes": s.limits.max_recording_bytes,
    }))
}

/// `GET /api/presets`: the bells of Table 1 and where they sit on the chart.
pub(crate) async fn presets() -> Json<serde_json::Value> {
    use clapper_app::simulate::Preset;
    let list: Vec<_> = [Preset::Lab, Preset::GsmTenor]
        .into_iter()
        .map(|p| {
            let b = p.loaded();
            json!({
                "preset": p.name(),
                "name": b.name,
                "r_over_lc": b.bell.r_over_lc(),
                "lb_over_lc": b.bell.lb_over_lc(),
                "tb_s": b.bell.tb(),
                "tc_s": b.bell.tc(),
            })
        })
        .collect();
    Json(json!({ "presets": list }))
}

fn check_stiffness(limits: &Limits, k: Option<f64>) -> Result<(), ApiError> {
    match k {
        Some(k) if k > limits.max_stiffness => Err(ApiError::BadRequest(format!(
            "stiffness {k:e} N m/rad is above this server's limit of {:e}",
            limits.max_stiffness
        ))),
        _ => Ok(()),
    }
}

/// `POST /api/simulate`: the options of `clapper simulate` in, the object
/// of `clapper simulate --json` out.
pub(crate) async fn simulate(State(s): State<AppState>, req: Body_<SimulateRequest>) -> Result<Response, ApiError> {
    let req = body(req)?;
    check_stiffness(&s.limits, req.stiffness)?;
    let max = s.limits.max_strokes;
    let sim = s
        .jobs
        .run(move || Ok(clapper_app::simulate::simulate(&req, None, Some(max))?))
        .await?;
    Ok(Json(sim.report).into_response())
}

/// `POST /api/stroke`: as `/api/simulate`, with the Fig 9 plot:
/// `{"report": {...}, "plot_svg": "<svg ...>"}`.
pub(crate) async fn stroke(State(s): State<AppState>, req: Body_<SimulateRequest>) -> Result<Response, ApiError> {
    let req = body(req)?;
    check_stiffness(&s.limits, req.stiffness)?;
    let max = s.limits.max_strokes;
    let (report, svg) = s
        .jobs
        .run(move || {
            let sim = simulate_traced(&req, None, Some(max))?;
            let svg = sim.plot_svg()?;
            Ok((sim.report, svg))
        })
        .await?;
    Ok(Json(json!({"report": report, "plot_svg": svg})).into_response())
}

/// `POST /api/animate`: one bell or two side by side (e.g. before and
/// after a change), or a ring in rounds, animated on one clock:
/// `{"bells": [request, ..], "arrangement": "side-by-side" | "rounds",
/// "fps": 300}`, each request as `/api/simulate` takes. Answers the
/// player's data (`clapper_plot::animation::player_json`) and the sound
/// as a base64 WAV: `{"animation": {..}, "audio_wav_base64": ".."}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AnimateBody {
    bells: Vec<SimulateRequest>,
    #[serde(default)]
    arrangement: Arrangement,
    #[serde(default)]
    fps: Option<f64>,
}

/// What a page's animation may hold, by arrangement: most bells, most
/// strokes a bell, most and default frames a second. The page holds
/// every frame, so each bound keeps it under about 30,000 frames: two
/// bells of 8 strokes at up to 600 a second (1/10 slow motion at 60), or
/// 16 bells of 4 strokes at up to 150.
fn animate_bounds(a: Arrangement) -> (usize, usize, f64, f64) {
    match a {
        Arrangement::SideBySide => (2, 8, 600.0, 300.0),
        Arrangement::Rounds => (16, 4, 150.0, 120.0),
    }
}

pub(crate) async fn animate(State(s): State<AppState>, req: Body_<AnimateBody>) -> Result<Response, ApiError> {
    let req = body(req)?;
    let (max_bells, max_strokes, max_fps, fps) = animate_bounds(req.arrangement);
    if req.bells.is_empty() || req.bells.len() > max_bells {
        return Err(ApiError::BadRequest(format!(
            "bells: give 1 to {max_bells} bell requests here, not {}",
            req.bells.len()
        )));
    }
    let max_strokes = max_strokes.min(s.limits.max_strokes);
    for b in &req.bells {
        check_stiffness(&s.limits, b.stiffness)?;
        if b.strokes > max_strokes {
            return Err(ApiError::BadRequest(format!(
                "strokes {} is more than an animation here allows ({max_strokes})",
                b.strokes
            )));
        }
    }
    let fps = req.fps.unwrap_or(fps);
    if !(1.0..=max_fps).contains(&fps) {
        return Err(ApiError::BadRequest(format!(
            "fps {fps} is out of range: 1 to {max_fps}"
        )));
    }
    let arrangement = req.arrangement;
    let v = s
        .jobs
        .run(move || {
            use base64::Engine as _;
            let opts = AnimateOptions {
                fps,
                ..AnimateOptions::default()
            };
            let bells = req.bells.into_iter().map(|r| (r, None)).collect();
            let a = clapper_app::animate::animate(bells, arrangement, &opts)?;
            let wav = clapper_io::signal_file::wav_bytes(&a.sound, 0.9).map_err(clapper_app::AppError::Sound)?;
            Ok(json!({
                "animation": clapper_plot::animation::player_json(&a.animation),
                "audio_wav_base64": base64::engine::general_purpose::STANDARD.encode(wav),
            }))
        })
        .await?;
    Ok(Json(v).into_response())
}

/// One chart cell as the stream sends it:
/// `[sustained (1, 0, or -1 for a failed stroke), strike angle (deg),
/// strike velocity (rad/s), lift-off angle (deg), D, odd-struckness (ms)]`,
/// `null` where none. Odd-struckness is last so that readers of the first
/// five are unaffected; a symmetric bell's is 0 wherever it strikes.
fn cell_json(c: &clapper_core::chart::ChartCell) -> serde_json::Value {
    match &c.result {
        Ok(s) => json!([
            i32::from(s.sustained),
            s.strike_theta.map(f64::to_degrees),
            s.strike_phidot,
            s.liftoff_theta.map(f64::to_degrees),
            s.double_strike_index,
            s.odd_struck.map(|t| t * 1e3)
        ]),
        Err(_) => json!([-1, null, null, null, null, null]),
    }
}

fn line(v: &serde_json::Value) -> Result<Bytes, Infallible> {
    let mut text = v.to_string();
    text.push('\n');
    Ok(Bytes::from(text))
}

/// `POST /api/chart`: sweep a chart and stream it as NDJSON, one line a
/// block of rows, so that a page can draw it while it is computed:
///
/// - `{"type": "start", "nx", "ny", "xs", "ys", "styles", "total"}`
/// - `{"type": "cells", "start": k, "cells": [[...], ...]}`: cells from flat
///   index `k`, in the order of `clapper_core::chart::Chart::cells`
/// - `{"type": "done", "strokes", "errors", "seconds"}`, or
///   `{"type": "error", "message"}` if it stopped (time limit).
///
/// The cells are those of `clapper chart` for the same options.
pub(crate) async fn chart(State(s): State<AppState>, req: Body_<ChartRequest>) -> Result<Response, ApiError> {
    let req = body(req)?;
    check_stiffness(&s.limits, req.stiffness)?;
    let points = req.grid[0].saturating_mul(req.grid[1]);
    if points > s.limits.max_chart_points {
        return Err(ApiError::BadRequest(format!(
            "grid {} x {} is {points} points, more than this server sweeps in one request ({}); \
             use `clapper chart` (with --shard for many machines) for larger charts",
            req.grid[0], req.grid[1], s.limits.max_chart_points
        )));
    }
    let spec = req.spec()?;
    let permit = s.jobs.slot().await?;
    let deadline = Instant::now() + s.limits.job_time;
    let limit_s = s.limits.job_time.as_secs();
    let write_timeout = s.limits.write_timeout;
    let (tx, rx) = tokio::sync::mpsc::channel::<Result<Bytes, Infallible>>(4);
    let runtime = tokio::runtime::Handle::current();
    tokio::task::spawn_blocking(move || {
        let _slot = permit;
        // A line to the client, unless it has gone or does not take it
        // within the write timeout: then the sweep stops and the slot is
        // freed.
        let send = |v: Result<Bytes, Infallible>| runtime.block_on(tx.send_timeout(v, write_timeout)).is_ok();
        // Asked before every stroke: the time limit, and a client gone.
        let stop = || Instant::now() > deadline || tx.is_closed();
        let started = Instant::now();
        let styles: Vec<&str> = spec.styles.list().iter().map(|s| s.name()).collect();
        let total = spec.cell_count();
        let start = json!({
            "type": "start", "nx": spec.nx, "ny": spec.ny, "xs": spec.xs(), "ys": spec.ys(),
            "styles": styles, "total": total,
        });
        if !send(line(&start)) {
            return;
        }
        // Blocks of whole rows: big enough to keep both cores busy, small
        // enough that the page fills in about ten steps.
        let row = spec.nx * styles.len();
        let rows = (512usize.div_ceil(row)).min(spec.ny.div_ceil(10)).max(1);
        let block = rows * row;
        let (mut k, mut errors) = (0, 0);
        while k < total {
            let end = (k + block).min(total);
            let cells = match sweep_cells_until(&spec, k..end, &|_| {}, &stop) {
                Ok(Some(c)) => c,
                Ok(None) => {
                    // Out of time (a departed client hears nothing).
                    let _ = send(line(&json!({
                        "type": "error",
                        "message": format!("stopped at the server's time limit of {limit_s} s after {k} of {total} strokes"),
                    })));
                    return;
                }
                Err(e) => {
                    let _ = send(line(&json!({"type": "error", "message": e.to_string()})));
                    return;
                }
            };
            errors += cells.iter().filter(|c| c.result.is_err()).count();
            let out = json!({"type": "cells", "start": k, "cells": cells.iter().map(cell_json).collect::<Vec<_>>()});
            // The client has gone, or is not reading: stop sweeping.
            if !send(line(&out)) {
                return;
            }
            k = end;
        }
        let _ = send(line(&json!({
            "type": "done", "strokes": total, "errors": errors, "seconds": started.elapsed().as_secs_f64(),
        })));
    });
    let stream = tokio_stream::wrappers::ReceiverStream::new(rx);
    Ok((
        [(header::CONTENT_TYPE, "application/x-ndjson")],
        Body::from_stream(stream),
    )
        .into_response())
}

/// A recording sent as a bell file's or ring CSV's text (a sound file read
/// as text) is refused as such, not parsed: a parser's message about its
/// first bytes would not say what is wrong.
fn refuse_recording(req: &DiagnoseRequest) -> Result<(), ApiError> {
    for text in [&req.toml, &req.csv].into_iter().flatten() {
        let head = text.trim_start_matches('\u{feff}');
        let sound = ["RIFF", "RIFX", "RF64", "ID3", "fLaC", "OggS", "FORM"]
            .iter()
            .any(|m| head.starts_with(m));
        if sound || text.contains('\0') {
            return Err(ApiError::BadRequest(format!(
                "this is {}, not a bell file (TOML) or ring CSV; the strikes in a recording are heard by \
                 POST /api/strikes (the page's Strikes tab)",
                if sound {
                    "a recording (a sound file)"
                } else {
                    "a binary file"
                }
            )));
        }
    }
    Ok(())
}

/// `POST /api/diagnose`: a preset, bell file text or ring CSV in; the
/// object of `clapper diagnose --json` out, with `simulate`: each bell's
/// source for `/api/simulate` (`{"bell": its own file}` or `{"preset"}`).
pub(crate) async fn diagnose(State(s): State<AppState>, req: Body_<DiagnoseRequest>) -> Result<Response, ApiError> {
    let req = body(req)?;
    refuse_recording(&req)?;
    let (bells, _) = req.bells()?;
    let sources = req.one_bell_sources()?;
    let rep = s.jobs.run(move || Ok(diagnose_bells(&bells)?)).await?;
    // The page simulates a bell it marked on the chart with these.
    let mut out = serde_json::to_value(rep).map_err(|e| ApiError::Internal(e.to_string()))?;
    out["simulate"] = serde_json::Value::Array(sources);
    Ok(Json(out).into_response())
}

/// Most rows `POST /api/tower` rings: a peal's 5,040.
const MAX_TOWER_ROWS: usize = 5040;

/// `POST /api/tower`: `{"toml": RING} or {"csv": RING}, "tower": TOML?,
/// "request": {...the options of clapper tower...}}` in; the object of
/// `clapper tower --json` out.
pub(crate) async fn tower(
    State(s): State<AppState>,
    req: Body_<clapper_app::tower::TowerInput>,
) -> Result<Response, ApiError> {
    let req = body(req)?;
    let report = s
        .jobs
        .run(move || Ok(clapper_app::tower::tower_input(&req, Some(MAX_TOWER_ROWS))?.report))
        .await?;
    Ok(Json(report).into_response())
}

/// `POST /api/design-clapper`: `{"clapper": {...the [clapper] keys...},
/// "bell_period_s", "pivot_m", "target_period_s", "adjust"}` in; the object
/// of `clapper design-clapper --json` out.
pub(crate) async fn design_clapper(req: Body_<DesignRequest>) -> Result<Response, ApiError> {
    let req = body(req)?;
    Ok(Json(design(&req)?).into_response())
}

/// `POST /api/diagnose/report`: the same request; the HTML report of
/// `clapper diagnose --report` as a download.
pub(crate) async fn diagnose_report(
    State(s): State<AppState>,
    req: Body_<DiagnoseRequest>,
) -> Result<Response, ApiError> {
    let req = body(req)?;
    refuse_recording(&req)?;
    let (bells, source) = req.bells()?;
    let html = s
        .jobs
        .run(move || {
            let rep = diagnose_bells(&bells)?;
            Ok(report_page(&rep, &bells, &source)?)
        })
        .await?;
    Ok((
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (
                header::CONTENT_DISPOSITION,
                "attachment; filename=\"clapper-diagnosis.html\"",
            ),
        ],
        html,
    )
        .into_response())
}

/// The listening test's sounds, encoded once: 100 stimuli, then the reference.
pub(crate) struct Stimuli {
    wavs: Vec<Bytes>,
    trials: Vec<(String, f64, f64)>,
}

async fn stimuli(s: &AppState) -> Result<std::sync::Arc<Stimuli>, ApiError> {
    let jobs = s.jobs.clone();
    s.stimuli
        .get_or_try_init(|| async move {
            jobs.run(|| {
                let set = StimulusSet::new(DEFAULT_RATE_HZ)?;
                let mut wavs = vec![];
                for st in &set.stimuli {
                    wavs.push(Bytes::from(set.wav(&st.signal)?));
                }
                wavs.push(Bytes::from(set.wav(&set.reference)?));
                let trials = set
                    .stimuli
                    .iter()
                    .map(|st| (st.name.clone(), st.ratio, st.delay_ms))
                    .collect();
                Ok(std::sync::Arc::new(Stimuli { wavs, trials }))
            })
            .await
        })
        .await
        .cloned()
}

/// Query of `GET /api/listening/sheet`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SheetQuery {
    /// Listener number, from 0.
    #[serde(default)]
    listener: u64,
    /// Seed of the orders.
    #[serde(default = "one")]
    seed: u64,
}

fn one() -> u64 {
    1
}

/// `GET /api/listening/sheet?listener=L&seed=S`: listener L's 100 trials
/// in a fresh random order (the sheets of `clapper listening-test make`).
pub(crate) async fn listening_sheet(
    State(s): State<AppState>,
    q: Result<Query<SheetQuery>, QueryRejection>,
) -> Result<Response, ApiError> {
    let q = q?.0;
    let st = stimuli(&s).await?;
    let trials: Vec<_> = clapper_core::listening::order(q.seed, q.listener)
        .into_iter()
        .enumerate()
        .map(|(t, k)| {
            let (name, ratio, delay) = &st.trials[k];
            json!({
                "trial": t + 1, "stimulus": name, "amplitude_ratio": ratio, "delay_ms": delay,
                "url": format!("/api/listening/stimulus/{name}"),
            })
        })
        .collect();
    Ok(Json(json!({"listener": q.listener, "seed": q.seed, "reference": "/api/listening/stimulus/reference.wav", "trials": trials})).into_response())
}

/// `GET /api/listening/stimulus/{name}`: `s000.wav` .. `s099.wav` or
/// `reference.wav`, 16-bit mono at 44.1 kHz.
pub(crate) async fn listening_stimulus(
    State(s): State<AppState>,
    Path(name): Path<String>,
) -> Result<Response, ApiError> {
    let index = if name == "reference.wav" {
        Some(100)
    } else {
        name.strip_prefix('s')
            .and_then(|r| r.strip_suffix(".wav"))
            .filter(|d| d.len() == 3)
            .and_then(|d| d.parse::<usize>().ok())
            .filter(|k| *k < 100)
    };
    let index = index.ok_or_else(|| {
        ApiError::NotFound(format!(
            "no stimulus {name}: they are s000.wav to s099.wav and reference.wav"
        ))
    })?;
    let st = stimuli(&s).await?;
    Ok((
        [
            (header::CONTENT_TYPE, "audio/wav"),
            (header::CACHE_CONTROL, "public, max-age=86400"),
        ],
        st.wavs[index].clone(),
    )
        .into_response())
}

/// One answer in JSON.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AnswerJson {
    listener: String,
    amplitude_ratio: f64,
    delay_ms: f64,
    /// +1 single strike, -1 double strike.
    answer: i8,
    #[serde(default)]
    trial: Option<usize>,
    #[serde(default)]
    stimulus: Option<String>,
}

/// Most answers in one request: 1000 listeners' full sheets.
const MAX_ANSWERS: usize = 100_000;

/// Answers given as JSON or as the text of filled answer sheets.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct AnswersRequest {
    #[serde(default)]
    answers: Vec<AnswerJson>,
    #[serde(default)]
    csv: Option<String>,
}

impl AnswersRequest {
    fn answers(self) -> Result<Vec<Answer>, ApiError> {
        let mut out = vec![];
        for (k, a) in self.answers.into_iter().enumerate() {
            if a.answer != 1 && a.answer != -1 {
                return Err(ApiError::BadRequest(format!(
                    "answer {}: {} is neither 1 (single strike) nor -1 (double strike)",
                    k + 1,
                    a.answer
                )));
            }
            out.push(Answer {
                listener: a.listener,
                ratio: a.amplitude_ratio,
                delay_ms: a.delay_ms,
                answer: a.answer,
            });
        }
        if let Some(text) = &self.csv {
            out.extend(
                clapper_io::answers::parse_answers(text, "answers").map_err(|e| ApiError::BadRequest(e.to_string()))?,
            );
        }
        if out.len() > MAX_ANSWERS {
            return Err(ApiError::BadRequest(format!(
                "{} answers: at most {MAX_ANSWERS} in one request",
                out.len()
            )));
        }
        Ok(out)
    }
}

/// `POST /api/listening/parse`: `{"csv": "..."}` (filled answer sheets)
/// in, `{"answers": [...]}` out: for uploading answers into the page.
pub(crate) async fn listening_parse(req: Body_<AnswersRequest>) -> Result<Response, ApiError> {
    let answers = body(req)?.answers()?;
    let list: Vec<AnswerJson> = answers
        .into_iter()
        .map(|a| AnswerJson {
            listener: a.listener,
            amplitude_ratio: a.ratio,
            delay_ms: a.delay_ms,
            answer: a.answer,
            trial: None,
            stimulus: None,
        })
        .collect();
    Ok(Json(json!({ "answers": list })).into_response())
}

/// `POST /api/listening/analyse`: answers in (JSON list and/or CSV text);
/// the analysis of `clapper listening-test analyse --json` and the Fig 13
/// plot out: `{"analysis": {...}, "plot_svg": "<svg ...>"}`.
pub(crate) async fn listening_analyse(
    State(s): State<AppState>,
    req: Body_<AnswersRequest>,
) -> Result<Response, ApiError> {
    let answers = body(req)?.answers()?;
    let (rep, svg) = s
        .jobs
        .run(move || {
            let (an, rep) = analyse(&answers)?;
            let svg = clapper_plot::chart_figure_svg(&figure(&an)).map_err(clapper_app::AppError::from)?;
            Ok((rep, svg))
        })
        .await?;
    Ok(Json(json!({"analysis": rep, "plot_svg": svg})).into_response())
}

/// `POST /api/strikes?nominals=F1,F2,..[&double_min_ratio=R][&handbells=true][&timing=auto|plain|recording][&channel=N|mix|auto]`
/// (or `bells=N` for the nominals learned from the recording, as `--bells
/// N`; `handbells=true` as `--handbells`; `timing` as `--timing`, auto
/// unless asked; `channel` as `--channel`):
/// a recording of a ring (the body: a WAV file, mono or stereo, 8 to 192
/// kHz) heard as `clapper strikes` hears it: `{"report": {...}, "csv":
/// "...", "plot_svg": "<svg ..."}`, the report as `clapper strikes --json`,
/// the CSV as `--csv`, the plot as `--plot`.
pub(crate) async fn strikes(
    State(s): State<AppState>,
    q: Result<Query<StrikesQuery>, QueryRejection>,
    wav: Result<Bytes, axum::extract::rejection::BytesRejection>,
) -> Result<Response, ApiError> {
    let q = q?.0;
    let wav = wav.map_err(|r| {
        crate::uploads::body_rejection(r, || {
            format!(
                "recording too large: at most {} MiB here; longer ones belong to clapper strikes",
                s.limits.max_recording_bytes >> 20
            )
        })
    })?;
    // The bells: their nominals given, or how many, to be learned (as the CLI).
    let kind = if q.handbells.unwrap_or(false) {
        clapper_app::strikes::Voice::Handbell
    } else {
        clapper_app::strikes::Voice::Tower
    };
    let asked: clapper_app::strikes::TimingAsked = q.timing.as_deref().unwrap_or("auto").parse()?;
    let nominals = asked_nominals(&q, kind)?;
    let channel: clapper_io::signal_file::ChannelChoice = q
        .channel
        .as_deref()
        .unwrap_or("auto")
        .parse()
        .map_err(ApiError::BadRequest)?;
    if wav.is_empty() {
        return Err(ApiError::BadRequest(
            "no recording: send the WAV file as the request's body".into(),
        ));
    }
    let opts = clapper_app::strikes::strike_options(
        q.double_min_ratio
            .unwrap_or(clapper_app::strikes::DEFAULT_DOUBLE_MIN_RATIO),
    )?;
    let out = s
        .jobs
        .run(move || {
            let (sig, told) = clapper_io::signal_file::recording_from_bytes_chosen(&wav, "the recording", channel)
                .map_err(|e| clapper_app::AppError::Request(e.to_string()))?;
            let bells = q.bells.unwrap_or_default();
            let (nominals, learned) = match nominals {
                Some(n) => (n, None),
                None => match clapper_app::strikes::learned_or_none(&sig, bells, kind)? {
                    Learning::Learned(_, l) => (l.nominals.iter().map(|b| b.nominal_hz).collect(), Some(*l)),
                    // No bell's strike to learn from: the report of none, as the CLI's.
                    Learning::Unheard(mut report) => {
                        report.note_recording(&told);
                        return Ok(strikes_json(&report, &sig, &[])?);
                    }
                },
            };
            // Timed as the CLI times them, chosen on the same opening window.
            let head = clapper_app::strikes::opening(&sig);
            let chosen = clapper_app::strikes::choose_timing(&head, &nominals, kind, asked, &opts)?;
            let voices = &chosen.voices;
            let mut report = clapper_app::strikes::StrikesReport::timed(&sig, voices, &opts, chosen.timing())?;
            if let Some(l) = learned {
                report.note_learned(l);
            }
            report.note_choice(chosen.choice.clone());
            report.note_recording(&told);
            Ok(strikes_json(&report, &sig, voices)?)
        })
        .await?;
    Ok(Json(out).into_response())
}

/// A strikes `report` of `sig` heard about `voices` as the page takes it:
/// the report, its CSV and its plot.
fn strikes_json(
    report: &clapper_app::strikes::StrikesReport,
    sig: &clapper_signal::Signal,
    voices: &[clapper_signal::strikes::BellVoice],
) -> Result<serde_json::Value, clapper_app::AppError> {
    let csv = clapper_io::strike_file::csv_text(&report.csv_rows()).map_err(clapper_app::AppError::Request)?;
    let fig = clapper_app::strikes::StrikingFigure::new(report, sig, "the recording", voices)?;
    let svg = clapper_plot::striking_plot_svg(&fig.plot()).map_err(clapper_app::AppError::from)?;
    Ok(json!({ "report": report, "csv": csv, "plot_svg": svg }))
}

/// The nominals (Hz, treble first) a strikes query `q` gives, checked as
/// `kind`'s bells; `None` where it asks for them to be learned (`bells=N`).
fn asked_nominals(q: &StrikesQuery, kind: clapper_app::strikes::Voice) -> Result<Option<Vec<f64>>, ApiError> {
    Ok(match (&q.nominals, q.bells) {
        (Some(_), Some(_)) => {
            return Err(ApiError::BadRequest(
                "give the bells' nominals or how many bells ring (bells=N), not both".into(),
            ))
        }
        (None, None) => {
            return Err(ApiError::BadRequest(
                "say which bells to listen for: nominals=F1,F2,.. (Hz, treble first) or bells=N".into(),
            ))
        }
        (Some(n), None) => {
            let nominals: Vec<f64> = n
                .split(',')
                .map(|v| {
                    v.trim()
                        .parse::<f64>()
                        .map_err(|_| ApiError::BadRequest(format!("nominals: '{v}' is not a number (Hz)")))
                })
                .collect::<Result<_, _>>()?;
            // Refused here, before the recording is read.
            clapper_app::strikes::voices_from_nominals(&nominals, kind)?;
            Some(nominals)
        }
        (None, Some(_)) => None,
    })
}

/// The query of `POST /api/strikes`. A name it does not know is refused:
/// a misspelt `handbell=true` was ignored and the handbells heard as
/// tower bells (an independent tester, issue 43).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct StrikesQuery {
    /// Nominals (Hz), treble first, comma-separated.
    nominals: Option<String>,
    /// Without nominals: the bells ringing (3 to 16), their nominals learned.
    bells: Option<usize>,
    /// The double strike's least amplitude ratio (default 0.3).
    double_min_ratio: Option<f64>,
    /// Handbells (a strike note and its twelfth), as `--handbells`.
    handbells: Option<bool>,
    /// How strikes are timed: auto (the default), plain or recording, as `--timing`.
    timing: Option<String>,
    /// Which of the recording's channels are heard: a number (1 the
    /// first), mix or auto (the default), as `--channel`.
    channel: Option<String>,
}
