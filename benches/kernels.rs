//! Criterion benchmarks of the hot paths: the bootstrap kernel, the loader, and the
//! fingers found on a hand's skin.
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

/// The floor of the random bootstrap, its two halves alone at 10,000 X-rays: the index
/// draws (ChaCha8 and Lemire's draw, as `phalanx::stats::rng` writes them, counted in a byte
/// per X-ray) and the matrix product of 64 resamples' counts with 28 quantities
/// (matrixmultiply's dgemm). One thread each; `bench/run.sh` prints the floor they imply.
fn floor(c: &mut Criterion) {
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};
    let n = 10_000usize;
    let mut g = c.benchmark_group("floor");
    g.sample_size(10);
    g.throughput(Throughput::Elements((64 * n) as u64));
    g.bench_function("draws_64x10000", |b| {
        let mut counts = vec![0u8; 64 * n];
        b.iter(|| {
            let mut rng = ChaCha8Rng::from_seed([7; 32]);
            counts.iter_mut().for_each(|c| *c = 0);
            for row in counts.chunks_exact_mut(n) {
                for _ in 0..n {
                    // Lemire's multiply-shift (the rejection step is taken about n / 2^32 of the time).
                    let i = ((u64::from(rng.next_u32()) * n as u64) >> 32) as usize;
                    row[i] = row[i].wrapping_add(1);
                }
            }
            black_box(&counts);
        })
    });
    let a: Vec<f64> = (0..64 * n).map(|i| (i % 3) as f64).collect();
    let cols = columns(n);
    let v: Vec<f64> = (0..n)
        .flat_map(|i| cols.iter().map(move |c| c[i]))
        .collect();
    let mut out = vec![0.0; 64 * 28];
    // Elements: multiply-adds.
    g.throughput(Throughput::Elements((64 * n * 28) as u64));
    g.bench_function("gemm_64x10000x28", |b| {
        b.iter(|| {
            // SAFETY: a is 64 x n, v is n x 28 (one X-ray's quantities side by side, as the
            // kernel lays them out) and out is 64 x 28, all row-major within their vectors.
            unsafe {
                matrixmultiply::dgemm(
                    64,
                    n,
                    28,
                    1.0,
                    a.as_ptr(),
                    n as isize,
                    1,
                    v.as_ptr(),
                    28,
                    1,
                    0.0,
                    out.as_mut_ptr(),
                    28,
                    1,
                );
            }
            black_box(&out);
        })
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

/// The fingers found on the skin of a synthetic right hand of about 50,000 triangles
/// (`tube_hand right 32 0.865 0`, the hand of `bench/run.sh`'s rig rows): the search
/// alone, its mesh read once. Budget: under a second in the debug build (the shared
/// rigs took 2-5 ms each in release).
fn find_fingers(c: &mut Criterion) {
    use phalanx::dataset::Finger;
    use phalanx::rig::deform::synthetic::{HandSpec, tube_hand};
    use phalanx::rig::find::{FindOptions, MeshSelect, find_hand, hand_mesh};
    use phalanx::rig::naming::Side;
    let spec = HandSpec {
        side: Side::Right,
        fingers: Finger::ALL.to_vec(),
        around: 32,
        ring_spacing: 0.000_865,
        weight_shift: 0.0,
        ..HandSpec::default()
    };
    let bytes = tube_hand(&spec).to_glb().expect("a GLB");
    let file = phalanx::rig::GltfFile::from_bytes("hand.glb", &bytes).expect("the GLB reads");
    let mesh = hand_mesh(&file, &MeshSelect::Whole).expect("a hand mesh");
    let opts = FindOptions {
        fingers: 5,
        wrist: None,
        side: None,
        ..FindOptions::default()
    };
    let mut g = c.benchmark_group("find_hand");
    g.sample_size(10);
    g.bench_function("tube_hand_50k_triangles", |b| {
        b.iter(|| black_box(find_hand(&mesh, &opts)))
    });
    g.finish();
}

criterion_group!(
    benches,
    bootstrap_kernel,
    floor,
    loader,
    analysis_paper,
    find_fingers
);
criterion_main!(benches);
