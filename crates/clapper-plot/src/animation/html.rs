//! The animation as one HTML page: the frames as JSON, the sound as an
//! embedded WAV, and the canvas player (`player.js`), which the web app
//! serves too.

use base64::Engine as _;
use serde_json::{json, Value};

use super::layout::esc;
use super::model::Animation;
use crate::PlotError;

/// The canvas player: `ClapperPlayer.mount(element, data, audioUrl)`,
/// `data` as [`player_json`] writes it.
pub const PLAYER_JS: &str = include_str!("player.js");

/// The animation as the player reads it: degrees and seconds at this edge
/// (keys name their units), the figure in metres. Each bell's `t_s`,
/// `t_sim_s`, `theta_deg` and `phi_deg` are its frames; `strikes` its
/// impacts (`side` "hand" or "back").
pub fn player_json(anim: &Animation) -> Value {
    let bells: Vec<Value> = anim
        .bells
        .iter()
        .map(|b| {
            json!({
                "name": b.name,
                "caption": b.caption,
                "figure": b.figure,
                "t_s": b.frames.iter().map(|f| f.t).collect::<Vec<_>>(),
                "t_sim_s": b.frames.iter().map(|f| f.t_sim).collect::<Vec<_>>(),
                "theta_deg": b.frames.iter().map(|f| f.theta.to_degrees()).collect::<Vec<_>>(),
                "phi_deg": b.frames.iter().map(|f| f.phi.to_degrees()).collect::<Vec<_>>(),
                "strikes": b.strikes.iter().map(|s| json!({
                    "t_s": s.t,
                    "t_sim_s": s.t_sim,
                    "side": if s.side > 0 { "back" } else { "hand" },
                    "stroke": s.stroke,
                    "first": s.first,
                    "ideal_s": s.ideal,
                    "speed_rad_s": s.speed,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "title": anim.title,
        "duration_s": anim.duration,
        "rounds_interval_s": anim.rounds_interval,
        "bells": bells,
    })
}

/// A page that plays the animation with its sound (`wav`: a WAV file's
/// bytes, embedded as a data URL; empty for none). Everything is inside
/// the file: it opens from a disk with no server and no network.
pub fn animation_html(anim: &Animation, wav: &[u8]) -> Result<String, PlotError> {
    anim.check()?;
    // JSON inside <script> must not close it: "</" is written "<\/".
    let data = player_json(anim).to_string().replace("</", "<\\/");
    let audio = if wav.is_empty() {
        String::new()
    } else {
        format!(
            "data:audio/wav;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(wav)
        )
    };
    Ok(format!(
        r#"<!doctype html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<style>
body {{ font-family: system-ui, sans-serif; margin: 1rem auto; max-width: 980px; color: #222; }}
h1 {{ font-size: 1.1rem; font-weight: 600; }}
.cp-controls {{ display: flex; gap: 0.8rem; align-items: center; margin: 0.4rem 0; flex-wrap: wrap; }}
.cp-time {{ flex: 1; min-width: 160px; }}
canvas {{ display: block; }}
p.note {{ color: #555; font-size: 0.85rem; }}
</style></head>
<body>
<h1>{title}</h1>
<div id="player"></div>
<p class="note">Drawn from clapper's simulation: each moment shows the simulated state at that time, and the sound is synthesised from the same strikes. A strike flashes where the ball meets the bell. Made by <code>clapper animate</code>.</p>
<script type="application/json" id="clapper-animation">{data}</script>
<script id="clapper-audio" type="text/plain">{audio}</script>
<script>
{player}
</script>
<script>
const clapperData = JSON.parse(document.getElementById("clapper-animation").textContent);
const clapperAudio = document.getElementById("clapper-audio").textContent.trim();
window.player = ClapperPlayer.mount(document.getElementById("player"), clapperData, clapperAudio || null);
</script>
</body></html>
"#,
        title = esc(&anim.title),
        player = PLAYER_JS,
    ))
}

#[cfg(test)]
mod tests {
    use super::super::model::tests::swinging;
    use super::*;

    #[test]
    fn the_page_carries_the_frames_and_the_sound() {
        let a = swinging(20, 25.0);
        let page = animation_html(&a, b"RIFFxxxxWAVE").expect("page");
        let start = page.find(r#"id="clapper-animation">"#).expect("data") + 23;
        let end = start + page[start..].find("</script>").expect("closed");
        let v: Value = serde_json::from_str(&page[start..end]).expect("JSON");
        assert_eq!(
            v["bells"][0]["phi_deg"][7],
            json!(a.bells[0].frames[7].phi.to_degrees())
        );
        assert_eq!(v["title"], json!("test <bell> & co"));
        assert!(page.contains("data:audio/wav;base64,UklGRnh4eHhXQVZF"));
        assert!(page.contains("ClapperPlayer"));
    }

    #[test]
    fn a_name_cannot_close_the_script() {
        let mut a = swinging(5, 25.0);
        a.bells[0].name = "</script><b>".into();
        let page = animation_html(&a, &[]).expect("page");
        assert_eq!(page.matches("</script>").count(), 4);
    }
}
