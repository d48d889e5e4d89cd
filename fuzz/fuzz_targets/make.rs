//! Fuzzes `phalanx rig` in memory: the rig reader (glTF, GLB or FBX, told
//! apart by the header as `read::open` does), `make::make` (the hand found
//! on its skin, its joints placed from the paper's data and the atlas, the
//! skin weighted, the copy written) and, as `session::rig` does before it
//! writes, the copy read back and audited. Nothing is written to disk.
//!
//! The input's last byte (left in the file: a GLB's padding or a glTF's
//! trailing whitespace) chooses the side, the finger count, the names and
//! whether a wrist is given; each input is made both without and with
//! `--replace-fingers` (a rigged hand is refused at once without it).
#![no_main]

use libfuzzer_sys::fuzz_target;
use phalanx::analysis::{Analysis, Settings, analyse_without_bootstrap};
use phalanx::dataset::{Dataset, SummaryTable};
use phalanx::rig::judge::{SoftTissue, WristRatios};
use phalanx::rig::make::names::Names;
use phalanx::rig::make::place::Proportions;
use phalanx::rig::make::write::WriteOptions;
use phalanx::rig::make::{MakeOptions, make};
use phalanx::rig::naming::Side;
use phalanx::rig::{AuditOptions, AuditedRig, GltfFile, Rig, session};
use std::path::Path;
use std::sync::OnceLock;

const PAPER: &[u8] = include_bytes!("../../data/measurements.csv");
const SOFT_TISSUE: &[u8] = include_bytes!("../../data/literature/buryanov-kotiuk-2010.csv");

/// The paper's analysis and the proportions `rig` places joints from (the
/// atlas's, read at start-up from data/atlas, when it is there).
fn proportions() -> &'static (Analysis, Proportions) {
    static P: OnceLock<(Analysis, Proportions)> = OnceLock::new();
    P.get_or_init(|| {
        let settings = Settings::default();
        let d = Dataset::from_bytes("measurements.csv", PAPER).expect("the paper's data loads");
        let a = analyse_without_bootstrap(&d, &settings);
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/atlas/measurements.csv");
        let atlas = Dataset::load(&path)
            .ok()
            .map(|d| analyse_without_bootstrap(&d, &settings));
        let wrist: Option<WristRatios> = session::wrist_ratios_beside(&path).ok().flatten();
        let soft = SummaryTable::from_bytes("soft-tissue.csv", SOFT_TISSUE)
            .map(|t| SoftTissue::from_table(&t, None))
            .unwrap_or(SoftTissue::Unknown);
        let p = Proportions::new(&a, atlas.as_ref(), wrist.as_ref(), soft);
        (a, p)
    })
}

fuzz_target!(|data: &[u8]| {
    let (a, proportions) = proportions();
    let file = if phalanx::rig::fbx::is_fbx(Path::new("fuzz.glb"), data) {
        phalanx::rig::fbx::read("fuzz.fbx", data)
    } else {
        GltfFile::from_bytes("fuzz.glb", data)
    };
    let Ok(file) = file else {
        return;
    };
    let Ok(rig) = Rig::from_file(file, None) else {
        return;
    };
    let knob = data.last().copied().unwrap_or(0);
    let side = match knob % 3 {
        0 => None,
        1 => Some(Side::Left),
        _ => Some(Side::Right),
    };
    let fingers = match (knob / 3) % 4 {
        0 => None,
        k => Some(k as usize + 2),
    };
    let names = [
        Names::Openxr,
        Names::Vrm,
        Names::Mixamo,
        Names::Unreal,
        Names::Rigify,
    ][usize::from(knob / 12) % 5];
    // A wrist given (`--wrist`): the first node's world origin, as a point
    // of the file's own scale.
    let wrist = (knob >= 128)
        .then(|| rig.file.world.first().map(|m| m.w_axis.truncate()))
        .flatten();
    for replace_fingers in [false, true] {
        let opts = MakeOptions {
            side,
            wrist,
            fingers,
            write: WriteOptions {
                names,
                replace_fingers,
                glb: knob & 1 == 0,
            },
        };
        // External buffers resolve in a folder that does not exist: never read.
        let Ok(made) = make(
            &rig,
            proportions,
            &opts,
            Path::new("/nonexistent-phalanx-fuzz"),
        ) else {
            continue;
        };
        for f in &made.hand.fingers {
            assert!(f.joints.iter().all(|(_, p)| p.is_finite()));
        }
        // `rig` reads the copy back before writing it, and audits it.
        let Ok(copy) = GltfFile::from_bytes("rigged.glb", &made.written.bytes) else {
            continue;
        };
        let Ok(again) = Rig::from_file(copy, None) else {
            continue;
        };
        let chains: Vec<_> = again
            .chains
            .iter()
            .filter(|c| c.side.is_none_or(|s| s == made.hand.side))
            .cloned()
            .collect();
        let _ = AuditedRig::with(
            "rigged.glb",
            &chains,
            &again.notes,
            a,
            &AuditOptions::default(),
            again.weights.as_ref(),
        );
    }
});
