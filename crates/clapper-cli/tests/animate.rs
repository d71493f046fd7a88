//! `clapper animate` through the built binary: what is drawn is what was
//! simulated (angles from the files against `clapper simulate --trace`),
//! strikes flash in the GIF's picture of their impact, and the page's
//! sound has its strikes where the strikes are drawn (onsets measured from
//! the audio).

mod common;

use base64::Engine as _;
use common::{clapper, json};
use serde_json::Value;

fn animate(args: &[&str], out: &std::path::Path) -> Value {
    let mut all: Vec<&str> = vec!["animate"];
    all.extend_from_slice(args);
    let out_s = out.to_str().unwrap();
    all.extend_from_slice(&["--out", out_s]);
    json(&all)
}

/// The player's data in a page.
fn page_data(page: &str) -> Value {
    let start = page.find(r#"id="clapper-animation">"#).unwrap() + 23;
    let end = start + page[start..].find("</script>").unwrap();
    serde_json::from_str(&page[start..end]).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// `values` or `keyTimes` of the `n`th animateTransform of an SVG.
fn svg_list(svg: &str, n: usize, key: &str) -> Vec<f64> {
    let at = svg.match_indices("<animateTransform").nth(n).unwrap().0;
    let rest = &svg[at..];
    let start = rest.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
    let end = start + rest[start..].find('"').unwrap();
    rest[start..end].split(';').map(|v| v.parse().unwrap()).collect()
}

#[test]
fn the_drawn_angles_are_the_simulated_angles() {
    let dir = tempfile::tempdir().unwrap();
    // 400 frames a second: every frame's simulated time is on the trace's
    // 0.5 ms grid (the strokes are shifted by 0.2 s and 0.25 s).
    let html = dir.path().join("lab.html");
    animate(&["--preset", "lab", "--fps", "400"], &html);
    let trace = dir.path().join("trace.csv");
    clapper()
        .args(["simulate", "--preset", "lab", "--trace", trace.to_str().unwrap()])
        .assert()
        .success();
    let text = std::fs::read_to_string(&trace).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').take(3).map(|v| v.parse().unwrap()).collect())
        .collect();
    let data = page_data(&std::fs::read_to_string(&html).unwrap());
    let bell = &data["bells"][0];
    let (ts, theta, phi) = (
        floats(&bell["t_sim_s"]),
        floats(&bell["theta_deg"]),
        floats(&bell["phi_deg"]),
    );
    let mut matched = 0;
    for k in 0..ts.len() {
        // The trace writes 6 decimals; a frame matches the row of its time.
        let Some(row) = rows.iter().find(|r| (r[0] - ts[k]).abs() < 1e-9) else {
            continue;
        };
        assert!(
            (row[1] - theta[k]).abs() < 1.5e-6,
            "theta at {} s: {} drawn, {} simulated",
            ts[k],
            theta[k],
            row[1]
        );
        assert!(
            (row[2] - phi[k]).abs() < 1.5e-6,
            "phi at {} s: {} drawn, {} simulated",
            ts[k],
            phi[k],
            row[2]
        );
        matched += 1;
    }
    assert!(matched > 1000, "only {matched} frames matched a trace row");

    // The SVG's key frames are the page's frames, angle for angle.
    let svg_path = dir.path().join("lab.svg");
    animate(&["--preset", "lab", "--fps", "400"], &svg_path);
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let (svg_theta, svg_phi, key_times) = (
        svg_list(&svg, 0, "values"),
        svg_list(&svg, 1, "values"),
        svg_list(&svg, 1, "keyTimes"),
    );
    assert_eq!(svg_phi.len(), phi.len());
    let t_anim = floats(&bell["t_s"]);
    let dur = data["duration_s"].as_f64().unwrap();
    for k in 0..phi.len() {
        assert_eq!(svg_theta[k], theta[k]);
        assert_eq!(svg_phi[k], phi[k]);
        assert!((key_times[k] * dur - t_anim[k]).abs() < 1e-12);
    }
}

#[test]
fn strikes_flash_in_the_gif_within_one_frame_of_their_impact() {
    let dir = tempfile::tempdir().unwrap();
    let gif_path = dir.path().join("lab.gif");
    let report = animate(&["--preset", "lab", "--style", "wrong"], &gif_path);
    let strikes: Vec<f64> = report["bells"][0]["strikes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["t_s"].as_f64().unwrap())
        .collect();
    assert!(strikes.len() >= 2);
    let bytes = std::fs::read(&gif_path).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(&bytes[..]).unwrap();
    // Frame j (25 a second) shows time j/25 s; each frame after the first
    // is drawn over the one before, so keep the whole picture.
    let (w, h) = (usize::from(d.width()), usize::from(d.height()));
    let mut screen = vec![0u8; w * h * 4];
    let mut flashing = vec![];
    while let Some(f) = d.read_next_frame().unwrap() {
        for y in 0..usize::from(f.height) {
            for x in 0..usize::from(f.width) {
                let src = (y * usize::from(f.width) + x) * 4;
                let dst = ((y + usize::from(f.top)) * w + x + usize::from(f.left)) * 4;
                screen[dst..dst + 4].copy_from_slice(&f.buffer[src..src + 4]);
            }
        }
        flashing.push(screen.chunks_exact(4).any(|p| p[..3] == [0xff, 0xcc, 0x00]));
    }
    let fps = 25.0;
    for &t in &strikes {
        let j = (t * fps - 1e-9).ceil() as usize;
        assert!(j as f64 / fps - t < 1.0 / fps, "strike at {t} s");
        assert!(
            flashing[j],
            "no flash in frame {j} ({} s) for the strike at {t} s",
            j as f64 / fps
        );
    }
    for (j, &f) in flashing.iter().enumerate() {
        let tj = j as f64 / fps;
        let near = strikes.iter().any(|&t| (0.0..0.1 + 1e-9).contains(&(tj - t)));
        assert_eq!(
            f, near,
            "frame {j} ({tj} s): flash {f}, a strike within 0.1 s before {near}"
        );
    }
}

/// Onsets in `x` (rate `rate`): 0.5 ms blocks of the first difference's
/// energy that rise 6 times above the mean of the 10 ms before, and above
/// 1e-4 of the loudest block; a run of rising blocks is one onset.
fn onsets(x: &[f64], rate: f64) -> Vec<f64> {
    let block = (rate * 5e-4).round() as usize;
    let e: Vec<f64> = x
        .windows(2)
        .map(|w| (w[1] - w[0]).powi(2))
        .collect::<Vec<_>>()
        .chunks(block)
        .map(|c| c.iter().sum::<f64>())
        .collect();
    let peak = e.iter().cloned().fold(0.0, f64::max);
    let mut out = vec![];
    let mut last: Option<usize> = None;
    for b in 20..e.len() {
        let before = e[b - 20..b].iter().sum::<f64>() / 20.0;
        if e[b] > 6.0 * before && e[b] > 1e-4 * peak {
            if last.is_none_or(|l| b > l + 4) {
                out.push(b as f64 * block as f64 / rate);
            }
            last = Some(b);
        }
    }
    out
}

#[test]
fn the_pages_sound_strikes_where_the_strikes_are_drawn() {
    let dir = tempfile::tempdir().unwrap();
    for style in ["right", "wrong"] {
        let html = dir.path().join(format!("{style}.html"));
        animate(&["--preset", "lab", "--style", style, "--strokes", "4"], &html);
        let page = std::fs::read_to_string(&html).unwrap();
        let data = page_data(&page);
        let start = page.find("data:audio/wav;base64,").unwrap() + 22;
        let end = start + page[start..].find('<').unwrap();
        let wav = base64::engine::general_purpose::STANDARD
            .decode(page[start..end].trim())
            .unwrap();
        let mut r = hound::WavReader::new(std::io::Cursor::new(wav)).unwrap();
        let rate = f64::from(r.spec().sample_rate);
        let x: Vec<f64> = r.samples::<i16>().map(|s| f64::from(s.unwrap())).collect();
        let heard = onsets(&x, rate);
        let strikes = data["bells"][0]["strikes"].as_array().unwrap();
        let drawn: Vec<f64> = strikes.iter().map(|s| s["t_s"].as_f64().unwrap()).collect();
        let firsts: Vec<f64> = strikes
            .iter()
            .filter(|s| s["first"].as_bool().unwrap())
            .map(|s| s["t_s"].as_f64().unwrap())
            .collect();
        assert_eq!(firsts.len(), 4, "{style}: a blow a stroke");
        let nearest = |t: f64, set: &[f64]| set.iter().map(|u| (u - t).abs()).fold(f64::INFINITY, f64::min);
        // Every blow drawn is heard within 5 ms ...
        let worst = firsts.iter().map(|&t| nearest(t, &heard)).fold(0.0, f64::max);
        assert!(
            worst < 5e-3,
            "{style}: a blow heard {:.1} ms from where it is drawn; onsets {heard:?}",
            worst * 1e3
        );
        // ... and everything heard is a strike drawn.
        for &t in &heard {
            assert!(
                nearest(t, &drawn) < 5e-3,
                "{style}: an onset at {t} s with no strike drawn within 5 ms"
            );
        }
        eprintln!(
            "{style}: {} onsets heard, worst blow {:.2} ms from its flash",
            heard.len(),
            worst * 1e3
        );
    }
}

#[test]
fn a_ring_rings_rounds_in_one_page() {
    let dir = tempfile::tempdir().unwrap();
    let ring = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/ring-of-eight.csv");
    let html = dir.path().join("ring.html");
    let report = animate(&["--ring", ring], &html);
    let bells = report["bells"].as_array().unwrap();
    assert_eq!(bells.len(), 8);
    let interval = report["rounds_interval_s"].as_f64().unwrap();
    assert!((0.1..0.6).contains(&interval), "interval {interval} s");
    // The bells that keep ringing right land within half an interval of
    // their places; bell 6, which cannot ring right (`diagnose` says it
    // stands apart), goes over to wrong and is heard furthest out.
    let mut worst = (0.0f64, String::new());
    for b in bells {
        let sustained = !b["caption"].as_str().unwrap().contains("cannot keep it up");
        assert_eq!(sustained, b["name"] != "6", "{}", b["name"]);
        for s in b["strikes"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s["first"].as_bool().unwrap())
        {
            let (t, ideal) = (s["t_s"].as_f64().unwrap(), s["ideal_s"].as_f64().unwrap());
            if sustained {
                assert!((t - ideal).abs() < 0.5 * interval, "{}: {t} against {ideal}", b["name"]);
            }
            if (t - ideal).abs() > worst.0 {
                worst = ((t - ideal).abs(), b["name"].as_str().unwrap().to_string());
            }
        }
    }
    assert_eq!(worst.1, "6", "the furthest blow from its place: {worst:?}");
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page_data(&page)["bells"][7]["phi_deg"].as_array().unwrap().len() > 100);
}

#[test]
fn bad_requests_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let e = clapper()
        .args(["animate", "--preset", "lab", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!e.status.success());
    assert!(String::from_utf8_lossy(&e.stderr).contains("must end in .svg, .gif or .html"));
    let svg = dir.path().join("x.svg");
    for (args, says) in [
        (vec!["--fps", "0"], "--fps 0 is out of range"),
        (vec!["--size", "10x10"], "64 to 4096"),
        (vec!["--trace", "t.csv"], "--trace and --plot belong"),
        (vec!["--strokes", "500"], "too many to animate"),
    ] {
        let o = clapper()
            .args(["animate", "--preset", "lab", "--out", svg.to_str().unwrap()])
            .args(&args)
            .output()
            .unwrap();
        assert!(!o.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert!(!svg.exists(), "nothing written on an error");
}
