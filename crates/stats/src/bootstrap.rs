//! Bootstrap of means: exact enumeration for small samples, seeded resampling otherwise.
//!
//! The unit resampled is the X-ray: one resample is a vector of counts
//! `c_1..c_n` (how often each X-ray is drawn, summing to n), and every quantity
//! observed on those X-rays gets the resampled mean `sum_i c_i x_i / n` from the
//! same counts. With n X-rays there are only C(2n-1, n) distinct count vectors
//! (126 for n = 5), each with multinomial probability `n! / prod(c_i!) / n^n`;
//! when that number is no larger than the resamples asked for, all of them are
//! enumerated with their weights (exact and deterministic) instead of drawn.

use super::Interval;
use super::describe::{normal_cdf, normal_quantile};
use super::rng;
use rayon::prelude::*;
use schemars::JsonSchema;
use serde::Serialize;

/// Resamples per random stream. Chunk `k` always holds resamples
/// `64k .. 64k+63` and draws from stream `k`, whatever the thread count.
pub const CHUNK: usize = 64;

/// How the bootstrap distribution was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(tag = "method", rename_all = "lowercase")]
pub enum Plan {
    /// Every distinct resample enumerated with its multinomial weight.
    Exact { distinct: usize },
    /// `resamples` resamples drawn at random.
    Random { resamples: usize },
}

impl Plan {
    /// Exact enumeration when C(2n-1, n) <= `requested`, random draws otherwise.
    pub fn choose(n: usize, requested: usize) -> Plan {
        match distinct_resamples(n, requested) {
            Some(distinct) => Plan::Exact { distinct },
            None => Plan::Random {
                resamples: requested,
            },
        }
    }

    /// Number of points in the bootstrap distribution.
    pub fn len(self) -> usize {
        match self {
            Plan::Exact { distinct } => distinct,
            Plan::Random { resamples } => resamples,
        }
    }

    /// True when the plan has no resamples.
    pub fn is_empty(self) -> bool {
        self.len() == 0
    }
}

/// C(2n-1, n), the number of distinct resamples of n units, when it is at most `limit`.
pub fn distinct_resamples(n: usize, limit: usize) -> Option<usize> {
    if n == 0 {
        return None;
    }
    // C(2n-1, n) = prod_{i=1..n} (n-1+i)/i, exact at every step.
    let mut c: u128 = 1;
    for i in 1..=n as u128 {
        c = c * (n as u128 - 1 + i) / i;
        if c > limit as u128 {
            return None;
        }
    }
    Some(c as usize)
}

/// The bootstrap distribution of the means of several quantities measured on the same units.
#[derive(Debug, Clone)]
pub struct Distribution {
    pub plan: Plan,
    /// Probability of each point (sums to 1).
    pub weights: Vec<f64>,
    /// `means[q][j]`: the mean of quantity `q` in resample `j`.
    pub means: Vec<Vec<f64>>,
}

/// Bootstraps the means of `columns` (each of the same length n >= 1).
///
/// `key` separates independent groups under one seed. Cost: O(m n q) for m
/// resamples and q quantities; memory O(m q).
pub fn resample_means(columns: &[&[f64]], requested: usize, seed: u64, key: u64) -> Distribution {
    resample_means_with(columns, requested, seed, key, &NoProgress)
}

/// The means of `columns` (each of the same length n >= 1) over `resamples` random
/// resamples, even where [`resample_means`] would enumerate them exactly: for a
/// statistic that combines independent resamples of several samples (e.g. a difference of
/// two cohorts' means), which an exact enumeration of each would not pair. The draws
/// depend on (n, `seed`, `key`) only, not on the columns. Cost: O(resamples n q).
pub fn resample_means_random(
    columns: &[&[f64]],
    resamples: usize,
    seed: u64,
    key: u64,
) -> Distribution {
    let n = columns.first().map_or(0, |c| c.len());
    random(columns, n, resamples.max(1), seed, key, &NoProgress)
}

/// Receives progress of long computations: `advance(k)` after k more units of
/// work (resamples), from any thread. Keeps the statistics free of any display code.
pub trait Progress: Sync {
    /// Called once with the total before any work is done.
    fn start(&self, _total: u64) {}
    fn advance(&self, _done: u64) {}
}

/// Progress that goes nowhere.
pub struct NoProgress;

impl Progress for NoProgress {}

/// [`resample_means`] reporting resamples done to `progress`.
pub fn resample_means_with(
    columns: &[&[f64]],
    requested: usize,
    seed: u64,
    key: u64,
    progress: &dyn Progress,
) -> Distribution {
    let n = columns.first().map_or(0, |c| c.len());
    let plan = Plan::choose(n, requested.max(1));
    match plan {
        Plan::Exact { distinct } => exact(columns, n, distinct),
        Plan::Random { resamples } => random(columns, n, resamples, seed, key, progress),
    }
}

/// Mean of each column under counts `c` (summing to n).
#[inline]
fn weighted_means(columns: &[&[f64]], counts: &[u32], n: usize, out: &mut [f64]) {
    for (o, col) in out.iter_mut().zip(columns) {
        let s: f64 = counts
            .iter()
            .zip(col.iter())
            .map(|(&c, &x)| f64::from(c) * x)
            .sum();
        *o = s / n as f64;
    }
}

/// Every distinct resample of n units with its multinomial probability:
/// depends on n only, so it is built once and reused (e.g. by the coverage
/// simulation, which bootstraps thousands of samples of the same size).
#[derive(Debug, Clone)]
pub struct Enumeration {
    n: usize,
    /// The count vectors, one after another (`distinct * n` counts).
    counts: Vec<u32>,
    /// Probability of each count vector (sums to 1).
    pub weights: Vec<f64>,
}

impl Enumeration {
    /// Enumerates the C(2n-1, n) resamples of n units (`distinct` of them).
    pub fn new(n: usize, distinct: usize) -> Enumeration {
        let ln_fact: Vec<f64> = (0..=n)
            .scan(0.0f64, |acc, k| {
                if k > 0 {
                    *acc += (k as f64).ln();
                }
                Some(*acc)
            })
            .collect();
        let ln_norm = ln_fact[n] - n as f64 * (n as f64).ln();
        let mut weights = Vec::with_capacity(distinct);
        let mut counts = Vec::with_capacity(distinct * n);
        let mut c = vec![0u32; n];
        compositions(n, &mut c, |c| {
            let ln_w = ln_norm - c.iter().map(|&k| ln_fact[k as usize]).sum::<f64>();
            weights.push(ln_w.exp());
            counts.extend_from_slice(c);
        });
        // Normalise away rounding so the weights sum to 1.
        let total: f64 = weights.iter().sum();
        weights.iter_mut().for_each(|w| *w /= total);
        Enumeration { n, counts, weights }
    }

    /// The bootstrap distribution of the means of `columns` (each of length n).
    pub fn distribution(&self, columns: &[&[f64]]) -> Distribution {
        let distinct = self.weights.len();
        let mut means = vec![Vec::with_capacity(distinct); columns.len()];
        let mut row = vec![0.0; columns.len()];
        for c in self.counts.chunks_exact(self.n.max(1)) {
            weighted_means(columns, c, self.n, &mut row);
            for (m, v) in means.iter_mut().zip(&row) {
                m.push(*v);
            }
        }
        Distribution {
            plan: Plan::Exact { distinct },
            weights: self.weights.clone(),
            means,
        }
    }
}

fn exact(columns: &[&[f64]], n: usize, distinct: usize) -> Distribution {
    Enumeration::new(n, distinct).distribution(columns)
}

/// Calls `visit` with every vector of n non-negative counts summing to n
/// (Nijenhuis and Wilf's NEXCOM), in a fixed order. O(1) amortised per vector.
fn compositions(n: usize, r: &mut [u32], mut visit: impl FnMut(&[u32])) {
    let k = r.len();
    let n32 = n as u32;
    r.iter_mut().for_each(|c| *c = 0);
    r[0] = n32;
    let (mut t, mut h) = (n32, 0usize);
    visit(r);
    while r[k - 1] != n32 {
        if t > 1 {
            h = 0;
        }
        h += 1;
        t = r[h - 1];
        r[h - 1] = 0;
        r[0] = t - 1;
        r[h] += 1;
        visit(r);
    }
}

/// Most chunks drawn by one task before one matrix product sums them all: the product
/// reads (packs) the value matrix once per task, so the more resamples per product, the
/// less that costs (a quarter of the time at 64). Fewer where a task's counts would pass
/// [`TASK_BYTES`]. The tasks are fixed by n and the chunk numbers, not by the threads, and
/// each resample's sum does not depend on how many rows the product has, so the result is
/// the same at any thread count and task size.
const CHUNKS_PER_TASK: usize = 4;

/// Most bytes of counts one task holds (one per X-ray per resample): at 100,000 X-rays a
/// task is one chunk (6.4 MB), so the workers' counts stay small beside the data.
const TASK_BYTES: usize = 8 << 20;

/// X-rays per block of the product: a task's counts are turned into floating point
/// resamples-per-task x `XRAYS` at a time (at most 1 MB), so the kernel needs O(resamples
/// per task x n) bytes of counts and this block, whatever n. A multiple of matrixmultiply's
/// depth panel (256 X-rays).
const XRAYS: usize = 512;

/// Draws the resamples of one task's chunks, each chunk from its own stream of `streams`
/// (chunk k holds resamples 64k .. 64k+63 and draws from stream k), and writes their
/// means, resample by resample, to `out` (`len * q` values for `len` resamples in all).
///
/// The draws: resample j draws n X-ray indices one after another (the crate's unbiased
/// index draw), counted in a byte per X-ray; a count past 255 spills into `overflow`, so
/// the counts stay exact. The sums: every quantity of every resample at once, as the
/// matrix product S = C V of the counts C (`len` x n) and the row-major values V (n x q),
/// by matrixmultiply's blocked `dgemm` (X-rays in blocks of [`XRAYS`], each block adding
/// into S); each spilled draw then adds its row once more, and S / n are the means.
///
/// Summation order: `dgemm` sums each resample's products over X-rays in panels of 256, in
/// index order from zero within a panel, then adds the panel to the running sum, with a
/// fused multiply-add where the processor has one (x86-64 with AVX2 and FMA, AVX-512,
/// AArch64). A mean can therefore differ in its last bits from a plain left-to-right
/// `sum_i c_i x_i / n`, and on a processor without FMA from one with it; the resamples
/// (the counts) are the same everywhere. Cost: n `len` draws and n `len` q multiply-adds,
/// O(`len` n) bytes.
fn random_task(
    rows: &[f64],
    q: usize,
    n: usize,
    streams: &mut [(rand_chacha::ChaCha8Rng, usize)],
    work: &mut TaskWork,
    out: &mut [f64],
) {
    if n == 0 || q == 0 {
        // No X-rays: no draws, and the means are 0 / 0.
        out.iter_mut().for_each(|s| *s = f64::NAN);
        return;
    }
    let len: usize = streams.iter().map(|s| s.1).sum();
    let n32 = u32::try_from(n).unwrap_or(u32::MAX);
    let counts = &mut work.counts[..len * n];
    counts.iter_mut().for_each(|c| *c = 0);
    work.overflow.iter_mut().for_each(Vec::clear);
    let mut rows_of_counts = counts.chunks_exact_mut(n).enumerate();
    for (rng, chunk_len) in streams.iter_mut() {
        for (r, counts) in rows_of_counts.by_ref().take(*chunk_len) {
            for _ in 0..n {
                let i = rng::index(rng, n32) as usize;
                match counts[i].checked_add(1) {
                    Some(c) => counts[i] = c,
                    None => work.overflow[r].push(i),
                }
            }
        }
    }
    let sums = out;
    let mut i0 = 0;
    while i0 < n {
        let i1 = (i0 + XRAYS).min(n);
        let k = i1 - i0;
        let block = &mut work.block[..len * k];
        to_float(counts, n, i0, i1, block);
        let values = &rows[i0 * q..i1 * q];
        let beta = if i0 == 0 { 0.0 } else { 1.0 };
        // SAFETY: `block` is `len` x k row-major (row stride k), `values` k x q row-major
        // (row stride q) and `sums` `len` x q row-major (row stride q), all within their
        // slices; `sums` is borrowed mutably, so it aliases neither input.
        unsafe {
            matrixmultiply::dgemm(
                len,
                k,
                q,
                1.0,
                block.as_ptr(),
                k as isize,
                1,
                values.as_ptr(),
                q as isize,
                1,
                beta,
                sums.as_mut_ptr(),
                q as isize,
                1,
            );
        }
        i0 = i1;
    }
    for (r, sums) in sums.chunks_exact_mut(q).enumerate() {
        // Counts past 255: each spilled draw adds its row once more.
        for &i in &work.overflow[r] {
            for (acc, x) in sums.iter_mut().zip(&rows[i * q..(i + 1) * q]) {
                *acc += x;
            }
        }
        sums.iter_mut().for_each(|s| *s /= n as f64);
    }
}

/// Copies X-rays `i0..i1` of every row of `counts` (rows of n) into `block` as floating
/// point, the left factor of the product. AVX2 where the processor has it (detected at run
/// time): the same values either way, a quarter of the instructions.
fn to_float(counts: &[u8], n: usize, i0: usize, i1: usize, block: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor supports AVX2, checked just above.
            unsafe { to_float_avx2(counts, n, i0, i1, block) };
            return;
        }
    }
    to_float_body(counts, n, i0, i1, block);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn to_float_avx2(counts: &[u8], n: usize, i0: usize, i1: usize, block: &mut [f64]) {
    to_float_body(counts, n, i0, i1, block);
}

#[inline(always)]
fn to_float_body(counts: &[u8], n: usize, i0: usize, i1: usize, block: &mut [f64]) {
    for (b, c) in block.chunks_exact_mut(i1 - i0).zip(counts.chunks_exact(n)) {
        for (x, &c) in b.iter_mut().zip(&c[i0..i1]) {
            *x = f64::from(c);
        }
    }
}

/// Per-worker buffers of [`random_task`], reused across tasks.
struct TaskWork {
    /// Resamples per task x n counts, one byte each.
    counts: Vec<u8>,
    overflow: Vec<Vec<usize>>,
    /// Resamples per task x [`XRAYS`] counts as floating point, the left factor.
    block: Vec<f64>,
}

fn random(
    columns: &[&[f64]],
    n: usize,
    resamples: usize,
    seed: u64,
    key: u64,
    progress: &dyn Progress,
) -> Distribution {
    let q = columns.len();
    let chunks = resamples.div_ceil(CHUNK);
    let chunks_per_task = (TASK_BYTES / (CHUNK * n.max(1))).clamp(1, CHUNKS_PER_TASK);
    let tasks = chunks.div_ceil(chunks_per_task);
    let per_task = chunks_per_task * CHUNK;
    // Row-major copy, the right factor of the product: one X-ray's quantities side by side.
    let mut rows = vec![0.0f64; n * q];
    for (k, col) in columns.iter().enumerate() {
        for (i, &x) in col.iter().enumerate() {
            rows[i * q + k] = x;
        }
    }
    let per_task_means: Vec<Vec<f64>> = (0..tasks)
        .into_par_iter()
        .map_init(
            || {
                let most = per_task.min(resamples);
                TaskWork {
                    counts: vec![0u8; most * n],
                    overflow: vec![Vec::new(); most],
                    block: vec![0.0; most * XRAYS.min(n)],
                }
            },
            |work, t| {
                let first = t * chunks_per_task;
                let mut streams: Vec<(rand_chacha::ChaCha8Rng, usize)> = (first
                    ..(first + chunks_per_task).min(chunks))
                    .map(|k| {
                        let len = CHUNK.min(resamples - k * CHUNK);
                        (rng::stream(seed, key, k as u64), len)
                    })
                    .collect();
                let len: usize = streams.iter().map(|s| s.1).sum();
                let mut out = vec![0.0; len * q];
                random_task(&rows, q, n, &mut streams, work, &mut out);
                progress.advance(len as u64);
                out
            },
        )
        .collect();
    let mut means = vec![Vec::with_capacity(resamples); q];
    for task in &per_task_means {
        for row in task.chunks_exact(q.max(1)) {
            for (m, v) in means.iter_mut().zip(row) {
                m.push(*v);
            }
        }
    }
    Distribution {
        plan: Plan::Random { resamples },
        weights: vec![1.0 / resamples as f64; resamples],
        means,
    }
}

/// A weighted bootstrap distribution of one statistic, sorted for quantiles.
pub struct Sorted {
    values: Vec<f64>,
    cumulative: Vec<f64>,
}

impl Sorted {
    /// Sorts `values` (with `weights`) ascending; equal values keep their order, so the
    /// cumulative weights are summed in one fixed order. O(m log m); the pairs are sorted
    /// in place (a stable sort of contiguous pairs, not of indices into the values).
    pub fn new(values: &[f64], weights: &[f64]) -> Sorted {
        // Equal weights (every random bootstrap): which of equal values comes first cannot
        // change the result (values equal under total_cmp are the same bits, and the
        // cumulative sums add the same weight each step), so the values alone are sorted,
        // unstably: the same bits as the stable sort of pairs below, in about half the time.
        if let Some(&w) = weights.first()
            && weights.len() == values.len()
            && weights.iter().all(|x| x.to_bits() == w.to_bits())
        {
            let mut sorted = values.to_vec();
            sorted.sort_unstable_by(f64::total_cmp);
            let mut acc = 0.0;
            let cumulative = sorted
                .iter()
                .map(|_| {
                    acc += w;
                    acc
                })
                .collect();
            return Sorted {
                values: sorted,
                cumulative,
            };
        }
        let mut pairs: Vec<(f64, f64)> = values
            .iter()
            .copied()
            .zip(weights.iter().copied())
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut acc = 0.0;
        let mut cumulative = Vec::with_capacity(pairs.len());
        let mut sorted = Vec::with_capacity(pairs.len());
        for (v, w) in pairs {
            acc += w;
            cumulative.push(acc);
            sorted.push(v);
        }
        Sorted {
            values: sorted,
            cumulative,
        }
    }

    /// The weighted quantile: the smallest value whose cumulative weight reaches `p`
    /// (the inverse of the weighted empirical distribution function).
    pub fn quantile(&self, p: f64) -> f64 {
        let p = p.clamp(0.0, 1.0);
        let i = self.cumulative.partition_point(|&c| c < p - 1e-12);
        self.values[i.min(self.values.len() - 1)]
    }

    /// P*(value < x) + P*(value = x) / 2, ties within a relative 1e-12.
    pub fn mid_rank(&self, x: f64) -> f64 {
        let tol = 1e-12 * x.abs().max(1e-300);
        let below = self.values.partition_point(|&v| v < x - tol);
        let upto = self.values.partition_point(|&v| v <= x + tol);
        let at = |i: usize| if i == 0 { 0.0 } else { self.cumulative[i - 1] };
        at(below) + (at(upto) - at(below)) / 2.0
    }
}

/// Percentile interval: the (1-c)/2 and (1+c)/2 weighted quantiles.
pub fn percentile_interval(dist: &Sorted, confidence: f64) -> Interval {
    let alpha = 1.0 - confidence;
    Interval::new(dist.quantile(alpha / 2.0), dist.quantile(1.0 - alpha / 2.0))
}

/// Bias-corrected and accelerated (BCa) interval of a mean (Efron 1987).
///
/// Bias correction z0 = Phi^-1(P*(theta* < theta) + P*(theta* = theta)/2);
/// acceleration a = sum d^3 / (6 (sum d^2)^(3/2)) from the jackknife, where for
/// a mean the leave-one-out estimates are (S - x_i)/(n-1), so d_i is
/// proportional to x_i - mean: O(n), no refits. The interval is the weighted
/// quantiles at Phi(z0 + (z0 + z)/(1 - a (z0 + z))) for z = -/+ z_{(1+c)/2}.
/// Errs with a reason when the correction is undefined.
pub fn bca_interval(
    dist: &Sorted,
    sample: &[f64],
    estimate: f64,
    confidence: f64,
) -> Result<Interval, &'static str> {
    let n = sample.len();
    if n < 2 {
        return Err("BCa needs at least 2 X-rays for the jackknife");
    }
    let p0 = dist.mid_rank(estimate);
    if p0 <= 0.0 || p0 >= 1.0 {
        return Err("BCa undefined: every resample falls on one side of the estimate");
    }
    let z0 = normal_quantile(p0);
    let (mut s2, mut s3) = (0.0, 0.0);
    for &x in sample {
        let d = (x - estimate) / (n - 1) as f64;
        s2 += d * d;
        s3 += d * d * d;
    }
    if s2 == 0.0 {
        return Err("BCa undefined: every X-ray gives the same value");
    }
    let a = s3 / (6.0 * s2.powf(1.5));
    let z = normal_quantile(1.0 - (1.0 - confidence) / 2.0);
    let adjust = |zq: f64| -> Option<f64> {
        let num = z0 + zq;
        let den = 1.0 - a * num;
        (den > 0.0).then(|| normal_cdf(z0 + num / den))
    };
    match (adjust(-z), adjust(z)) {
        (Some(lo), Some(hi)) if lo.is_finite() && hi.is_finite() => {
            Ok(Interval::new(dist.quantile(lo), dist.quantile(hi)))
        }
        _ => Err("BCa undefined: acceleration too large for this confidence level"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_distinct_resamples() {
        // C(2n-1, n): 1, 3, 10, 35, 126, 462, 1716, 6435, 24310 (OEIS A001700).
        let expect = [1, 3, 10, 35, 126, 462, 1716, 6435, 24310];
        for (n, &e) in (1..=9).zip(&expect) {
            assert_eq!(distinct_resamples(n, usize::MAX), Some(e));
        }
        assert_eq!(distinct_resamples(9, 10_000), None);
        assert_eq!(Plan::choose(5, 10_000), Plan::Exact { distinct: 126 });
        assert_eq!(Plan::choose(5, 125), Plan::Random { resamples: 125 });
        assert_eq!(Plan::choose(40, 10_000), Plan::Random { resamples: 10_000 });
    }

    #[test]
    fn enumeration_visits_every_composition_once_with_weights_summing_to_one() {
        for n in 1..=7 {
            let xs: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let d = resample_means(&[&xs], usize::MAX, 0, 0);
            assert_eq!(d.weights.len(), distinct_resamples(n, usize::MAX).unwrap());
            let total: f64 = d.weights.iter().sum();
            assert!((total - 1.0).abs() < 1e-12);
            // The exact bootstrap mean of the mean is the sample mean, and its variance
            // is (1/n) * population variance / ... : E*[mean*] = mean, Var* = s_pop^2 / n.
            let m: f64 = d.weights.iter().zip(&d.means[0]).map(|(w, v)| w * v).sum();
            let sample_mean = xs.iter().sum::<f64>() / n as f64;
            assert!((m - sample_mean).abs() < 1e-12);
            let var: f64 = d
                .weights
                .iter()
                .zip(&d.means[0])
                .map(|(w, v)| w * (v - m).powi(2))
                .sum();
            let pop_var = xs.iter().map(|x| (x - sample_mean).powi(2)).sum::<f64>() / n as f64;
            assert!((var - pop_var / n as f64).abs() < 1e-12, "n={n}");
        }
    }

    #[test]
    fn n_equals_two_by_hand() {
        // x = (1, 3): resamples (2,0) -> 1 w 1/4, (1,1) -> 2 w 1/2, (0,2) -> 3 w 1/4.
        let d = resample_means(&[&[1.0, 3.0]], 100, 0, 0);
        let mut pairs: Vec<(f64, f64)> = d.means[0]
            .iter()
            .copied()
            .zip(d.weights.iter().copied())
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(pairs, vec![(1.0, 0.25), (2.0, 0.5), (3.0, 0.25)]);
        let s = Sorted::new(&d.means[0], &d.weights);
        assert_eq!(s.quantile(0.25), 1.0);
        assert_eq!(s.quantile(0.2501), 2.0);
        assert_eq!(s.quantile(0.75), 2.0);
        assert_eq!(s.quantile(0.76), 3.0);
        assert!((s.mid_rank(2.0) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn random_plan_is_thread_count_independent_and_seeded() {
        let xs: Vec<f64> = (0..50).map(|i| (i as f64).sqrt()).collect();
        let run = |threads: usize, seed: u64| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| resample_means(&[&xs], 1000, seed, 3).means)
        };
        let one = run(1, 9);
        assert_eq!(one, run(2, 9));
        assert_eq!(one, run(3, 9));
        assert_ne!(one, run(1, 10));
        assert_eq!(one[0].len(), 1000);
    }

    /// The plain definition: resample j of chunk k draws n indices from stream k in order,
    /// and its mean is sum_i c_i x_i / n summed in index order.
    fn plain_means(cols: &[Vec<f64>], resamples: usize, seed: u64, key: u64) -> Vec<Vec<f64>> {
        let n = cols[0].len();
        let mut means = vec![Vec::new(); cols.len()];
        for j in 0..resamples {
            let (k, within) = (j / CHUNK, j % CHUNK);
            let mut r = rng::stream(seed, key, k as u64);
            let mut counts = vec![0u32; n];
            for _ in 0..=within {
                counts.iter_mut().for_each(|c| *c = 0);
                for _ in 0..n {
                    counts[rng::index(&mut r, n as u32) as usize] += 1;
                }
            }
            for (m, col) in means.iter_mut().zip(cols) {
                let mut sum = 0.0;
                for (c, x) in counts.iter().zip(col) {
                    sum += f64::from(*c) * x;
                }
                m.push(sum / n as f64);
            }
        }
        means
    }

    #[test]
    fn the_matrix_product_kernel_draws_the_plain_definitions_resamples() {
        // Integer values: every product and partial sum is exact whatever the order, so the
        // kernel (matrix product in panels, FMA or not) must equal the plain definition bit
        // for bit: the same draws from the same streams give the same resamples. n = 2100
        // spans five blocks of X-rays (the last partial); 300 resamples are 5 chunks, in a
        // task of 4 chunks and one of 1.
        let n = 2100;
        let cols: Vec<Vec<f64>> = (0..5)
            .map(|q| (0..n).map(|i| ((i * 37 + q * 11) % 97) as f64).collect())
            .collect();
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let d = resample_means(&refs, 300, 42, 9);
        assert_eq!(d.means, plain_means(&cols, 300, 42, 9));
    }

    #[test]
    fn the_matrix_product_kernel_equals_the_plain_sums_to_rounding() {
        // Real values: the product sums in another order (panels of 256 X-rays, FMA where
        // the processor has it), so a mean may differ in its last bits: here by at most a
        // few units in the last place (relative 1e-15 x log2 n is the worst case).
        let n = 300;
        let cols: Vec<Vec<f64>> = (0..7)
            .map(|q| {
                (0..n)
                    .map(|i| 1.0 + ((i * 37 + q * 11) % 97) as f64 / 7.0)
                    .collect()
            })
            .collect();
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let d = resample_means(&refs, 150, 42, 9);
        let plain = plain_means(&cols, 150, 42, 9);
        for (q, (a, b)) in d.means.iter().zip(&plain).enumerate() {
            for (j, (x, y)) in a.iter().zip(b).enumerate() {
                assert!(
                    (x - y).abs() <= 8.0 * f64::EPSILON * y.abs(),
                    "resample {j}, quantity {q}: {x} vs {y}"
                );
            }
        }
    }

    #[test]
    fn random_bootstrap_se_matches_theory() {
        // Var*(mean*) = s_pop^2 / n exactly; 4000 resamples estimate it within ~5%.
        let xs: Vec<f64> = (0..30).map(|i| ((i * 7) % 11) as f64).collect();
        let d = resample_means(&[&xs], 4000, 1, 0);
        let n = xs.len() as f64;
        let m = xs.iter().sum::<f64>() / n;
        let pop_var = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n;
        let bm = d.means[0].iter().sum::<f64>() / 4000.0;
        let bv = d.means[0].iter().map(|v| (v - bm).powi(2)).sum::<f64>() / 3999.0;
        assert!(
            (bv / (pop_var / n) - 1.0).abs() < 0.1,
            "{bv} vs {}",
            pop_var / n
        );
    }

    #[test]
    fn bca_equals_percentile_for_symmetric_sample() {
        // Symmetric sample: a = 0 and, for the exact distribution, z0 = 0,
        // so BCa reduces to the percentile interval.
        let xs = [1.0, 2.0, 3.0, 4.0, 5.0];
        let d = resample_means(&[&xs], 10_000, 0, 0);
        let s = Sorted::new(&d.means[0], &d.weights);
        let p = percentile_interval(&s, 0.95);
        let b = bca_interval(&s, &xs, 3.0, 0.95).unwrap();
        assert_eq!(p, b);
        assert!(p.low < 3.0 && p.high > 3.0);
    }

    #[test]
    fn bca_refuses_degenerate_input() {
        let xs = [2.0, 2.0, 2.0];
        let d = resample_means(&[&xs], 10_000, 0, 0);
        let s = Sorted::new(&d.means[0], &d.weights);
        assert!(bca_interval(&s, &xs, 2.0, 0.95).is_err());
        assert!(bca_interval(&s, &[2.0], 2.0, 0.95).is_err());
    }
}
