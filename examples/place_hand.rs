//! Places the joints of each hand of a rig file on the fingers found on its skin
//! (`phalanx::rig::make::place`) and prints each made joint's distance from the artist's.
//!
//! Usage: `cargo run --release --example place_hand -- RIG.glb [RIG.fbx ...]` (from the
//! checkout, so data/ is found).

use glam::DVec3;
use phalanx::analysis::{self, Settings};
use phalanx::dataset::{Dataset, Finger, SummaryTable};
use phalanx::rig::Rig;
use phalanx::rig::find::{FindOptions, MeshSelect, find_hand, hand_mesh};
use phalanx::rig::judge::{SoftTissue, WristRatios};
use phalanx::rig::make::place::{Proportions, place};
use std::path::Path;

fn main() {
    let settings = Settings::default();
    let data = analysis::analyse_without_bootstrap(
        &Dataset::load(Path::new("data/measurements.csv")).expect("data"),
        &settings,
    );
    let atlas = analysis::analyse_without_bootstrap(
        &Dataset::load(Path::new("data/atlas/measurements.csv")).expect("atlas"),
        &settings,
    );
    let wrist = WristRatios::load(Path::new("data/atlas/landmarks.csv")).expect("landmarks");
    let table = SummaryTable::load(Path::new(phalanx::rig::judge::SOFT_TISSUE_TABLE)).expect("table");
    let soft = SoftTissue::from_table(&table, None);
    let p = Proportions::new(&data, Some(&atlas), Some(&wrist), soft);
    for path in std::env::args().skip(1) {
        let rig = match Rig::load(Path::new(&path), None) {
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
            let Ok(mesh) = hand_mesh(&rig.file, &select) else { continue };
            let opts = FindOptions {
                fingers: chains.len(),
                wrist: wrist.map(|w| w.position),
                side: *side,
            };
            let hand = match find_hand(&mesh, &opts) {
                Ok(h) => h,
                Err(e) => {
                    println!("{path}: {e}");
                    continue;
                }
            };
            let made = place(&mesh, &hand, &p);
            println!("{path} {:?}", side);
            for n in &made.notes {
                println!("  note: {n}");
            }
            for m in &made.fingers {
                let Some(chain) = chains.iter().find(|c| c.finger == m.finger) else { continue };
                let art: Vec<DVec3> = chain.joints.iter().map(|j| j.position).collect();
                let mut line = format!("  {:<7}", m.finger.name());
                let mut pairs: Vec<(String, DVec3, DVec3, DVec3)> = Vec::new();
                if m.finger == Finger::Thumb {
                    if let (Some(c), Some(mc)) = (m.cmc, &chain.metacarpal) {
                        pairs.push(("CMC".into(), c, mc.position, art[0] - mc.position));
                    }
                }
                for (k, (joint, at)) in m.joints.iter().enumerate() {
                    if k >= art.len() {
                        break;
                    }
                    let dir = if k + 1 < art.len() { art[k + 1] - art[k] } else { art[k] - art[k - 1] };
                    pairs.push((joint.name().to_string(), *at, art[k], dir));
                }
                for (name, made, artist, dir) in pairs {
                    let d = made - artist;
                    let u = dir.normalize_or_zero();
                    let along = d.dot(u);
                    let across = (d - along * u).length();
                    let n = hand.palm_normal;
                    let palmward = (d - along * u).dot((n - n.dot(u) * u).normalize_or_zero());
                    line.push_str(&format!(
                        " {name} {:.1} (along {:+.1}, across {:.1}, palmward {:+.1})",
                        d.length() * 1000.0,
                        along * 1000.0,
                        across * 1000.0,
                        palmward * 1000.0
                    ));
                }
                println!("{line}");
                // Where the artist's MCP lies between the back and the palm (0 = back).
                let n = hand.palm_normal;
                if let Some((b, pm)) = mesh.inside_along(art[0], n) {
                    println!("    artist MCP depth {:.2} of {:.1} mm", -b / (pm - b), (pm - b) * 1000.0);
                }
                for (k, (_, at)) in m.joints.iter().enumerate().skip(1) {
                    if k + 1 >= art.len() { break; }
                    if let Some((b, pm)) = mesh.inside_along(art[k], n) {
                        println!("    artist joint {k} depth {:.2} of {:.1} mm", -b / (pm - b), (pm - b) * 1000.0);
                    }
                    let _ = at;
                }
            }
        }
    }
}
