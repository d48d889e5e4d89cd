//! Fuzzes the glTF rig reader, the audit of whatever it accepts (bends from
//! its skin weights included; each MCP judged from its CMC or the wrist against
//! the atlas in data/atlas, read at start-up), and `--fix` in memory (weights
//! and keys moved; also with each MCP placed from its ray's base), the moves
//! read back and the fixed copy audited again. Nothing is written to disk.
#![no_main]

use libfuzzer_sys::fuzz_target;
use phalanx::analysis::{Settings, analyse};
use phalanx::dataset::Dataset;
use phalanx::rig::judge::WristRatios;
use phalanx::rig::{AuditOptions, AuditedRig, GltfFile, Rig, session};
use std::path::Path;
use std::sync::OnceLock;

const PAPER: &[u8] = include_bytes!("../../data/measurements.csv");

fuzz_target!(|data: &[u8]| {
    static ANALYSIS: OnceLock<phalanx::analysis::Analysis> = OnceLock::new();
    let a = ANALYSIS.get_or_init(|| {
        let d = Dataset::from_bytes("measurements.csv", PAPER).expect("the paper's data loads");
        analyse(&d, &Settings { resamples: 200, ..Settings::default() })
    });
    static ATLAS: OnceLock<Option<(phalanx::analysis::Analysis, Option<WristRatios>)>> =
        OnceLock::new();
    let atlas = ATLAS.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/atlas/measurements.csv");
        let d = Dataset::load(&path).ok()?;
        let a = analyse(&d, &Settings { resamples: 200, ..Settings::default() });
        Some((a, session::wrist_ratios_beside(&path).ok().flatten()))
    });
    let Ok(file) = GltfFile::from_bytes("fuzz.glb", data) else {
        return;
    };
    let Ok(rig) = Rig::from_file(file, None) else {
        return;
    };
    let mut audited = AuditedRig::with(
        "fuzz.glb",
        &rig.chains,
        &rig.notes,
        a,
        &AuditOptions::default(),
        rig.weights.as_ref(),
    );
    if let Some((atlas, wrist)) = atlas {
        audited.judge_rays(
            atlas,
            wrist.as_ref(),
            a,
            &AuditOptions::default(),
            rig.weights.as_ref(),
        );
    }
    for f in &audited.fingers {
        for j in &f.audit.joints {
            assert!(j.suggested.is_finite());
        }
        if let Some(m) = &f.metacarpal_check {
            assert!(m.suggested.is_finite() && m.expected.is_finite());
        }
    }
    // External buffers resolve in a folder that does not exist: never read.
    // The fix is made in memory (no file is written), with the finger's
    // explanation and with each MCP placed from its ray's base
    // (`--fix-mcp atlas`); its moves are read back and the fixed copy is
    // audited again, as `audit --fix` and `--moves` do.
    let placed = atlas
        .as_ref()
        .map(|_| phalanx::rig::judge::ray::mcp_from_base(&audited, a, &audited.tips, &[]));
    for fingers in std::iter::once(&audited.fingers).chain(placed.as_ref()) {
        let Ok(fixed) = phalanx::rig::fix::fix_with(
            &rig.file,
            fingers,
            rig.weights.as_ref(),
            Path::new("/nonexistent-phalanx-fuzz"),
            true,
            &phalanx::rig::fix::FixOptions::default(),
        ) else {
            continue;
        };
        let Ok(copy) = GltfFile::from_bytes("fixed.glb", &fixed.bytes) else {
            continue;
        };
        let _ = phalanx::rig::fix::moves::moves(&rig.file, &copy);
        if let Ok(again) = Rig::from_file(copy, None) {
            let _ = AuditedRig::with(
                "fixed.glb",
                &again.chains,
                &again.notes,
                a,
                &AuditOptions::default(),
                again.weights.as_ref(),
            );
        }
    }
});
