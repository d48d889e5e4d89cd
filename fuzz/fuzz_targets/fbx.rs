//! Fuzzes the FBX rig reader (ufbx, then the glTF document it makes), the
//! recognition of its hands and their audit, with bends from its skin weights,
//! and the fix `--moves` lists, made in memory.
//! Seeded with the SteamVR gloves (fuzz/seed.sh copies them from ../shared).
#![no_main]

use libfuzzer_sys::fuzz_target;
use phalanx::analysis::{Settings, analyse};
use phalanx::dataset::Dataset;
use phalanx::rig::{AuditOptions, AuditedRig, Rig};
use std::sync::OnceLock;

const PAPER: &[u8] = include_bytes!("../../data/measurements.csv");

fuzz_target!(|data: &[u8]| {
    static ANALYSIS: OnceLock<phalanx::analysis::Analysis> = OnceLock::new();
    let a = ANALYSIS.get_or_init(|| {
        let d = Dataset::from_bytes("measurements.csv", PAPER).expect("the paper's data loads");
        analyse(&d, &Settings { resamples: 200, ..Settings::default() })
    });
    let Ok(file) = phalanx::rig::fbx::read("fuzz.fbx", data) else {
        return;
    };
    assert!(file.world.iter().all(|m| m.is_finite()));
    let Ok(rig) = Rig::from_file(file, None) else {
        return;
    };
    let audited = AuditedRig::with(
        "fuzz.fbx",
        &rig.chains,
        &rig.notes,
        a,
        &AuditOptions::default(),
        rig.weights.as_ref(),
    );
    for f in &audited.fingers {
        for j in &f.audit.joints {
            assert!(j.suggested.is_finite());
        }
    }
    // `--moves`: the fix made in memory on the glTF document read from the
    // FBX file, and its moves read back. Nothing is written to disk.
    if let Ok(fixed) = phalanx::rig::fix::fix_with(
        &rig.file,
        &audited.fingers,
        rig.weights.as_ref(),
        std::path::Path::new("/nonexistent-phalanx-fuzz"),
        true,
        &phalanx::rig::fix::FixOptions::default(),
    ) && let Ok(copy) = phalanx::rig::GltfFile::from_bytes("fixed.glb", &fixed.bytes)
    {
        let _ = phalanx::rig::fix::moves::moves(&rig.file, &copy);
    }
});
