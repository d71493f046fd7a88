//! One stroke of the lab bell, both contact models, both styles, with each
//! integrator (Taylor, the default, and Dormand–Prince).
use clapper_core::prelude::*;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn strokes(c: &mut Criterion) {
    let bell = Bell::lab();
    let mut g = c.benchmark_group("lab bell stroke");
    for (name, contact) in [
        ("impact", ContactModel::Impact),
        ("penalty k=1e6", ContactModel::Penalty),
    ] {
        for (iname, integrator) in [("taylor", Integrator::default()), ("dopri5", Integrator::Dopri5)] {
            let cfg = SimConfig {
                contact,
                integrator,
                ..SimConfig::default()
            };
            for style in [Style::Right, Style::Wrong] {
                g.bench_function(format!("{name} {iname} {style:?}"), |b| {
                    b.iter(|| first_stroke(black_box(&bell), black_box(&cfg), style).unwrap())
                });
            }
        }
    }
    g.finish();
}

criterion_group!(benches, strokes);
criterion_main!(benches);
