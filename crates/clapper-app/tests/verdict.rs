//! One verdict for a real bell (issue 45): `simulate` and the chart judge a
//! style from steady ringing (handstroke and backstroke), so they agree at
//! every point, and a bell and its mirror image get mirrored answers.

use clapper_app::chart::ChartRequest;
use clapper_app::simulate::{simulate, SimulateRequest};
use clapper_core::chart::{sweep, Chart};
use clapper_core::Choice;
use serde_json::json;

fn chart(offset_m: f64) -> Chart {
    let req: ChartRequest = serde_json::from_value(json!({"grid": [20, 20], "pivot_offset": offset_m})).unwrap();
    sweep(&req.spec().unwrap(), &|_| {}).unwrap()
}

/// Every point and style of the paper's 20 x 20 chart with the clapper
/// pivot 5 mm off: `simulate` at the point (through its request, as the
/// command line, web and Python ask it) gives the chart's verdict and
/// odd-struckness, bit for bit; the chart 5 mm the other way is its mirror.
#[test]
fn simulate_and_the_chart_agree_at_every_point_of_an_offset_chart() {
    let d = 0.005;
    let (plus, minus) = (chart(d), chart(-d));
    let mut sustained = 0;
    let mut hand_only = 0;
    for (c, m) in plus.cells.iter().zip(&minus.cells) {
        let req: SimulateRequest = serde_json::from_value(json!({
            "chart_point": [c.x, c.y],
            "pivot_offset": d,
            "style": c.style.name(),
            "strokes": 2,
        }))
        .unwrap();
        let sim = simulate(&req, None, None).unwrap().report;
        let s = c.result.as_ref().unwrap();
        let at = format!("({}, {}) {}", c.x, c.y, c.style.name());
        assert_eq!(sim.sustained, s.sustained, "verdict at {at}");
        assert_eq!(
            sim.verdict,
            if s.sustained { c.style.name() } else { "neither" },
            "{at}"
        );
        assert_eq!(sim.odd_struck_ms, s.odd_struck.map(|t| t * 1e3), "odd-struck at {at}");
        assert_eq!(
            sim.odd_struck_ms.is_some(),
            s.sustained,
            "odd-struck only where sustained, {at}"
        );
        assert_eq!(sim.odd_struck_ms.is_none(), sim.odd_struck_undefined.is_some(), "{at}");
        // The mirror image: the same verdict, the odd-struckness negated.
        let m = m.result.as_ref().unwrap();
        assert_eq!(m.sustained, s.sustained, "mirror verdict at {at}");
        assert_eq!(m.odd_struck.map(|t| -t), s.odd_struck, "mirror odd-struck at {at}");
        sustained += usize::from(s.sustained);
        // Where the handstroke alone would have judged otherwise.
        hand_only += usize::from(sim.strokes[0].sustained != s.sustained);
    }
    assert_eq!(plus.cells.len(), 800);
    assert!(sustained > 200, "{sustained} of 800 sustained");
    // The points a handstroke alone misjudges exist: the test tells the
    // two verdicts apart.
    assert!(hand_only > 0, "no point where the handstroke alone misjudges");
    eprintln!("{sustained} of 800 sustained; the handstroke alone misjudges {hand_only}");
}
