//! Criterion benchmarks of the hot paths: the bootstrap kernel and the loader.
//!
//! `cargo bench` runs them. Whole-command wall time and peak memory are measured
//! by `bench/run.sh` instead (see BENCHMARKS.md).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use phalanx::analysis::{Settings, analyse};
use phalanx::dataset::Dataset;
use phalanx::stats::bootstrap::resample_means;
use phalanx::synth::{SynthOptions, generate};
use std::hint::black_box;

/// Columns like one group of the analysis: 28 quantities of n X-rays.
fn columns(n: usize) -> Vec<Vec<f64>> {
    (0..28)
        .map(|q| {
            (0..n)
                .map(|i| 0.3 + ((i * 7919 + q * 104_729) % 1000) as f64 * 1e-4)
                .collect()
        })
        .collect()
}

fn bootstrap_kernel(c: &mut Criterion) {
    let mut g = c.benchmark_group("bootstrap_kernel");
    g.sample_size(10);
    for &n in &[1_000usize, 10_000] {
        let cols = columns(n);
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let resamples = 1_000;
        // Elements: resample x X-ray pairs (each touching 28 quantities).
        g.throughput(Throughput::Elements((n * resamples) as u64));
        g.bench_with_input(BenchmarkId::new("random_28q_1000res", n), &n, |b, _| {
            b.iter(|| black_box(resample_means(&refs, resamples, 1, 0)))
        });
    }
    let paper: Vec<f64> = vec![0.4867, 0.4728, 0.4862, 0.5047, 0.4728];
    // Elements: the 126 distinct resamples of 5 X-rays.
    g.throughput(Throughput::Elements(126));
    g.bench_function("exact_n5", |b| {
        b.iter(|| black_box(resample_means(&[&paper], 10_000, 1, 0)))
    });
    g.finish();
}

fn loader(c: &mut Criterion) {
    let mut g = c.benchmark_group("loader");
    g.sample_size(10);
    for &n in &[1_000usize, 10_000] {
        let bytes = generate(&SynthOptions {
            xrays: n,
            seed: 1,
            metadata: true,
        });
        g.throughput(Throughput::Bytes(bytes.len() as u64));
        g.bench_with_input(BenchmarkId::new("parse_validate", n), &bytes, |b, bytes| {
            b.iter(|| black_box(Dataset::from_bytes("bench.csv", bytes)))
        });
    }
    g.finish();
}

fn analysis_paper(c: &mut Criterion) {
    let d = Dataset::load(std::path::Path::new("data/measurements.csv")).expect("paper data");
    c.bench_function("analyse_paper_data", |b| {
        b.iter(|| black_box(analyse(&d, &Settings::default())))
    });
}

criterion_group!(benches, bootstrap_kernel, loader, analysis_paper);
criterion_main!(benches);
