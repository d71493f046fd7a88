//! Chart time against grid size: cost should grow linearly with the number
//! of points. Run on one thread so the figure is per core.
use clapper_core::chart::{sweep, ChartSpec};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};

fn charts(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let mut g = c.benchmark_group("chart both styles, 1 thread");
    g.sample_size(10);
    for n in [10usize, 20, 40] {
        let spec = ChartSpec {
            nx: n,
            ny: n,
            ..ChartSpec::default()
        };
        g.throughput(Throughput::Elements((2 * n * n) as u64));
        g.bench_with_input(BenchmarkId::from_parameter(format!("{n}x{n}")), &spec, |b, spec| {
            b.iter(|| pool.install(|| sweep(spec, &|_| {}).unwrap()))
        });
    }
    g.finish();
}

criterion_group!(benches, charts);
criterion_main!(benches);
