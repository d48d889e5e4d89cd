//! Synthetic measurement data for benchmarks and tests (never mixed into real data).
//!
//! The model, per X-ray (one hand):
//! - a hand scale s = exp(0.08 z), so hands differ in size by about 8%
//!   (and, with metadata, male hands are 8% larger on average);
//! - per finger, a total length J = T_f * s * exp(0.03 z_f), with T_f the mean
//!   total of that finger in the paper's Table 1 (thumb 520, index 757, middle
//!   865, ring 838, little 654 image units);
//! - per finger, relative values around the paper's means with the paper's
//!   spread: J~1 = m1 + sd1 z1 and J~2 = m2 + sd2 (rho z1 + sqrt(1 - rho^2) z2)
//!   with rho = -0.4 (a long proximal segment goes with a shorter middle one),
//!   J~3 = 1 - J~1 - J~2; for the thumb J~2 = 1 - J~1; every J~k kept >= 0.05;
//! - lengths Jk = J~k * J, rounded to 2 decimals as in Table 1.
//!
//! With metadata: sex female or male (even odds), age uniform in 18..80 years,
//! side right (90%) or left. All draws come from one ChaCha8 stream of the seed,
//! so a seed always gives the same file.

use crate::dataset::Finger;
use crate::format;
use crate::stats::rng;
use std::fmt::Write as _;

/// Random-stream key of the generator (separate from the bootstrap's).
const SYNTH_KEY: u64 = 0x5E_17_4E;

/// Paper-based parameters of one finger: mean total, mean J~1, J~2, and their SDs.
struct FingerModel {
    finger: Finger,
    total: f64,
    mean: [f64; 2],
    sd: [f64; 2],
}

/// Means and SDs of Table 1 (see `phalanx stats` on data/measurements.csv).
const MODELS: [FingerModel; 5] = [
    FingerModel {
        finger: Finger::Index,
        total: 757.0,
        mean: [0.4846, 0.2726],
        sd: [0.0131, 0.0039],
    },
    FingerModel {
        finger: Finger::Middle,
        total: 865.0,
        mean: [0.4681, 0.2984],
        sd: [0.0114, 0.0118],
    },
    FingerModel {
        finger: Finger::Ring,
        total: 838.0,
        mean: [0.4587, 0.2904],
        sd: [0.0092, 0.0089],
    },
    FingerModel {
        finger: Finger::Little,
        total: 654.0,
        mean: [0.4570, 0.2644],
        sd: [0.0096, 0.0098],
    },
    FingerModel {
        finger: Finger::Thumb,
        total: 520.0,
        mean: [0.5314, 0.4686],
        sd: [0.0139, 0.0139],
    },
];

/// Correlation of J~1 and J~2 within a finger.
const RHO: f64 = -0.4;
/// Smallest relative value generated.
const MIN_REL: f64 = 0.05;

/// Options of the generator.
#[derive(Debug, Clone, Copy)]
pub struct SynthOptions {
    pub xrays: usize,
    pub seed: u64,
    /// Fill sex, age and side.
    pub metadata: bool,
}

/// A synthetic dataset as CSV bytes in the measurement format. O(xrays).
pub fn generate(o: &SynthOptions) -> Vec<u8> {
    let mut r = rng::stream(o.seed, SYNTH_KEY, 0);
    let mut out = String::with_capacity(o.xrays * 5 * 64 + 64);
    out.push_str("xray,finger,j1,j2,j3,sex,age,side,source,unit\n");
    let width = o.xrays.max(1).to_string().len().max(6);
    for i in 0..o.xrays {
        let id = format!("syn-{:0width$}", i + 1);
        let male = rng::unit_open(&mut r) < 0.5;
        let age = 18.0 + 62.0 * rng::unit_open(&mut r);
        let right = rng::unit_open(&mut r) < 0.9;
        let sex_scale = if o.metadata && male { 1.08 } else { 1.0 };
        let scale = sex_scale * (0.08 * rng::standard_normal(&mut r)).exp();
        let (sex, age, side) = if o.metadata {
            (
                if male { "male" } else { "female" },
                format::num(age, 0),
                if right { "right" } else { "left" },
            )
        } else {
            ("", String::new(), "")
        };
        for m in &MODELS {
            let total = m.total * scale * (0.03 * rng::standard_normal(&mut r)).exp();
            let (z1, z2) = (rng::standard_normal(&mut r), rng::standard_normal(&mut r));
            let r1 = (m.mean[0] + m.sd[0] * z1).max(MIN_REL);
            let lengths: Vec<f64> = if m.finger == Finger::Thumb {
                let r1 = r1.min(1.0 - MIN_REL);
                vec![r1 * total, (1.0 - r1) * total]
            } else {
                let r2 = (m.mean[1] + m.sd[1] * (RHO * z1 + (1.0 - RHO * RHO).sqrt() * z2))
                    .max(MIN_REL)
                    .min(1.0 - r1 - MIN_REL);
                vec![r1 * total, r2 * total, (1.0 - r1 - r2) * total]
            };
            let _ = write!(out, "{id},{}", m.finger.name());
            for k in 0..3 {
                match lengths.get(k) {
                    Some(l) => {
                        let _ = write!(out, ",{}", format::num(l.max(0.01), 2));
                    }
                    None => out.push(','),
                }
            }
            let _ = writeln!(
                out,
                ",{sex},{age},{side},synthetic (phalanx synth --seed {}),image units",
                o.seed
            );
        }
    }
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Quantity, Settings, analyse};
    use crate::dataset::Dataset;

    #[test]
    fn synthetic_data_loads_and_follows_the_model() {
        let o = SynthOptions {
            xrays: 400,
            seed: 7,
            metadata: true,
        };
        let bytes = generate(&o);
        assert_eq!(bytes, generate(&o), "same seed, same file");
        assert_ne!(bytes, generate(&SynthOptions { seed: 8, ..o }));
        let d = Dataset::from_bytes("syn.csv", &bytes).unwrap();
        assert_eq!(d.rows.len(), 2000);
        assert_eq!(d.xray_count(), 400);
        let a = analyse(
            &d,
            &Settings {
                resamples: 200,
                ..Settings::default()
            },
        );
        let idx = a.finger(Finger::Index).unwrap();
        let rel1 = idx.quantity(Quantity::RelJ1).unwrap();
        // The model's mean 0.4846 and SD 0.0131: with n = 400, the mean is within 4 SE (0.0026).
        assert!((rel1.mean - 0.4846).abs() < 0.0026, "{}", rel1.mean);
        assert!((rel1.sd.unwrap() - 0.0131).abs() < 0.002, "{:?}", rel1.sd);
        // Hands of one X-ray share the scale: totals of index and middle correlate.
        let mid = a.finger(Finger::Middle).unwrap();
        let (x, y): (Vec<f64>, Vec<f64>) = idx
            .xrays
            .iter()
            .zip(&mid.xrays)
            .map(|(a, b)| (a.total, b.total))
            .unzip();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let (mx, my) = (mean(&x), mean(&y));
        let cov: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
        let vx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
        let vy: f64 = y.iter().map(|b| (b - my).powi(2)).sum();
        assert!(
            cov / (vx * vy).sqrt() > 0.5,
            "hand scale shared across fingers"
        );
        let sexes: Vec<&str> = d
            .rows
            .iter()
            .filter_map(|r| r.meta.sex.as_deref())
            .collect();
        assert!(sexes.contains(&"female") && sexes.contains(&"male"));
    }

    #[test]
    fn without_metadata_the_columns_are_empty() {
        let bytes = generate(&SynthOptions {
            xrays: 3,
            seed: 1,
            metadata: false,
        });
        let d = Dataset::from_bytes("syn.csv", &bytes).unwrap();
        assert!(
            d.rows
                .iter()
                .all(|r| r.meta.sex.is_none() && r.meta.age.is_none())
        );
    }
}
