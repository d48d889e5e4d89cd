//! Writes a synthetic skinned hand of tubes (see `phalanx::rig::deform::synthetic`)
//! as a .glb, for trying and benchmarking `phalanx deform`.
//!
//! Usage: `cargo run --release --example tube_hand -- OUT.glb [left|right] [AROUND RING_SPACING_MM WEIGHT_SHIFT_MM]`
//! (defaults: right, 16 vertices per ring, 1 mm between rings, weights centred on the joints).
//! `32 1.44 0` gives about 30,000 triangles.

use phalanx::dataset::Finger;
use phalanx::rig::deform::synthetic::{HandSpec, tube_hand};
use phalanx::rig::naming::Side;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(out) = args.first() else {
        eprintln!("usage: tube_hand OUT.glb [left|right] [AROUND RING_SPACING_MM WEIGHT_SHIFT_MM]");
        std::process::exit(2);
    };
    let side = args
        .get(1)
        .and_then(|s| Side::parse(s))
        .unwrap_or(Side::Right);
    let num = |i: usize, default: f64| {
        args.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|x| x.is_finite() && *x >= 0.0)
            .unwrap_or(default)
    };
    let spec = HandSpec {
        side,
        fingers: Finger::ALL.to_vec(),
        around: num(2, 16.0).clamp(3.0, 256.0) as usize,
        ring_spacing: num(3, 1.0).max(0.1) * 0.001,
        weight_shift: num(4, 0.0) * 0.001,
        ..HandSpec::default()
    };
    let rig = tube_hand(&spec);
    match rig.to_glb() {
        Ok(bytes) => {
            if let Err(e) = std::fs::write(out, bytes) {
                eprintln!("cannot write {out}: {e}");
                std::process::exit(1);
            }
            eprintln!(
                "wrote {out}: {} vertices, {} triangles",
                rig.mesh.positions.len(),
                rig.mesh.triangles.len()
            );
        }
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}
