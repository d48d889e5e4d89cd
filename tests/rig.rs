//! `phalanx rig`: a hand's fingers found on its skin, their joints placed
//! from the statistics, the skin weighted (`rig::make`). Run as a user runs
//! it, on every shared rig with a mesh (../shared/rigs, skipped with the
//! reason when absent) and on the vendored WebXR hands: against the artists'
//! own joints, honest (the same joints with the finger bones deleted), its
//! rest shape kept, its deformation against the artist's, and its refusals.

use crate::audit::hand::skinned_rest_vertices;
use crate::common::{Workdir, glb, manifest_dir, shared_rig_files, unglb};
use glam::DVec3;
use phalanx::dataset::Finger;
use phalanx::rig::naming::Side;
use phalanx::rig::{FingerChain, Rig, bend};
use serde_json::{Value, json};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// One file of a shared rig to rig: its path and the side to give (`--side`
/// for a body with two hands).
fn cases(rigs: &[PathBuf]) -> Vec<(PathBuf, Option<&'static str>)> {
    let mut out = Vec::new();
    for r in rigs {
        if r.to_string_lossy().contains("mannequiny") {
            out.push((r.clone(), Some("right")));
            out.push((r.clone(), Some("left")));
        } else {
            out.push((r.clone(), None));
        }
    }
    out
}

/// A short label: the file's name and the side given.
fn label(path: &Path, side: Option<&str>) -> String {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    match side {
        Some(s) => format!("{name} ({s})"),
        None => name,
    }
}

/// Runs `rig --replace-fingers` on `path` into `wd`, returning the JSON
/// document and the written file.
fn rig_replacing(wd: &Workdir, path: &Path, side: Option<&str>, n: usize) -> (Value, PathBuf) {
    // Named after the input (and side), so a WebXR hand's side is still in
    // its file name for `deform`.
    let stem = path.file_stem().unwrap().to_string_lossy();
    let out = wd
        .path()
        .join(format!("{stem}-{}-{n}.glb", side.unwrap_or("rigged")));
    let mut args = vec![
        "rig",
        path.to_str().unwrap(),
        "--replace-fingers",
        "--out",
        out.to_str().unwrap(),
        "--format",
        "json",
        "-q",
    ];
    if let Some(s) = side {
        args.extend(["--side", s]);
    }
    let doc = wd.run_in_repo(&args).ok().json();
    (doc, out)
}

/// The artist's chains of the side rigged (all of a one-hand file).
fn artists(path: &Path, side: Option<&str>) -> Vec<FingerChain> {
    let rig = Rig::load(path, None).unwrap();
    let want = side.map(|s| if s == "left" { Side::Left } else { Side::Right });
    rig.chains
        .into_iter()
        .filter(|c| want.is_none() || c.side.is_none() || c.side == want)
        .collect()
}

fn point(v: &Value) -> DVec3 {
    let a: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    DVec3::new(a[0], a[1], a[2])
}

/// A made joint against the artist's: the distance in mm, its part along
/// the artist's finger axis there (`dir`, signed: + distal) and across it.
fn split(made: DVec3, artist: DVec3, dir: DVec3) -> (f64, f64, f64) {
    let d = made - artist;
    let u = dir.normalize_or_zero();
    let along = d.dot(u);
    (
        d.length() * 1e3,
        along * 1e3,
        (d - along * u).length() * 1e3,
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// One made joint against the artist's: the rig, the joint type, the
/// distance, along, across (mm).
struct Row {
    rig: String,
    kind: &'static str,
    distance: f64,
    along: f64,
    across: f64,
    /// The part across that lies in the palm's plane (sideways), not in
    /// depth (towards the palm), mm.
    sideways: f64,
}

/// On every shared rig with a mesh: `rig --replace-fingers`, then each made
/// joint against the artist's, per joint type (median and largest distance,
/// along the artist's finger axis and across it), printed as the closing
/// note's table. Checked, as the issue asks, the finding apart from the
/// placing:
/// - finding: the made MCP within 6 mm of the artist's on the median rig
///   (the rigs' medians; the SteamVR gloves' artists put their MCPs 8-11 mm
///   from the statistics' place, see the note printed); every made tip
///   within 2 mm of the skin's end as the audit reads it on the written
///   file (`bend::skin_end`, the written weights); the made PIP and DIP
///   within 2 mm sideways of the artist's finger axis on the median rig (in
///   the palm's plane; their depth is the placing's rule, 0.4 of the skin's
///   thickness from the back, and the whole distance across is printed);
/// - placing: every made finger inside the joint region, at T^2/bound at
///   most 0.1, by the audit of the written file (the JSON's `t2`, `bound`).
#[test]
fn rigged_fingers_against_the_artists_joints_on_every_shared_rig() {
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    let wd = Workdir::with_paper_data();
    let mut rows: Vec<Row> = Vec::new();
    let mut tips: Vec<(String, f64)> = Vec::new();
    for (n, (path, side)) in cases(&rigs).into_iter().enumerate() {
        let name = label(&path, side);
        let (doc, out) = rig_replacing(&wd, &path, side, n);
        let chains = artists(&path, side);
        let written = Rig::load(&out, None).unwrap();
        let weights = written
            .weights
            .as_ref()
            .expect("the rigged file has weights");
        for f in doc["fingers"].as_array().unwrap() {
            let finger: Finger = serde_json::from_value(f["finger"].clone()).unwrap();
            // Placing: inside, far inside.
            let (t2, bound) = (f["t2"].as_f64().unwrap(), f["bound"].as_f64().unwrap());
            assert!(
                f["inside"] == json!(true) && t2 / bound <= 0.1,
                "{name} {finger}: T^2 {t2} of {bound}"
            );
            let made: Vec<(String, DVec3, String)> = f["joints"]
                .as_array()
                .unwrap()
                .iter()
                .map(|j| {
                    (
                        j["joint"].as_str().unwrap().to_string(),
                        point(&j["position"]),
                        j["node"].as_str().unwrap().to_string(),
                    )
                })
                .collect();
            let cmc = made.iter().find(|m| m.0 == "CMC").map(|m| m.1);
            let chain_joints: Vec<&(String, DVec3, String)> =
                made.iter().filter(|m| m.0 != "CMC").collect();
            // The tip against the skin's end the audit reads on the written file.
            let chain = written
                .chains
                .iter()
                .find(|c| {
                    c.finger == finger && c.joints.iter().any(|j| j.name == chain_joints[0].2)
                })
                .unwrap_or_else(|| panic!("{name} {finger}: not read back"));
            let reach = bend::skin_end(chain, weights)
                .unwrap_or_else(|| panic!("{name} {finger}: no skin end read"));
            let k = chain.joints.len();
            let last = chain.joints[k - 1]
                .position
                .distance(chain.joints[k - 2].position);
            let past = (reach - last) * 1e3;
            assert!(
                past.abs() <= 2.0,
                "{name} {finger}: the skin ends {past:.2} mm past the made tip"
            );
            tips.push((format!("{name} {finger}"), past));
            // Against the artist's joints.
            let Some(art) = chains.iter().find(|c| c.finger == finger) else {
                continue;
            };
            let a: Vec<DVec3> = art.joints.iter().map(|j| j.position).collect();
            let thumb = finger == Finger::Thumb;
            // The palm's normal from the artist's joints: the wrist, the
            // index's MCP and the little finger's (else the ring's).
            let mcp_of = |g: Finger| {
                chains
                    .iter()
                    .find(|c| c.finger == g)
                    .map(|c| c.joints[0].position)
            };
            let wrist = chains
                .iter()
                .find_map(|c| c.wrist.as_ref().map(|w| w.position));
            let normal = match (
                wrist,
                mcp_of(Finger::Index),
                mcp_of(Finger::Little).or(mcp_of(Finger::Ring)),
            ) {
                (Some(w), Some(i), Some(l)) => (i - w).cross(l - w).normalize_or_zero(),
                _ => DVec3::ZERO,
            };
            let sideways = |made: DVec3, artist: DVec3, dir: DVec3| -> f64 {
                let u = dir.normalize_or_zero();
                let d = made - artist;
                let perp = d - d.dot(u) * u;
                let n = (normal - normal.dot(u) * u).normalize_or_zero();
                (perp - perp.dot(n) * n).length() * 1e3
            };
            if let (Some(cmc), Some(mc)) = (cmc, &art.metacarpal) {
                let (d, al, ac) = split(cmc, mc.position, a[0] - mc.position);
                rows.push(Row {
                    rig: name.clone(),
                    kind: "thumb CMC",
                    distance: d,
                    along: al,
                    across: ac,
                    sideways: sideways(cmc, mc.position, a[0] - mc.position),
                });
            }
            let kinds: Vec<&'static str> = if thumb {
                vec!["thumb MCP", "thumb IP", "thumb tip"]
            } else {
                vec!["finger MCP", "finger PIP", "finger DIP", "finger tip"]
            };
            for (i, m) in chain_joints.iter().enumerate() {
                if i >= a.len() || (i + 1 == kinds.len() && !art.has_tip) {
                    break;
                }
                let dir = if i + 1 < a.len() {
                    a[i + 1] - a[i]
                } else {
                    a[i] - a[i - 1]
                };
                let (d, al, ac) = split(m.1, a[i], dir);
                rows.push(Row {
                    rig: name.clone(),
                    kind: kinds[i],
                    distance: d,
                    along: al,
                    across: ac,
                    sideways: sideways(m.1, a[i], dir),
                });
            }
        }
    }
    // The table: per joint type, over every rig.
    let mut table = String::from(
        "| joint | n | median mm | largest mm | median along | median across | of it sideways | largest across |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let kinds = [
        "thumb CMC",
        "thumb MCP",
        "thumb IP",
        "thumb tip",
        "finger MCP",
        "finger PIP",
        "finger DIP",
        "finger tip",
    ];
    for kind in kinds {
        let of: Vec<&Row> = rows.iter().filter(|r| r.kind == kind).collect();
        if of.is_empty() {
            continue;
        }
        let d: Vec<f64> = of.iter().map(|r| r.distance).collect();
        let largest = of
            .iter()
            .max_by(|a, b| a.distance.total_cmp(&b.distance))
            .unwrap();
        let across_max = of.iter().map(|r| r.across).fold(0.0, f64::max);
        writeln!(
            table,
            "| {kind} | {} | {:.1} | {:.1} ({}) | {:+.1} | {:.1} | {:.1} | {:.1} |",
            of.len(),
            median(d),
            largest.distance,
            largest.rig,
            median(of.iter().map(|r| r.along).collect()),
            median(of.iter().map(|r| r.across).collect()),
            median(of.iter().map(|r| r.sideways).collect()),
            across_max
        )
        .unwrap();
    }
    // Per rig: its median finger MCP distance and PIP/DIP across.
    // A rig is a file: the mannequin's two hands are one rig.
    let file = |r: &str| r.split(" (").next().unwrap_or(r).to_string();
    let mut names: Vec<String> = rows.iter().map(|r| file(&r.rig)).collect();
    names.dedup();
    let (mut mcp, mut inner) = (Vec::new(), Vec::new());
    for r in &names {
        let m = median(
            rows.iter()
                .filter(|x| file(&x.rig) == *r && x.kind == "finger MCP")
                .map(|x| x.distance)
                .collect(),
        );
        let inner_of = |f: fn(&Row) -> f64| {
            median(
                rows.iter()
                    .filter(|x| {
                        file(&x.rig) == *r && (x.kind == "finger PIP" || x.kind == "finger DIP")
                    })
                    .map(f)
                    .collect(),
            )
        };
        let (i, all) = (inner_of(|x| x.sideways), inner_of(|x| x.across));
        writeln!(
            table,
            "{r}: finger MCP median {m:.2} mm; PIP and DIP across median {all:.2} mm, \
             {i:.2} mm of it sideways"
        )
        .unwrap();
        mcp.push(m);
        inner.push(i);
    }
    let worst_tip = tips.iter().map(|t| t.1.abs()).fold(0.0, f64::max);
    writeln!(
        table,
        "made tips: the skin's end at most {worst_tip:.2} mm from the made tip"
    )
    .unwrap();
    eprintln!("{table}");
    let (mcp, inner) = (median(mcp), median(inner));
    eprintln!(
        "the median rig: finger MCPs {mcp:.2} mm, PIPs and DIPs {inner:.2} mm sideways of the \
         artists' axes"
    );
    assert!(
        mcp <= 6.0,
        "the median rig's finger MCPs are {mcp:.1} mm from the artists'\n{table}"
    );
    assert!(
        inner <= 2.0,
        "the median rig's PIPs and DIPs are {inner:.1} mm sideways of the artists' axes\n{table}"
    );
}

/// `json` with every node whose name `drop` says deleted (the indices of the
/// rest renumbered in children and scenes), and its skins, joints and
/// weights taken away.
fn without_nodes(mut json: Value, drop: impl Fn(&str) -> bool) -> Value {
    let nodes = json["nodes"].as_array().unwrap().clone();
    let mut map = vec![None; nodes.len()];
    let mut kept = Vec::new();
    for (i, n) in nodes.iter().enumerate() {
        if !drop(n["name"].as_str().unwrap_or("")) {
            map[i] = Some(kept.len());
            kept.push(n.clone());
        }
    }
    let renumber = |list: &Value| -> Value {
        Value::Array(
            list.as_array()
                .unwrap()
                .iter()
                .filter_map(|i| map[i.as_u64().unwrap() as usize].map(|j| json!(j)))
                .collect(),
        )
    };
    for n in &mut kept {
        let o = n.as_object_mut().unwrap();
        o.remove("skin");
        if let Some(c) = o.get("children").cloned() {
            o.insert("children".into(), renumber(&c));
        }
    }
    json["nodes"] = Value::Array(kept);
    for s in json["scenes"].as_array_mut().unwrap() {
        let list = s["nodes"].clone();
        s["nodes"] = renumber(&list);
    }
    json.as_object_mut().unwrap().remove("skins");
    json.as_object_mut().unwrap().remove("animations");
    for mesh in json["meshes"].as_array_mut().unwrap() {
        for prim in mesh["primitives"].as_array_mut().unwrap() {
            let attrs = prim["attributes"].as_object_mut().unwrap();
            attrs.remove("JOINTS_0");
            attrs.remove("WEIGHTS_0");
        }
    }
    json
}

/// Each made joint of a `rig` document, by finger and joint.
fn joints_of(doc: &Value) -> Vec<(String, DVec3)> {
    let mut out = Vec::new();
    for f in doc["fingers"].as_array().unwrap() {
        let finger = f["finger"].as_str().unwrap();
        for j in f["joints"].as_array().unwrap() {
            out.push((
                format!("{finger} {}", j["joint"].as_str().unwrap()),
                point(&j["position"]),
            ));
        }
    }
    out
}

/// The vendored WebXR hands (data/rigs/webxr-generic-hand), the tests' own
/// hands that need nothing from ../shared.
fn vendored_hands() -> Vec<PathBuf> {
    ["left.glb", "right.glb"]
        .iter()
        .map(|f| manifest_dir().join("data/rigs/webxr-generic-hand").join(f))
        .filter(|p| p.is_file())
        .collect()
}

/// Honesty: `rig --replace-fingers` on a WebXR hand gives the same joints,
/// within 0.01 mm, as `rig` on the same hand with its finger bones deleted
/// (every finger and metacarpal node gone, no skin, no joints, no weights),
/// given the wrist where the hand bone was. The rig reads the skin, not the
/// bones.
#[test]
fn the_joints_made_do_not_depend_on_the_finger_bones() {
    let hands = vendored_hands();
    assert_eq!(
        hands.len(),
        2,
        "data/rigs/webxr-generic-hand has both hands"
    );
    let wd = Workdir::with_paper_data();
    for (n, path) in hands.iter().enumerate() {
        let (doc, _) = rig_replacing(&wd, path, None, 100 + n);
        let rig = Rig::load(path, None).unwrap();
        let wrist = rig
            .chains
            .iter()
            .find_map(|c| c.wrist.clone())
            .unwrap()
            .position;
        let (json, bin) = unglb(&std::fs::read(path).unwrap());
        let bare = without_nodes(json, |name| {
            ["thumb", "index", "middle", "ring", "pinky"]
                .iter()
                .any(|f| name.starts_with(f))
        });
        assert!(
            !bare["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .any(|n| n["name"].as_str().is_some_and(|s| s.contains("phalanx"))),
            "the finger nodes are gone"
        );
        let input = wd.write(&format!("bare-{n}.glb"), glb(&bare, &bin));
        let out = wd.path().join(format!("bare-rigged-{n}.glb"));
        let at = format!("{},{},{}", wrist.x, wrist.y, wrist.z);
        let made = wd
            .run_in_repo(&[
                "rig",
                input.to_str().unwrap(),
                "--wrist",
                &at,
                "--out",
                out.to_str().unwrap(),
                "--format",
                "json",
                "-q",
            ])
            .ok()
            .json();
        let (a, b) = (joints_of(&doc), joints_of(&made));
        assert_eq!(a.len(), b.len(), "{}: {a:?} {b:?}", path.display());
        assert_eq!(
            a.len(),
            20,
            "five fingers, four points each (the thumb CMC to tip)"
        );
        for ((ka, pa), (kb, pb)) in a.iter().zip(&b) {
            assert_eq!(ka, kb);
            assert!(
                pa.distance(*pb) <= 1e-5,
                "{}: {ka} {:.4} mm apart",
                path.display(),
                pa.distance(*pb) * 1e3
            );
        }
        // The bare hand's new rig is a rig: five chains read back.
        let back = Rig::load(&out, None).unwrap();
        assert_eq!(back.chains.len(), 5, "{}", path.display());
    }
}

/// The rest shape is kept: every vertex of the rigged WebXR hands, skinned
/// in the bind pose of the written file (glTF 2.0 skinning written from the
/// specification, tests/audit/hand.rs), lies within 1e-5 of where the
/// original file's skin puts it.
#[test]
fn a_rigged_hand_keeps_its_rest_shape() {
    let wd = Workdir::with_paper_data();
    for (n, path) in vendored_hands().iter().enumerate() {
        let (_, out) = rig_replacing(&wd, path, None, 200 + n);
        let before = skinned_rest_vertices(&std::fs::read(path).unwrap());
        let after = skinned_rest_vertices(&std::fs::read(&out).unwrap());
        assert_eq!(before.len(), after.len());
        let worst = before
            .iter()
            .zip(&after)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-5,
            "{}: a vertex moved {worst} m",
            path.display()
        );
    }
}

/// Deformation: each made rig against the artist's (`deform RIGGED
/// --against ORIGINAL`: A the made rig, B the artist's), in the fist and the
/// grip, by linear blend and dual quaternions: the made rig is better at no
/// fewer joints than it is worse, on every shared rig whose artist skinned
/// it smoothly. The GDQuest mannequin is a segmented body (each bone moves a
/// rigid piece: no edge stretches at most joints), which any smooth blend
/// loses to on strain; its tally is printed and not asserted. The tally per
/// rig is printed.
#[test]
#[ignore = "slow: 40 deformations of the shared rigs (run by .ci/run)"]
fn a_rigged_hand_deforms_no_worse_than_the_artists() {
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    let wd = Workdir::with_paper_data();
    let mut tally = String::new();
    let mut worse = Vec::new();
    for (n, (path, side)) in cases(&rigs).into_iter().enumerate() {
        let name = label(&path, side);
        let (_, out) = rig_replacing(&wd, &path, side, 300 + n);
        let (mut made, mut artist, mut judged, mut rigid) = (0, 0, 0, 0);
        for pose in ["fist", "grip"] {
            for skinning in ["lbs", "dqs"] {
                let doc = wd
                    .run_in_repo(&[
                        "deform",
                        out.to_str().unwrap(),
                        "--against",
                        path.to_str().unwrap(),
                        "--pose",
                        pose,
                        "--skinning",
                        skinning,
                        "--format",
                        "json",
                    ])
                    .ok()
                    .json();
                for hand in doc["verdicts"].as_array().unwrap() {
                    for j in hand["joints"].as_array().unwrap() {
                        match j["overall"].as_str() {
                            Some("a") => made += 1,
                            Some("b") => artist += 1,
                            _ => {}
                        }
                        // The artist's skin where it was remade (not the
                        // other hand's, which is the same in both files):
                        // rigid when no edge stretches (strain p95 within
                        // its tie, 0.005) at the joint.
                        if j["overall"].as_str() != Some("same") {
                            let p95 = j["measures"]
                                .as_array()
                                .unwrap()
                                .iter()
                                .find(|m| m["measure"] == "strain_p95")
                                .and_then(|m| m["b"].as_f64());
                            judged += 1;
                            rigid += usize::from(p95.is_some_and(|x| x <= 0.005));
                        }
                    }
                }
            }
        }
        writeln!(
            tally,
            "{name}: the made rig better at {made} joints, the artist's at {artist}"
        )
        .unwrap();
        if 2 * rigid > judged {
            // A segmented mannequin: each bone moves its own rigid piece,
            // which no smooth blend matches on strain. Printed, not held to.
            writeln!(
                tally,
                "  {name}: the artist's skin is rigid (no edge stretches) at {rigid} of {judged} \
                 joints: a segmented mannequin, which smooth weights cannot beat on strain; not \
                 asserted"
            )
            .unwrap();
        } else if made < artist {
            worse.push(name);
        }
    }
    eprintln!("{tally}");
    assert!(
        worse.is_empty(),
        "the made rig deforms worse on {worse:?}\n{tally}"
    );
}

/// Bad input: a clear error, exit 2, nothing written. A mesh that is not a
/// hand (a box); a hand whose fingers are already rigged, without
/// `--replace-fingers`; two hands without `--side` (the GDQuest mannequin,
/// when ../shared is there).
#[test]
fn rig_refuses_what_is_not_a_hand_at_rest_and_writes_nothing() {
    let wd = Workdir::with_paper_data();
    // A box, 8 corners and 12 triangles.
    let corners: Vec<[f32; 3]> = (0..8)
        .map(|i| {
            [
                (i & 1) as f32 * 0.1,
                ((i >> 1) & 1) as f32 * 0.1,
                ((i >> 2) & 1) as f32 * 0.1,
            ]
        })
        .collect();
    let tris: [[u16; 3]; 12] = [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    let mut bin: Vec<u8> = corners
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let index_at = bin.len();
    bin.extend(tris.iter().flatten().flat_map(|i| i.to_le_bytes()));
    let json = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "box", "mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [0.1, 0.1, 0.1]},
            {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": index_at},
            {"buffer": 0, "byteOffset": index_at, "byteLength": 72}
        ],
        "buffers": [{"byteLength": index_at + 72}]
    });
    let boxed = wd.write("box.glb", glb(&json, &bin));
    let out = wd.path().join("box-rigged.glb");
    wd.run_in_repo(&[
        "rig",
        boxed.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
    .data_error()
    .stderr_has("box.glb");
    assert!(!out.exists(), "nothing written for a box");

    // Fingers already rigged.
    let hand = vendored_hands()
        .into_iter()
        .next()
        .expect("a vendored hand");
    let out = wd.path().join("again.glb");
    wd.run_in_repo(&[
        "rig",
        hand.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
    .data_error()
    .stderr_has("--replace-fingers");
    assert!(!out.exists(), "nothing written for a rigged hand");

    // The side given is not the side the bones name.
    let out = wd.path().join("wrong-side.glb");
    let left = vendored_hands()
        .into_iter()
        .next()
        .expect("a vendored hand");
    let (mut named, bin) = unglb(&std::fs::read(&left).unwrap());
    if let Some(w) = named["nodes"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|n| n["name"] == "wrist")
    {
        // WebXR's names say no side; a hand bone named for the left does.
        w["name"] = json!("LeftHand");
    }
    let input = wd.write("named-left.glb", glb(&named, &bin));
    wd.run_in_repo(&[
        "rig",
        input.to_str().unwrap(),
        "--replace-fingers",
        "--side",
        "right",
        "--out",
        out.to_str().unwrap(),
    ])
    .data_error()
    .stderr_has("give --side left");
    assert!(!out.exists(), "nothing written for the wrong side");

    // Two hands, no side (without ../shared/rigs, shared_rig_files says so).
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    if let Some(body) = rigs
        .into_iter()
        .find(|r| r.to_string_lossy().contains("mannequiny"))
    {
        let out = wd.path().join("body.glb");
        wd.run_in_repo(&[
            "rig",
            body.to_str().unwrap(),
            "--replace-fingers",
            "--out",
            out.to_str().unwrap(),
        ])
        .data_error()
        .stderr_has("--side");
        assert!(!out.exists(), "nothing written for two hands");
    } else {
        crate::common::skip("two hands, no side: the GDQuest mannequin is not in ../shared/rigs");
    }
}

/// The audit uses the same finding: the vendored WebXR hands with their tip
/// nodes and their skin deleted (no weights give a tip) are judged on every
/// finger, the thumb included, from the fingertips found on the skin; each
/// found tip reaches as far past the last joint, within 2.5 mm, as the
/// skin's end the audit reads from the weights of the whole file (the tip
/// node and `skin_tip` past it, in the original's audit), an independent
/// reading of the same skin.
#[test]
fn the_audit_judges_tipless_fingers_by_the_tips_found_on_the_skin() {
    let wd = Workdir::with_paper_data();
    for (n, path) in vendored_hands().iter().enumerate() {
        let whole = wd
            .run_in_repo(&["audit", path.to_str().unwrap(), "--format", "json"])
            .ok()
            .json();
        let (json, bin) = unglb(&std::fs::read(path).unwrap());
        let bare = without_nodes(json, |name| name.ends_with("-tip"));
        let stem = path.file_stem().unwrap().to_string_lossy();
        let input = wd.write(&format!("{stem}-tipless-{n}.glb"), glb(&bare, &bin));
        let run = wd.run_in_repo(&["audit", input.to_str().unwrap(), "--format", "json"]);
        let doc = run.ok().json();
        let fingers = doc["rig"]["fingers"].as_array().unwrap();
        assert_eq!(fingers.len(), 5, "{}: every finger judged", path.display());
        for f in fingers {
            let name = f["finger"].as_str().unwrap();
            assert_eq!(f["has_tip"], json!(false), "{name}: the tip nodes are gone");
            assert_eq!(f["skin_tip"]["from_mesh"], json!(true), "{name}: {f}");
            let original = whole["rig"]["fingers"]
                .as_array()
                .unwrap()
                .iter()
                .find(|g| g["finger"] == f["finger"])
                .unwrap();
            // How far the skin reaches past the last joint: by the found tip
            // (along the last bone); by the weights (past the tip node along
            // the node's direction, plus the node's own distance).
            let joints = original["joints"].as_array().unwrap();
            let k = joints.len();
            let (last, tip) = (
                point(&joints[k - 2]["position"]),
                point(&joints[k - 1]["position"]),
            );
            let by_weights =
                last.distance(tip) + original["skin_tip"]["beyond_node"].as_f64().unwrap_or(0.0);
            let found = f["skin_tip"]["beyond_node"].as_f64().unwrap();
            eprintln!(
                "{} {name}: the skin reaches {:.2} mm past the last joint by the found tip, {:.2} mm by the weights",
                path.display(),
                found * 1e3,
                by_weights * 1e3
            );
            assert!(
                (found - by_weights).abs() <= 2.5e-3,
                "{}: {name}'s found tip reaches {:.2} mm, the weights' {:.2} mm",
                path.display(),
                found * 1e3,
                by_weights * 1e3
            );
        }
    }
}

/// The Khronos glTF validator adds no issue of any severity to the files
/// `rig` writes: the vendored WebXR hands re-rigged (`--replace-fingers`),
/// and rigged from their bare mesh (finger bones and skin deleted), each
/// against its input. Installed with npm by the audit's validator test; the
/// test is skipped with the reason when it cannot be.
#[test]
#[ignore = "slow: installs and runs the Khronos glTF validator with npm (run by .ci/run)"]
fn the_files_rig_writes_add_no_validator_issue() {
    let tools = match crate::audit::validator::validator() {
        Ok(t) => t,
        Err(why) => {
            crate::common::skip(format!("the Khronos glTF validator is unavailable: {why}"));
            return;
        }
    };
    let wd = Workdir::with_paper_data();
    let mut pairs: Vec<(PathBuf, PathBuf)> = Vec::new();
    for (n, path) in vendored_hands().iter().enumerate() {
        let (_, out) = rig_replacing(&wd, path, None, 400 + n);
        pairs.push((path.clone(), out));
        let (json, bin) = unglb(&std::fs::read(path).unwrap());
        let bare = without_nodes(json, |name| {
            ["thumb", "index", "middle", "ring", "pinky"]
                .iter()
                .any(|f| name.starts_with(f))
        });
        let stem = path.file_stem().unwrap().to_string_lossy();
        let input = wd.write(&format!("{stem}-bare-{n}.glb"), glb(&bare, &bin));
        let out = wd.path().join(format!("{stem}-made-{n}.glb"));
        wd.run_in_repo(&[
            "rig",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ])
        .ok();
        pairs.push((input, out));
    }
    let files: Vec<PathBuf> = pairs
        .iter()
        .flat_map(|(a, b)| [a.clone(), b.clone()])
        .collect();
    let reports = crate::audit::validator::issues(&tools, &files);
    for (k, (input, _)) in pairs.iter().enumerate() {
        let (before, after) = (&reports[2 * k], &reports[2 * k + 1]);
        for (key, &n) in after {
            let had = before.get(key).copied().unwrap_or(0);
            assert!(
                n <= had,
                "{}: rig adds {key:?} ({had} -> {n}); input {before:?}, output {after:?}",
                input.display()
            );
        }
        eprintln!("{}: input {before:?}; rigged {after:?}", input.display());
    }
}
