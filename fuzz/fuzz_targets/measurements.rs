//! Fuzzes the measurement loader, and the analysis of whatever it accepts.
#![no_main]

use libfuzzer_sys::fuzz_target;
use phalanx::analysis::{Settings, analyse};
use phalanx::dataset::Dataset;

fuzz_target!(|data: &[u8]| {
    match Dataset::from_bytes("fuzz.csv", data) {
        Ok(d) => {
            let a = analyse(
                &d,
                &Settings {
                    resamples: 50,
                    ..Settings::default()
                },
            );
            for f in &a.fingers {
                for q in &f.quantities {
                    assert!(q.mean.is_finite(), "non-finite mean from accepted data");
                    for i in q.intervals.all().into_iter().flatten() {
                        assert!(i.low <= i.high, "reversed interval");
                    }
                }
            }
        }
        Err(e) => assert!(!e.problems.is_empty(), "an error without a problem"),
    }
});
