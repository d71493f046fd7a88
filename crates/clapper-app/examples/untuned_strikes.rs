//! Eight (or N) synthetic strikes of untuned bells, one WAV file each
//! (`OUT/1.wav` treble first ..), for `ring_files` to build a ring from
//! where no recordings may be committed: the strike the tests of the
//! untuned-bell paths use (`clapper_signal::sampled_ring::UntunedStrike`,
//! a recorded tower bell's partial ratios, a blow, partials building up
//! over 30 ms), nominals a major scale down from 1000 Hz. Used by
//! `bench/strikes-speed`.
//!
//! cargo run --release -p clapper-app --example untuned_strikes -- OUT [--bells N] [--rate HZ]

use std::path::PathBuf;

use clapper_signal::sampled_ring::{Blow, UntunedStrike};
use clapper_signal::tower::major_scale;

fn main() {
    let v: Vec<String> = std::env::args().skip(1).collect();
    let get = |k: &str| v.iter().position(|a| a == k).and_then(|i| v.get(i + 1)).cloned();
    let out = PathBuf::from(v.first().expect("OUT: the folder to write the strikes to"));
    let n: usize = get("--bells").map_or(8, |s| s.parse().expect("a number of bells"));
    let rate: f64 = get("--rate").map_or(44_100.0, |s| s.parse().expect("a sample rate"));
    std::fs::create_dir_all(&out).expect("a folder to write to");
    for (i, b) in major_scale(n, 1000.0).expect("3 to 16 bells").iter().enumerate() {
        let strike = UntunedStrike {
            nominal_hz: b.nominal_hz,
            rise_s: 0.03,
            decay_s: 0.8,
            length_s: 2.0,
            blow: Some(Blow {
                amplitude: 0.6,
                decay_s: 0.002,
                seed: 2 * i as u64 + 1,
            }),
        };
        clapper_io::signal_file::write_wav(&out.join(format!("{}.wav", i + 1)), &strike.signal(rate), 0.9)
            .expect("a strike written");
    }
    println!("wrote {n} strikes to {}", out.display());
}
