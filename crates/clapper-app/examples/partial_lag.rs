//! Diagnostic (voice-1, docs/strikes.md "Which partials each recorded bell
//! is given"): how late the band finder hears one recorded bell through
//! each single partial, the recording struck eight times 2 s apart over
//! faint noise (median lateness in ms, strikes heard within 300 ms).
//!
//!     cargo run --release -p clapper-app --example partial_lag -- FILE F1,F2,..
use clapper_signal::sampled_ring::sample_onset;
use clapper_signal::strikes::{find_strikes, BellVoice, StrikeOptions, VoicePartial};
use clapper_signal::Signal;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let v: Vec<String> = std::env::args().skip(1).collect();
    let [file, list] = v.as_slice() else {
        return Err("usage: partial_lag FILE F1,F2,.. (a recording of one bell struck alone; partials in Hz)".into());
    };
    let s = clapper_io::signal_file::read_recording(std::path::Path::new(file))?;
    let fs: Vec<f64> = list.split(',').map(|x| x.trim().parse()).collect::<Result<_, _>>()?;
    let on = sample_onset(&s)?;
    let gap = (2.0 * s.rate) as usize;
    let mut out = vec![0.0; gap * 9];
    let mut truth = vec![];
    for k in 0..8 {
        let at = gap / 2 + k * gap;
        truth.push(at as f64 / s.rate + on);
        for (i, x) in s.samples.iter().enumerate() {
            if at + i < out.len() {
                out[at + i] += x;
            }
        }
    }
    // Faint noise, so that no band is exactly silent between strikes.
    let mut rng = Pcg64::seed_from_u64(1);
    for x in out.iter_mut() {
        *x += 1e-4 * (rng.random::<f64>() - 0.5);
    }
    let sig = Signal {
        samples: out,
        ..s.clone()
    };
    let one = |ps: Vec<f64>| {
        let voice = BellVoice {
            partials: ps
                .iter()
                .map(|&f| VoicePartial {
                    freq_hz: f,
                    strength: 1.0,
                    uncertainty: 0.005,
                })
                .collect(),
        };
        let Ok(h) = find_strikes(&sig, &[voice], &StrikeOptions::default()) else {
            return "not heard".to_string();
        };
        let mut e: Vec<f64> = truth
            .iter()
            .filter_map(|t| {
                h.strikes
                    .iter()
                    .map(|x| (x.t - t) * 1e3)
                    .filter(|d| d.abs() < 300.0)
                    .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            })
            .collect();
        e.sort_by(f64::total_cmp);
        format!(
            "{:?} heard {}",
            e.get(e.len() / 2).map(|x| (x * 10.0).round() / 10.0),
            e.len()
        )
    };
    for &f in &fs {
        println!("{f:.1}: {}", one(vec![f]));
    }
    println!("all: {}", one(fs.clone()));
    Ok(())
}
