//! # clapper-web
//!
//! The browser front end of clapper: a local HTTP server (axum) that
//! serves one self-contained page (the chart explorer, bell diagnosis and
//! the listening test; its HTML, script and style are compiled into the
//! binary, nothing is fetched at run time) and the JSON API behind it.
//! The API is described at `/api` on a running server (the page is
//! `assets/api.html`).
//!
//! Only requests to names that cannot be rebound to this machine by
//! another site are answered (loopback names, IP literals, and the names
//! allowed; [`AllowedHosts`]): a page elsewhere cannot drive the API
//! through the user's browser. Every request is bounded: a body size, a grid size, a stroke count, a
//! penalty stiffness, a number of computations at once and a time limit
//! per computation ([`Limits`]). A request beyond a bound gets a 4xx (or
//! 503 when the server is busy) with a one-line JSON message, never a
//! crash; computations run on blocking threads so that the server keeps
//! answering while they work.
//!
//! ```no_run
//! # async fn demo() -> std::io::Result<()> {
//! let listener = tokio::net::TcpListener::bind("127.0.0.1:8080").await?;
//! let hosts = clapper_web::AllowedHosts::loopback();
//! clapper_web::serve(listener, clapper_web::Limits::default(), hosts, std::future::pending()).await
//! # }
//! ```

#![warn(missing_docs)]

mod api;
mod assets;
mod error;
mod explain;
mod hosts;
mod jobs;
mod uploads;

use std::future::Future;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::DefaultBodyLimit;
use axum::routing::{get, post};
use axum::Router;

pub use error::ApiError;
pub use hosts::AllowedHosts;

/// Per-request bounds of the server. The defaults keep one request of
/// each kind under a few seconds on a two-core machine and the server's
/// memory under a few hundred MB whatever is asked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Largest request body (bytes). Default 1 MiB: a ring file of 64
    /// bells or 100 listeners' answers is a few tens of kB.
    pub max_body_bytes: usize,
    /// Largest recording uploaded to `/api/strikes` (bytes). Default 64 MiB:
    /// twelve minutes of mono 16-bit sound at 44.1 kHz (a phone's WAV of a
    /// touch); longer recordings belong to `clapper strikes`.
    pub max_recording_bytes: usize,
    /// Most chart points (nx × ny) in one chart request. Default 40,000
    /// (200 × 200): 80,000 strokes, about 3 s on two cores; larger charts
    /// belong to `clapper chart`.
    pub max_chart_points: usize,
    /// Most strokes in one simulation. Default 100.
    pub max_strokes: usize,
    /// Largest penalty stiffness k (N m/rad). Default 1e9: stiffer springs
    /// need ever smaller steps and add nothing over the impact model.
    pub max_stiffness: f64,
    /// Computations running at once; further requests wait. Default 4.
    pub max_jobs: usize,
    /// How long a request waits for a free computation slot before it is
    /// answered 503 "busy". Default 20 s.
    pub queue_wait: Duration,
    /// Time limit of one computation. Default 60 s: a chart stops
    /// streaming and says so; other requests are answered 503. It is
    /// checked before every stroke, so it holds to within one stroke.
    pub job_time: Duration,
    /// How long a streamed chart waits for its client to take the next
    /// lines before it stops and frees its slot. Default 3 s: a page
    /// reading as it draws takes a block in milliseconds, so a client
    /// this slow is not reading, and four such must not hold every slot.
    pub write_timeout: Duration,
    /// How long a connection may take to send a request's headers, and
    /// how long it may stay open idle between requests. Default 10 s: a
    /// browser sends its headers in one packet and reuses or closes an
    /// idle connection within seconds; a client that sends nothing only
    /// holds a connection.
    pub header_timeout: Duration,
    /// How long a request body may pause between its parts. Default 10 s,
    /// for the same reason: an upload that stalls longer has stopped.
    pub body_timeout: Duration,
    /// Least rate a request body must keep once [`Limits::body_timeout`]
    /// has passed since it began (bytes/s). Default 8 KiB/s (64 kbit/s,
    /// below any phone network): a client trickling bytes to hold a
    /// connection is cut off after 10 s, and a 64 MiB recording may take
    /// up to two hours.
    pub min_upload_rate: u64,
    /// Most bytes of recordings being received at once, over all uploads
    /// (bytes); an upload beyond it is answered 503 at once. Each upload
    /// counts what its Content-Length announces (or the largest recording
    /// if it does not say). Default 256 MiB: four recordings of the
    /// largest size, which keeps the server's memory for bodies under
    /// that whatever the clients do.
    pub max_upload_bytes_in_flight: usize,
    /// Most connections open at once; further ones wait to be accepted
    /// until one closes. Default 512: under the usual limit of 1024 open
    /// files, and with the header timeout a flood of idle connections
    /// drains within 10 s.
    pub max_connections: usize,
    /// On shutdown, how long open connections get to finish before they
    /// are closed. Default 1 s.
    pub shutdown_grace: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_body_bytes: 1 << 20,
            max_recording_bytes: 64 << 20,
            max_chart_points: 40_000,
            max_strokes: 100,
            max_stiffness: 1e9,
            max_jobs: 4,
            queue_wait: Duration::from_secs(20),
            job_time: Duration::from_secs(60),
            write_timeout: Duration::from_secs(3),
            header_timeout: Duration::from_secs(10),
            body_timeout: Duration::from_secs(10),
            min_upload_rate: 8 << 10,
            max_upload_bytes_in_flight: 256 << 20,
            max_connections: 512,
            shutdown_grace: Duration::from_secs(1),
        }
    }
}

/// What every handler shares.
#[derive(Clone)]
pub(crate) struct AppState {
    pub limits: Limits,
    pub jobs: jobs::Jobs,
    pub stimuli: Arc<tokio::sync::OnceCell<Arc<api::Stimuli>>>,
}

/// The application: every route of the page and the API, served to
/// loopback names and IP literals ([`AllowedHosts::loopback`]).
pub fn router(limits: Limits) -> Router {
    router_with(limits, AllowedHosts::loopback())
}

/// [`router`] serving `hosts`.
pub fn router_with(limits: Limits, hosts: AllowedHosts) -> Router {
    let state = AppState {
        limits,
        jobs: jobs::Jobs::new(limits),
        stimuli: Arc::new(tokio::sync::OnceCell::new()),
    };
    Router::new()
        .route("/", get(assets::index))
        .route("/app.js", get(assets::script))
        .route("/app.css", get(assets::style))
        .route("/player.js", get(assets::player))
        .route("/api", get(assets::api_page))
        .route("/api/health", get(api::health))
        .route("/api/presets", get(api::presets))
        .route("/api/simulate", post(api::simulate))
        .route("/api/stroke", post(api::stroke))
        .route("/api/animate", post(api::animate))
        .route("/api/chart", post(api::chart))
        .route("/api/diagnose", post(api::diagnose))
        .route("/api/diagnose/report", post(api::diagnose_report))
        .route("/api/design-clapper", post(api::design_clapper))
        .route("/api/tower", post(api::tower))
        .route("/api/listening/sheet", get(api::listening_sheet))
        .route("/api/listening/stimulus/{name}", get(api::listening_stimulus))
        .route("/api/listening/parse", post(api::listening_parse))
        .route("/api/listening/analyse", post(api::listening_analyse))
        .route(
            "/api/strikes",
            post(api::strikes).layer(DefaultBodyLimit::max(limits.max_recording_bytes)),
        )
        .fallback(error::not_found)
        .method_not_allowed_fallback(error::method_not_allowed)
        .layer(DefaultBodyLimit::max(limits.max_body_bytes))
        .with_state(state)
        .layer(axum::middleware::from_fn_with_state(
            uploads::Uploads::new(limits),
            uploads::gate,
        ))
        .layer(axum::middleware::from_fn_with_state(hosts, hosts::check))
        .layer(tower_http::timeout::RequestBodyTimeoutLayer::new(limits.body_timeout))
}

/// Serve the application on `listener` to `hosts` until `shutdown`
/// completes: at most [`Limits::max_connections`] connections at once,
/// each closed if its headers take longer than [`Limits::header_timeout`]
/// or it stays idle that long; on shutdown, open connections get
/// [`Limits::shutdown_grace`] to finish and are then dropped.
pub async fn serve(
    listener: tokio::net::TcpListener,
    limits: Limits,
    hosts: AllowedHosts,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    use hyper_util::rt::{TokioIo, TokioTimer};
    let app = router_with(limits, hosts);
    let open = Arc::new(tokio::sync::Semaphore::new(limits.max_connections.max(1)));
    let graceful = hyper_util::server::graceful::GracefulShutdown::new();
    let mut http = hyper::server::conn::http1::Builder::new();
    http.timer(TokioTimer::new()).header_read_timeout(limits.header_timeout);
    tokio::pin!(shutdown);
    loop {
        let permit = tokio::select! {
            p = open.clone().acquire_owned() => p.expect("the semaphore is never closed"),
            _ = &mut shutdown => break,
        };
        let stream = tokio::select! {
            a = listener.accept() => match a {
                Ok((stream, _)) => stream,
                // Out of file descriptors and the like: wait, do not spin.
                Err(_) => {
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
            _ = &mut shutdown => break,
        };
        let service = hyper_util::service::TowerToHyperService::new(app.clone());
        let io = TokioIo::new(explain::Explained::new(stream));
        let conn = graceful.watch(http.serve_connection(io, service));
        tokio::spawn(async move {
            let _ = conn.await;
            drop(permit);
        });
    }
    drop(listener);
    let _ = tokio::time::timeout(limits.shutdown_grace, graceful.shutdown()).await;
    Ok(())
}
