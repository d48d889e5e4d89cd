//! `phalanx audit` and `deform` on FBX rigs: the SteamVR gloves from
//! ../shared/rigs/steamvr-gloves (skipped with a reason when absent), read
//! against an independent reading of the same files, the same rig as glTF,
//! `--moves` applied back to the file with the loader, and broken files.

use crate::common::*;
use glam::{DMat4, DQuat, DVec3};
use serde_json::{Value, json};
use std::path::PathBuf;

const GLOVES: [(&str, &str); 2] = [
    ("vr_glove_model.fbx", "right"),
    ("vr_glove_left_model_slim.fbx", "left"),
];

/// The gloves' folder, or `None` (with the reason printed) when it is absent.
fn gloves() -> Option<PathBuf> {
    let dir = manifest_dir().join("../shared/rigs/steamvr-gloves");
    if dir.join(GLOVES[0].0).is_file() {
        Some(dir)
    } else {
        skip(format!("the SteamVR gloves are not in {}", dir.display()));
        None
    }
}

/// The bootstrap's resamples in these tests: enough for stable verdicts on
/// the paper's 5 X-rays, few enough for the debug build.
const RESAMPLES: &str = "1000";

/// `phalanx audit ARGS` with [`RESAMPLES`].
fn audit(wd: &Workdir, args: &[&str]) -> Run {
    let mut all = vec!["audit", "--resamples", RESAMPLES];
    all.extend_from_slice(args);
    // The full text, where the text is asked for (node names, units).
    if !args.iter().any(|a| ["--format", "--brief"].contains(a)) {
        all.push("--explain");
    }
    wd.run(&all)
}

/// A work directory with the paper's data and the gloves.
fn with_gloves() -> Option<Workdir> {
    let dir = gloves()?;
    let wd = Workdir::with_paper_data();
    for (name, _) in GLOVES {
        wd.write(name, std::fs::read(dir.join(name)).unwrap());
    }
    Some(wd)
}

fn v3(v: ufbx::Vec3) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

/// The independent reading: each node's world matrix composed here from the
/// local transforms the file gives (translation, rotation, scale; no
/// conversion of units or axes), and each bone's bind pose from its skin
/// cluster; both in metres (the file's unit times UnitScaleFactor / 100).
struct Reading {
    names: Vec<String>,
    composed: Vec<DVec3>,
    clusters: Vec<Option<DVec3>>,
}

fn read_independently(bytes: &[u8]) -> Reading {
    let scene = ufbx::load_memory(bytes, ufbx::LoadOpts::default()).expect("ufbx reads the glove");
    let unit = scene.settings.unit_meters;
    let n = scene.nodes.len();
    let mut world = vec![None::<DMat4>; n];
    fn compose(scene: &ufbx::Scene, i: usize, world: &mut Vec<Option<DMat4>>) -> DMat4 {
        if let Some(m) = world[i] {
            return m;
        }
        let nd = &scene.nodes[i];
        let t = &nd.local_transform;
        let local = DMat4::from_scale_rotation_translation(
            v3(t.scale),
            DQuat::from_xyzw(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w),
            v3(t.translation),
        );
        let up = match nd.parent.as_ref() {
            Some(p) => compose(scene, p.element.typed_id as usize, world),
            None => DMat4::IDENTITY,
        };
        world[i] = Some(up * local);
        up * local
    }
    let mut composed = Vec::new();
    for i in 0..n {
        composed.push(compose(&scene, i, &mut world).w_axis.truncate() * unit);
    }
    let mut clusters = vec![None; n];
    for d in scene.skin_deformers.iter() {
        for c in d.clusters.iter() {
            if let Some(b) = c.bone_node.as_ref() {
                let m = &c.bind_to_world;
                clusters[b.element.typed_id as usize] =
                    Some(DVec3::new(m.m03, m.m13, m.m23) * unit);
            }
        }
    }
    Reading {
        names: scene
            .nodes
            .iter()
            .map(|nd| nd.element.name.to_string())
            .collect(),
        composed,
        clusters,
    }
}

impl Reading {
    fn position(&self, name: &str) -> DVec3 {
        let i = self.names.iter().position(|n| n == name).expect(name);
        self.clusters[i].unwrap_or(self.composed[i])
    }
}

fn fingers(doc: &Value) -> &Vec<Value> {
    doc["rig"]["fingers"].as_array().unwrap()
}

fn point(v: &Value) -> DVec3 {
    DVec3::new(num(&v[0]), num(&v[1]), num(&v[2]))
}

#[test]
fn both_gloves_have_every_finger_with_metacarpal_and_tip_at_the_files_lengths() {
    let Some(wd) = with_gloves() else { return };
    for (name, side) in GLOVES {
        let bytes = wd.read(name);
        let reading = read_independently(&bytes);
        // The file's node transforms and its clusters agree (the gloves are saved in their bind pose).
        for (i, c) in reading.clusters.iter().enumerate() {
            if let Some(c) = c {
                assert!(
                    c.distance(reading.composed[i]) < 1e-7,
                    "{name} {}",
                    reading.names[i]
                );
            }
        }
        let doc = audit(&wd, &[name, "--tip", "skin", "--format", "json"])
            .ok()
            .json();
        let fs = fingers(&doc);
        let mut found: Vec<&str> = fs.iter().map(|f| f["finger"].as_str().unwrap()).collect();
        found.sort();
        assert_eq!(
            found,
            ["index", "little", "middle", "ring", "thumb"],
            "{name}"
        );
        let s = &side[..1];
        for f in fs {
            assert_eq!(f["side"], side, "{name}");
            assert_eq!(f["has_tip"], true, "{name}");
            let finger = match f["finger"].as_str().unwrap() {
                "little" => "pinky",
                x => x,
            };
            let joints: Vec<&str> = f["joints"]
                .as_array()
                .unwrap()
                .iter()
                .map(|j| j["name"].as_str().unwrap())
                .collect();
            let (meta, expected): (String, Vec<String>) = if finger == "thumb" {
                (
                    format!("finger_thumb_0_{s}"),
                    vec![
                        format!("finger_thumb_1_{s}"),
                        format!("finger_thumb_2_{s}"),
                        format!("finger_thumb_{s}_end"),
                    ],
                )
            } else {
                (
                    format!("finger_{finger}_meta_{s}"),
                    (0..3)
                        .map(|k| format!("finger_{finger}_{k}_{s}"))
                        .chain([format!("finger_{finger}_{s}_end")])
                        .collect(),
                )
            };
            assert_eq!(joints, expected, "{name}");
            assert_eq!(f["metacarpal"]["name"], meta.as_str(), "{name}");
            // Lengths within 0.1 mm of the independent reading (metres, +Y up or not).
            let ours: Vec<f64> = f["audit"]["segments"]
                .as_array()
                .unwrap()
                .iter()
                .map(num)
                .collect();
            let theirs: Vec<f64> = expected
                .windows(2)
                .map(|w| reading.position(&w[0]).distance(reading.position(&w[1])))
                .collect();
            assert_eq!(ours.len(), theirs.len());
            for (a, b) in ours.iter().zip(&theirs) {
                assert!((a - b).abs() < 1e-4, "{name} {finger}: {a} vs {b}");
                assert!(
                    *a > 0.01 && *a < 0.06,
                    "{name} {finger}: a phalanx of {a} m"
                );
            }
            let mc =
                point(&f["metacarpal"]["position"]).distance(point(&f["joints"][0]["position"]));
            let mc_theirs = reading
                .position(&meta)
                .distance(reading.position(&expected[0]));
            assert!((mc - mc_theirs).abs() < 1e-4, "{name} {finger} metacarpal");
        }
        // The marker-like helper bones are never joints.
        let text = doc.to_string();
        assert!(
            !text.contains("_aux\""),
            "{name}: an _aux bone was taken as a joint"
        );
    }
}

/// A glTF of the independent reading: every node at its position (no
/// rotation), parent and child as in the file, no mesh.
fn gltf_of(reading: &Reading, bytes: &[u8]) -> Value {
    let scene = ufbx::load_memory(bytes, ufbx::LoadOpts::default()).unwrap();
    let n = reading.names.len();
    let parent: Vec<Option<usize>> = scene
        .nodes
        .iter()
        .map(|nd| nd.parent.as_ref().map(|p| p.element.typed_id as usize))
        .collect();
    let pos = |i: usize| reading.clusters[i].unwrap_or(reading.composed[i]);
    let nodes: Vec<Value> = (0..n)
        .map(|i| {
            let t = pos(i) - parent[i].map_or(DVec3::ZERO, pos);
            let children: Vec<usize> = (0..n).filter(|&c| parent[c] == Some(i)).collect();
            let mut node = json!({"name": reading.names[i], "translation": t.to_array()});
            if !children.is_empty() {
                node["children"] = json!(children);
            }
            node
        })
        .collect();
    let roots: Vec<usize> = (0..n).filter(|&i| parent[i].is_none()).collect();
    json!({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": roots}], "nodes": nodes})
}

/// Each finger's standings: every joint's and every value's, and the explanation's moved joints.
fn verdicts(doc: &Value) -> Vec<(String, Vec<String>)> {
    let mut out: Vec<(String, Vec<String>)> = fingers(doc)
        .iter()
        .map(|f| {
            let a = &f["audit"];
            let mut v: Vec<String> = a["joints"]
                .as_array()
                .unwrap()
                .iter()
                .map(|j| format!("{} {}", j["joint"], j["standing"]))
                .collect();
            v.extend(
                a["values"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| format!("{} {}", x["quantity"], x["standing"])),
            );
            v.push(format!("moves {}", a["explanation"]["moved"]));
            (format!("{} {}", f["side"], f["finger"]), v)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn an_fbx_and_the_same_rig_as_gltf_give_the_same_verdicts() {
    // The glTF is built here from the independent reading (node positions
    // only), so it shares no code with the FBX reader; tips are the tip
    // nodes on both (--tip skin: the glTF has no mesh).
    let Some(wd) = with_gloves() else { return };
    for (name, _) in GLOVES {
        let reading = read_independently(&wd.read(name));
        let gltf = name.replace(".fbx", ".gltf");
        wd.write(&gltf, gltf_of(&reading, &wd.read(name)).to_string());
        let a = audit(&wd, &[name, "--tip", "skin", "--format", "json"])
            .ok()
            .json();
        let b = audit(&wd, &[&gltf, "--tip", "skin", "--format", "json"])
            .ok()
            .json();
        let (va, vb) = (verdicts(&a), verdicts(&b));
        assert_eq!(va.len(), 5);
        assert_eq!(va, vb, "{name}");
        // And the same segments to a micrometre (the glTF keeps the file's
        // axes, the FBX reader turns them to +X right, +Z front).
        for (fa, fb) in fingers(&a).iter().zip(fingers(&b)) {
            for (sa, sb) in fa["audit"]["segments"]
                .as_array()
                .unwrap()
                .iter()
                .zip(fb["audit"]["segments"].as_array().unwrap())
            {
                assert!((num(sa) - num(sb)).abs() < 1e-6);
            }
        }
    }
}

/// The CSV's rows: node name and the nine numbers.
fn csv_rows(bytes: &[u8]) -> Vec<(String, [f64; 9])> {
    let mut r = csv::Reader::from_reader(bytes);
    assert_eq!(
        r.headers().unwrap().iter().collect::<Vec<_>>(),
        [
            "node",
            "old_x_m",
            "old_y_m",
            "old_z_m",
            "new_x_m",
            "new_y_m",
            "new_z_m",
            "new_local_x",
            "new_local_y",
            "new_local_z"
        ]
    );
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            let v: Vec<f64> = (1..10).map(|k| rec[k].parse().unwrap()).collect();
            (rec[0].to_string(), v.try_into().unwrap())
        })
        .collect()
}

#[test]
fn moves_applied_to_the_fbx_with_the_loader_land_where_the_fix_puts_them() {
    let Some(wd) = with_gloves() else { return };
    for (name, _) in GLOVES {
        // One moves.csv for each glove in turn: --force replaces it.
        // The MCPs pinned: the middle finger's explanation then moves its PIP
        // (without the pin it names the MCP, which a plain fix holds).
        audit(
            &wd,
            &[name, "--moves", "moves.csv", "--force", "--hold", "mcp"],
        )
        .ok()
        .stderr_has("nodes to move")
        .stderr_has("Lcl Translation");
        let rows = csv_rows(&wd.read("moves.csv"));
        assert!(!rows.is_empty(), "{name}: the fix moves nothing");
        // Apply the CSV's Lcl Translations to the file's nodes with ufbx,
        // converting to metres and +Y up as the reader does, and evaluate.
        let bytes = wd.read(name);
        let opts = || ufbx::LoadOpts {
            target_axes: ufbx::CoordinateAxes {
                right: ufbx::CoordinateAxis::PositiveX,
                up: ufbx::CoordinateAxis::PositiveY,
                front: ufbx::CoordinateAxis::PositiveZ,
            },
            target_unit_meters: 1.0,
            ..Default::default()
        };
        let scene = ufbx::load_memory(&bytes, opts()).unwrap();
        let id = |n: &str| {
            scene
                .nodes
                .iter()
                .find(|nd| nd.element.name == n)
                .map(|nd| nd.element.element_id)
                .expect(n)
        };
        let overrides: Vec<ufbx::PropOverrideDesc> = rows
            .iter()
            .map(|(n, v)| ufbx::PropOverrideDesc {
                element_id: id(n),
                prop_name: "Lcl Translation".into(),
                value: ufbx::Vec4 {
                    x: v[6],
                    y: v[7],
                    z: v[8],
                    w: 0.0,
                },
                ..Default::default()
            })
            .collect();
        let anim = ufbx::create_anim(
            &scene,
            ufbx::AnimOpts {
                prop_overrides: ufbx::ListOpt::Ref(&overrides),
                ..Default::default()
            },
        )
        .unwrap();
        let moved =
            ufbx::evaluate_scene(&scene, &anim, 0.0, ufbx::EvaluateOpts::default()).unwrap();
        let world = |n: &str| {
            let nd = moved.nodes.iter().find(|nd| nd.element.name == n).expect(n);
            let m = &nd.node_to_world;
            DVec3::new(m.m03, m.m13, m.m23)
        };
        for (n, v) in &rows {
            let csv_new = DVec3::new(v[3], v[4], v[5]);
            let got = world(n);
            assert!(
                got.distance(csv_new) < 1e-6,
                "{name} {n}: {got} vs {csv_new}"
            );
        }
        // The CSV's new positions are the fix's: the audit's suggested
        // points for the moved joints.
        let doc = audit(&wd, &[name, "--format", "json", "--hold", "mcp"])
            .ok()
            .json();
        let mut suggested = 0;
        for f in fingers(&doc) {
            for (rj, j) in f["joints"]
                .as_array()
                .unwrap()
                .iter()
                .zip(f["audit"]["joints"].as_array().unwrap())
            {
                if j["explains"] == true
                    && let Some((_, v)) = rows.iter().find(|(n, _)| rj["name"] == n.as_str())
                {
                    assert!(point(&j["suggested"]).distance(DVec3::new(v[3], v[4], v[5])) < 1e-6);
                    suggested += 1;
                }
            }
        }
        assert!(
            suggested > 0,
            "{name}: no moved joint checked against the audit"
        );
    }
}

#[test]
fn fix_on_an_fbx_is_refused_pointing_to_moves() {
    let Some(wd) = with_gloves() else { return };
    audit(&wd, &[GLOVES[0].0, "--fix", "out.glb"])
        .expect_code(2)
        .stderr_has("cannot write FBX")
        .stderr_has("--moves FILE.csv");
    assert!(!wd.path().join("out.glb").exists(), "nothing is written");
}

#[test]
fn moves_on_a_gltf_rig_list_the_fixed_copys_translations() {
    let Some(wd) = with_gloves() else { return };
    let reading = read_independently(&wd.read(GLOVES[0].0));
    wd.write(
        "glove.gltf",
        gltf_of(&reading, &wd.read(GLOVES[0].0)).to_string(),
    );
    audit(
        &wd,
        &[
            "glove.gltf",
            // At 80% the index PIP moves 1.6 mm (at 95% its 0.9 mm move is
            // under the tolerance): a move to list.
            "--confidence",
            "0.8",
            "--moves",
            "m.csv",
            "--fix",
            "fixed.gltf",
        ],
    )
    .ok();
    let rows = csv_rows(&wd.read("m.csv"));
    assert!(!rows.is_empty());
    let fixed: Value = serde_json::from_slice(&wd.read("fixed.gltf")).unwrap();
    for (n, v) in rows {
        let node = fixed["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["name"] == n.as_str())
            .unwrap();
        let t = point(&node["translation"]);
        assert!(t.distance(DVec3::new(v[6], v[7], v[8])) < 1e-9, "{n}");
    }
}

/// The JSON chunk of a GLB file (read here, not with phalanx's reader).
fn glb_json(bytes: &[u8]) -> Value {
    assert_eq!(&bytes[..4], b"glTF");
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + len]).unwrap()
}

/// Each node's local translation, by name, from a glTF's JSON (`translation`,
/// or a `matrix`'s last column; zero when it has neither).
fn translations(doc: &Value) -> Vec<(String, DVec3)> {
    doc["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| {
            let t = match (&n["translation"], &n["matrix"]) {
                (t, _) if t.is_array() => point(t),
                (_, m) if m.is_array() => DVec3::new(num(&m[12]), num(&m[13]), num(&m[14])),
                _ => DVec3::ZERO,
            };
            (n["name"].as_str().unwrap_or("").to_string(), t)
        })
        .collect()
}

#[test]
fn moves_follow_the_fix_as_written_for_every_fix_option() {
    // However the fix chooses its joints (by default, only those outside,
    // MCPs from the atlas), --moves lists exactly the nodes whose
    // translation the written --fix copy changes, with that translation;
    // and --moves alone lists the same as --moves beside --fix.
    let wd = Workdir::with_paper_data();
    // The atlas's tips are at the bone and the rig's at the skin: the measured
    // soft tissue (data/literature/, read from the working directory) bridges
    // them, so the MCPs from the atlas are judged and --fix-mcp atlas moves them.
    for file in [
        "data/literature/buryanov-kotiuk-2010.csv",
        "data/literature/buryanov-kotiuk-2010.cohort.csv",
    ] {
        wd.write(file, std::fs::read(manifest_dir().join(file)).unwrap());
    }
    wd.write(
        "hand.glb",
        std::fs::read(manifest_dir().join("docs/examples/hand.glb")).unwrap(),
    );
    let atlas = manifest_dir().join("data/atlas/measurements.csv");
    let atlas = atlas.to_str().unwrap();
    let original = translations(&glb_json(&wd.read("hand.glb")));
    let mut listed = Vec::new();
    for opts in [vec![], vec!["--only-outside"], vec!["--fix-mcp", "atlas"]] {
        // The example hand's skin (a vertex or two per bone) is too coarse to
        // carry a bend, so with the weights carried every move is held: the
        // weights stay as painted here, as this test is about the moves.
        let mut args = vec!["hand.glb", "--metacarpals", atlas, crate::audit::KEEP];
        args.extend(&opts);
        let mut both = args.clone();
        // One set of outputs for each option in turn: --force replaces them.
        both.extend(["--fix", "fixed.glb", "--moves", "both.csv", "--force"]);
        audit(&wd, &both).ok();
        let mut alone = args.clone();
        alone.extend(["--moves", "alone.csv", "--force"]);
        audit(&wd, &alone).ok().stderr_has("nodes to move");
        assert_eq!(wd.read("both.csv"), wd.read("alone.csv"), "{opts:?}");
        let fixed = translations(&glb_json(&wd.read("fixed.glb")));
        let changed: Vec<(String, DVec3)> = original
            .iter()
            .zip(&fixed)
            .filter(|((_, a), (_, b))| a.distance(*b) > 1e-9)
            .map(|(_, b)| b.clone())
            .collect();
        let rows = csv_rows(&wd.read("both.csv"));
        assert!(!rows.is_empty(), "{opts:?}: the fix moves nothing");
        assert_eq!(
            rows.iter().map(|r| &r.0).collect::<Vec<_>>(),
            changed.iter().map(|c| &c.0).collect::<Vec<_>>(),
            "{opts:?}"
        );
        for ((n, v), (_, t)) in rows.iter().zip(&changed) {
            assert!(
                t.distance(DVec3::new(v[6], v[7], v[8])) < 1e-9,
                "{opts:?} {n}"
            );
        }
        listed.push(rows.into_iter().map(|r| r.0).collect::<Vec<_>>());
    }
    // The options matter here (--fix-mcp atlas moves MCPs), so a list that
    // ignored them would fail above.
    assert_ne!(listed[0], listed[2]);
}

#[test]
fn an_fbx_audit_says_what_the_file_was_once() {
    let Some(wd) = with_gloves() else { return };
    let run = audit(&wd, &[GLOVES[0].0]);
    let text = run.ok().stdout.replace("\n  ", " ");
    assert!(
        text.contains("read from binary FBX 7500 with ufbx: its units (metres) and axes"),
        "{text}"
    );
    assert!(!text.contains("glTF units"), "{text}");
    assert_eq!(text.matches("FBX 7500").count(), 1, "{text}");
    let doc = audit(&wd, &[GLOVES[0].0, "--format", "json"]).ok().json();
    assert_eq!(doc["fbx"]["version"], 7500);
    assert_eq!(doc["fbx"]["encoding"], "binary");
    // SteamVR's UnitScaleFactor is 100 (centimetres per unit): metres.
    assert_eq!(doc["fbx"]["unit_m"], 1.0);
    assert_eq!(doc["units"], "m");
    // A glTF's header says glTF, and its document has no fbx.
    wd.write(
        "hand.glb",
        std::fs::read(manifest_dir().join("docs/examples/hand.glb")).unwrap(),
    );
    audit(&wd, &["hand.glb"])
        .ok()
        .stdout_has("glTF units are metres");
    let doc = audit(&wd, &["hand.glb", "--format", "json"]).ok().json();
    assert!(doc.get("fbx").is_none());
}

#[test]
fn deform_on_a_glove_renders_and_measures() {
    let Some(wd) = with_gloves() else { return };
    let run = wd.run(&["deform", GLOVES[0].0, "--out", "deformed"]);
    run.ok();
    assert!(run.stdout.contains("index"), "{}", run.stdout);
    let pngs: Vec<_> = std::fs::read_dir(wd.path().join("deformed"))
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "png"))
        .collect();
    assert!(!pngs.is_empty(), "deform drew no picture");
}

#[test]
fn broken_fbx_files_get_a_clear_error_never_a_panic() {
    let Some(dir) = gloves() else { return };
    let wd = Workdir::with_paper_data();
    let glove = std::fs::read(dir.join(GLOVES[0].0)).unwrap();
    wd.write("truncated.fbx", &glove[..glove.len() / 3]);
    let mut corrupt = glove.clone();
    for b in corrupt[2000..40_000].iter_mut().step_by(7) {
        *b ^= 0x5a;
    }
    wd.write("corrupt.fbx", &corrupt);
    wd.write("notes.fbx", "These are my notes about the hand rig.\n");
    let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x01\0\0\0\x01\x08\x02\0\0\0\x90wS\xde";
    wd.write("picture.fbx", png);
    wd.write("empty.fbx", "");
    for (file, says) in [
        ("truncated.fbx", "cut short"),
        ("notes.fbx", "not an FBX file"),
        ("picture.fbx", "not an FBX file"),
        ("empty.fbx", "empty"),
    ] {
        audit(&wd, &[file])
            .expect_code(2)
            .stderr_has(file)
            .stderr_has(says);
    }
    // A corrupt file is refused or read; never a panic (checked by `run`).
    let code = audit(&wd, &["corrupt.fbx"]).code;
    assert!(matches!(code, Some(0 | 2)), "{code:?}");
    // An FBX named .glb is read as FBX (by its header).
    wd.write("glove.glb", &glove);
    audit(&wd, &["glove.glb"])
        .ok()
        .stdout_has("finger_index_0_r");
}

#[test]
fn a_maya_joint_n_hand_is_refused_naming_the_joints_and_pointing_to_map() {
    let wd = Workdir::with_paper_data();
    let nodes: Vec<Value> = (1..=21)
        .map(|k| {
            let mut n = json!({"name": format!("joint{k}"), "translation": [0.0, 0.02, 0.0]});
            if k < 21 {
                n["children"] = json!([k]);
            }
            n
        })
        .collect();
    let doc = json!({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes});
    wd.write("maya.gltf", doc.to_string());
    audit(&wd, &["maya.gltf"])
        .expect_code(2)
        .stderr_has("'joint1', 'joint2'")
        .stderr_has("and 15 more")
        .stderr_has("--map FILE");
}

/// A seeded mutation loop over the fuzz target's body (fuzz/fuzz_targets/fbx.rs)
/// for machines without cargo-fuzz: flipped bytes, cut tails and spliced
/// runs of the gloves, each read, recognised and audited; never a panic.
#[test]
#[ignore = "slow: 4,000 mutated gloves (run with --ignored)"]
fn mutated_gloves_never_panic() {
    use phalanx::analysis::{Settings, analyse};
    use phalanx::dataset::Dataset;
    use phalanx::rig::{AuditOptions, AuditedRig, Rig};
    let Some(dir) = gloves() else { return };
    let d = Dataset::from_bytes("measurements.csv", &paper_data()).unwrap();
    let a = analyse(
        &d,
        &Settings {
            resamples: 200,
            ..Settings::default()
        },
    );
    let seeds: Vec<Vec<u8>> = GLOVES
        .iter()
        .map(|(n, _)| std::fs::read(dir.join(n)).unwrap())
        .collect();
    // xorshift64*: the same mutations on every machine.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move |n: usize| {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_F491_4F6C_DD1D) % n.max(1) as u64) as usize
    };
    let (mut read, mut audited) = (0, 0);
    for k in 0..4000 {
        let mut b = seeds[k % 2].clone();
        match next(4) {
            0 => {
                for _ in 0..1 + next(16) {
                    let i = next(b.len());
                    b[i] ^= 1 << next(8);
                }
            }
            1 => b.truncate(next(b.len())),
            2 => {
                let (i, j, len) = (next(b.len()), next(b.len()), 1 + next(64));
                let run: Vec<u8> = b[j..(j + len).min(b.len())].to_vec();
                b.splice(i..i, run);
            }
            _ => {
                let i = next(b.len());
                let end = (i + 1 + next(8)).min(b.len());
                b[i..end].fill(0xff);
            }
        }
        let Ok(file) = phalanx::rig::fbx::read("mutant.fbx", &b) else {
            continue;
        };
        read += 1;
        let Ok(rig) = Rig::from_file(file, None) else {
            continue;
        };
        let audit = AuditedRig::with(
            "m",
            &rig.chains,
            &rig.notes,
            &a,
            &AuditOptions::default(),
            rig.weights.as_ref(),
        );
        audited += usize::from(!audit.fingers.is_empty());
    }
    eprintln!("mutated gloves: {read} of 4000 read, {audited} audited");
    assert!(read > 0 && audited > 0);
}

/// An ASCII FBX 7.4 file of two bones, `Hand` and its child `Finger`, in
/// metres (UnitScaleFactor 100 cm), with `Hand` at (`x`, 0, 0).
fn two_bones_fbx(x: &str) -> String {
    format!(
        "; FBX 7.4.0 project file\nFBXHeaderExtension:  {{\n\tFBXHeaderVersion: 1003\n\tFBXVersion: 7400\n}}\n\
         GlobalSettings:  {{\n\tVersion: 1000\n\tProperties70:  {{\n\t\tP: \"UnitScaleFactor\", \"double\", \"Number\", \"\",100\n\t}}\n}}\n\
         Objects:  {{\n\tModel: 100, \"Model::Hand\", \"LimbNode\" {{\n\t\tVersion: 232\n\t\tProperties70:  {{\n\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",{x},0,0\n\t\t}}\n\t}}\n\
         \tModel: 101, \"Model::Finger\", \"LimbNode\" {{\n\t\tVersion: 232\n\t\tProperties70:  {{\n\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",0,1,0\n\t\t}}\n\t}}\n}}\n\
         Connections:  {{\n\tC: \"OO\",100,0\n\tC: \"OO\",101,100\n}}\n"
    )
}

/// The regression test of a crash the fbx fuzz target found: a translation
/// finite in f64 (1e39 m) but beyond f32 (3.4e38), as the glTF document made
/// of the FBX file keeps it, read back as an infinite world matrix. It is
/// refused, naming the node; the same file at 1 m is read with finite matrices.
#[test]
fn an_fbx_transform_beyond_32_bit_floats_is_refused_naming_the_node() {
    let Err(e) = phalanx::rig::fbx::read("huge.fbx", two_bones_fbx("1e39").as_bytes()) else {
        panic!("a 1e39 m translation was read");
    };
    let text = e.to_string();
    assert!(
        text.contains("node 'Hand' has a transform too large to hold (beyond 32-bit floats"),
        "{text}"
    );
    let file = phalanx::rig::fbx::read("small.fbx", two_bones_fbx("1").as_bytes()).unwrap();
    assert!(file.world.iter().all(|m| m.is_finite()));
    let wd = Workdir::with_paper_data();
    wd.write("huge.fbx", two_bones_fbx("1e39"));
    audit(&wd, &["huge.fbx"])
        .expect_code(2)
        .stderr_has("huge.fbx: node 'Hand' has a transform too large to hold");
}
