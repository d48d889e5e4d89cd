//! Fuzzes the claims parser, and the check of whatever it accepts against the paper's data.
#![no_main]

use libfuzzer_sys::fuzz_target;
use phalanx::analysis::claims::check;
use phalanx::dataset::Dataset;
use phalanx::dataset::claims::Claims;

const PAPER: &[u8] = include_bytes!("../../data/measurements.csv");

fuzz_target!(|data: &[u8]| {
    let Ok(claims) = Claims::from_bytes("fuzz.csv", data) else {
        return;
    };
    let Ok(paper) = Dataset::from_bytes("measurements.csv", PAPER) else {
        return;
    };
    if claims.check_against(&paper).is_ok() {
        let results = check(&claims, &paper);
        assert_eq!(results.len(), claims.claims.len());
    }
});
