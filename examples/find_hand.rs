//! Finds the fingers on the skin of each hand of a rig file (`phalanx::rig::find`), given
//! the hand bone's origin as the wrist, and prints them with the time the finding took.
//!
//! Usage: `cargo run --release --example find_hand -- RIG.glb [RIG.fbx ...]`

use phalanx::rig::Rig;
use phalanx::rig::find::{FindOptions, find_hand};
use phalanx::rig::find::{MeshSelect, hand_mesh};
use std::time::Instant;

fn main() {
    let paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        eprintln!("usage: find_hand RIG.glb [RIG.fbx ...]");
        std::process::exit(2);
    }
    for path in paths {
        let rig = match Rig::load(std::path::Path::new(&path), None) {
            Ok(rig) => rig,
            Err(e) => {
                eprintln!("{e}");
                continue;
            }
        };
        let mut sides: Vec<_> = rig.chains.iter().map(|c| c.side).collect();
        sides.sort();
        sides.dedup();
        for side in &sides {
            let chains: Vec<_> = rig.chains.iter().filter(|c| c.side == *side).collect();
            let wrist = chains.iter().find_map(|c| c.wrist.clone());
            let select = match (&wrist, sides.len()) {
                (Some(w), 2..) => MeshSelect::UnderNode { node: w.node },
                _ => MeshSelect::Whole,
            };
            let mesh = match hand_mesh(&rig.file, &select) {
                Ok(m) => m,
                Err(e) => {
                    eprintln!("{e}");
                    continue;
                }
            };
            let opts = FindOptions {
                fingers: chains.len(),
                wrist: wrist.map(|w| w.position),
                side: *side,
                ..FindOptions::default()
            };
            let start = Instant::now();
            let found = find_hand(&mesh, &opts);
            let took = start.elapsed();
            match found {
                Ok(hand) => {
                    println!(
                        "{path}: a {} hand, {} vertices, found in {:.2} ms",
                        hand.side.name(),
                        mesh.positions.len(),
                        took.as_secs_f64() * 1000.0
                    );
                    for f in &hand.fingers {
                        let t = f.tip * 1000.0;
                        println!(
                            "  {:<7} tip ({:.1}, {:.1}, {:.1}) mm, persistence {:.0} mm, web {:.0} mm from the tip, radius {:.1} mm",
                            f.finger.name(),
                            t.x,
                            t.y,
                            t.z,
                            f.persistence * 1000.0,
                            f.web_arc * 1000.0,
                            f.radius[f.measured / 2] * 1000.0
                        );
                    }
                    for n in &hand.notes {
                        println!("  note: {n}");
                    }
                }
                Err(e) => println!("{path}: {}", e.in_file(&path)),
            }
        }
    }
}
