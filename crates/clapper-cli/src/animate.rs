//! `clapper animate`: the bell and its clapper drawn to scale and
//! animated, as an SVG, a GIF, or an HTML page that plays the synthesised
//! sound in step; one bell, or a ring ringing rounds.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use clapper_app::animate::{animate, AnimateOptions, Animated, Arrangement};
use clapper_app::simulate::SimulateRequest;
use clapper_app::sound::Partials;
use clapper_core::prelude::Style;
use clapper_plot::animation::{animation_gif, animation_html, animation_svg, player_json};

use crate::simulate::SimulateArgs;

#[derive(Args, Debug)]
pub struct AnimateArgs {
    /// The bell and its ringing: every option of `clapper simulate` (its
    /// --trace and --plot aside).
    #[command(flatten)]
    pub sim: SimulateArgs,
    /// A ring file (as `diagnose` takes: TOML `[[bell]]` tables or CSV): its
    /// bells ring rounds together, each with the options above.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["preset", "bell", "chart_point"])]
    pub ring: Option<PathBuf>,
    /// A second copy of the bell beside the first, ringing this style (e.g.
    /// `--style right --beside wrong`), on one clock.
    #[arg(long, value_parser = crate::simulate::choice::<Style>(), conflicts_with = "ring")]
    pub beside: Option<Style>,
    /// Output: .svg (animated, no script), .gif, or .html (canvas, with
    /// the sound, slow motion and a time cursor).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Frames per second of animation time. Default: 25 for a GIF (its
    /// clock counts hundredths), 50 for an SVG, and for a page 600 for one
    /// or two bells, 300 for a ring (so that 1/10 slow motion still shows
    /// 60 or 30 frames a second).
    #[arg(long)]
    pub fps: Option<f64>,
    /// Picture size WxH (px). Default 520x560 for one bell, 880x500 for
    /// two; for a ring 200 x 230 px a bell, in one row up to four bells,
    /// else two.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// The handstroke gap (s): an extra pause before each handstroke after
    /// the first, as in `clapper synth`. Rounds set their own.
    #[arg(long, default_value_t = AnimateOptions::default().sound.gap)]
    pub gap: f64,
    /// Which partials ring. In rounds every bell sounds a typical bell at
    /// a nominal set by its mass.
    #[arg(long, value_enum, default_value = "lab")]
    pub partials: Partials,
    /// Sample rate of the page's sound (Hz).
    #[arg(long, default_value_t = AnimateOptions::default().sound.rate)]
    pub rate: f64,
    /// Time after the last stroke (s).
    #[arg(long, default_value_t = AnimateOptions::default().sound.tail)]
    pub tail: f64,
}

/// The output's kind, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Kind {
    Svg,
    Gif,
    Html,
}

fn kind_of(path: &Path) -> Result<Kind> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    Ok(match ext.as_deref() {
        Some("svg") => Kind::Svg,
        Some("gif") => Kind::Gif,
        Some("html" | "htm") => Kind::Html,
        _ => bail!("output {} must end in .svg, .gif or .html", path.display()),
    })
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size {s:?} must be WxH in px, e.g. 520x560"))?;
    let n = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (64..=4096).contains(n))
            .ok_or_else(|| format!("size {s:?}: each side must be a whole number of px, 64 to 4096"))
    };
    Ok((n(w)?, n(h)?))
}

pub fn run(args: AnimateArgs) -> Result<()> {
    if args.sim.trace.is_some() || args.sim.plot.is_some() {
        bail!("animate writes --out; --trace and --plot belong to `clapper simulate`");
    }
    if crate::files::is_stdout(&args.out) {
        bail!("an animation is written to a file: give --out a name ending in .svg, .gif or .html");
    }
    let kind = kind_of(&args.out)?;
    let req = args.sim.request();
    let (bells, arrangement) = match &args.ring {
        Some(path) => {
            let ring = clapper_io::load_bells(path)?;
            if ring.is_empty() {
                bail!("ring file {} holds no bells", path.display());
            }
            let bells = ring.into_iter().map(|b| (req.clone(), Some(b))).collect();
            (bells, Arrangement::Rounds)
        }
        None => {
            let mut bells = vec![(req.clone(), args.sim.bell_file()?)];
            if let Some(style) = args.beside {
                bells.push((SimulateRequest { style, ..req }, args.sim.bell_file()?));
            }
            (bells, Arrangement::SideBySide)
        }
    };
    let n = bells.len();
    let fps = args.fps.unwrap_or(match (kind, n) {
        (Kind::Gif, _) => 25.0,
        (Kind::Svg, _) => 50.0,
        (Kind::Html, 1 | 2) => 600.0,
        (Kind::Html, _) => 300.0,
    });
    let mut opts = AnimateOptions {
        fps,
        impact_frames: kind != Kind::Gif,
        ..AnimateOptions::default()
    };
    opts.sound.gap = args.gap;
    opts.sound.partials = args.partials;
    opts.sound.rate = args.rate;
    opts.sound.tail = args.tail;
    let (w, h) = args.size.unwrap_or(match n {
        1 => (520, 560),
        2 => (880, 500),
        _ => {
            let cols = clapper_plot::animation::columns(n) as u32;
            (
                (200 * cols).clamp(360, 4096),
                (230 * n.div_ceil(cols as usize) as u32 + 40).min(4096),
            )
        }
    });
    let animated = animate(bells, arrangement, &opts)?;
    let a = &animated.animation;
    let bytes = match kind {
        Kind::Svg => animation_svg(a, w, h)?.into_bytes(),
        Kind::Gif => animation_gif(a, w, h)?,
        Kind::Html => {
            let wav = clapper_io::signal_file::wav_bytes(&animated.sound, 0.9)
                .map_err(anyhow::Error::msg)
                .context("cannot encode the sound")?;
            animation_html(a, &wav)?.into_bytes()
        }
    };
    crate::files::write_bytes(&args.out, bytes)?;
    report(&animated, &args.out, args.sim.json)
}

fn report(animated: &Animated, out: &Path, json: bool) -> Result<()> {
    if json {
        // The player's data without its frames: what was drawn, and when.
        let mut v = player_json(&animated.animation);
        if let Some(bells) = v["bells"].as_array_mut() {
            for b in bells {
                let frames = b["t_s"].as_array().map_or(0, Vec::len);
                if let Some(o) = b.as_object_mut() {
                    for key in ["t_s", "t_sim_s", "theta_deg", "phi_deg", "figure"] {
                        o.remove(key);
                    }
                    o.insert("frames".into(), frames.into());
                }
            }
        }
        v["out"] = out.display().to_string().into();
        crate::say!("{}", serde_json::to_string(&v)?);
    } else {
        crate::say_text!("{}", animated.text(&out.display().to_string()));
    }
    Ok(())
}
