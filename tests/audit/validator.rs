//! The Khronos glTF validator on the inputs and the fixed copies: the
//! fixtures the tests build have no error or warning, and a fix adds no issue
//! of any severity. The validator (npm `gltf-validator`, pinned in
//! tests/tools/package.json) is installed by the test with npm; without node
//! or npm, or when the install fails, the test is skipped with the reason.

use super::hand::{HandSpec, Naming, build, glb};
use crate::common::*;
use glam::{DMat4, DVec3};
use phalanx::rig::fix::Edit;
use phalanx::rig::{GltfFile, Rig, weights::SkinWeights};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// The tools folder with the validator installed, or why it cannot be.
pub(crate) fn validator() -> Result<std::path::PathBuf, String> {
    let tools = manifest_dir().join("tests/tools");
    for tool in ["node", "npm"] {
        let ok = Command::new(tool)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success());
        if !ok {
            return Err(format!("{tool} is not installed"));
        }
    }
    if !tools.join("node_modules/gltf-validator").is_dir() {
        let out = Command::new("npm")
            .args(["install", "--no-audit", "--no-fund"])
            .current_dir(&tools)
            .output()
            .map_err(|e| format!("npm install could not run ({e})"))?;
        if !out.status.success() {
            return Err(format!(
                "npm install failed: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
    }
    Ok(tools)
}

/// Issue counts by (code, severity) of each file, in order.
pub(crate) fn issues(
    tools: &std::path::Path,
    files: &[std::path::PathBuf],
) -> Vec<BTreeMap<(String, u64), usize>> {
    let out = Command::new("node")
        .arg(tools.join("validate.mjs"))
        .args(files)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| {
            let doc: Value = serde_json::from_str(l).unwrap();
            let mut count = BTreeMap::new();
            for i in doc["issues"].as_array().unwrap() {
                let key = (
                    i["code"].as_str().unwrap().to_string(),
                    i["severity"].as_u64().unwrap(),
                );
                *count.entry(key).or_default() += 1;
            }
            count
        })
        .collect()
}

#[test]
#[ignore = "slow: installs and runs the Khronos glTF validator with npm (run by .ci/run)"]
fn fixtures_are_valid_and_a_fix_adds_no_validator_issue() {
    let tools = match validator() {
        Ok(t) => t,
        Err(why) => {
            skip(format!("the Khronos glTF validator is unavailable: {why}"));
            return;
        }
    };
    let wd = Workdir::with_paper_data();
    let mut animated = HandSpec::new(Naming::Mixamo)
        .moved("index", 1, 1.0)
        .moved("middle", 0, 1.0)
        .moved("ring", 2, -0.4);
    animated.animate = true;
    animated.varying = vec![("index", 1)];
    animated.smooth = Some(vec![("index", 1, 1.5)]);
    let mut siblings = HandSpec::new(Naming::WebXr).moved("index", 1, 1.0);
    siblings.siblings = true;
    siblings.metacarpals = true;
    let mut rigify = HandSpec::new(Naming::Rigify).moved("ring", 1, -0.8);
    rigify.org_twins = true;
    // Both hands, node matrices, metacarpals, no smooth skin: the builder's
    // other branches.
    let mut plain = HandSpec::new(Naming::Unreal5).moved("index", 1, 1.0);
    plain.left_too = true;
    plain.matrices = true;
    plain.metacarpals = true;
    let mut cases: Vec<(String, Vec<u8>, Vec<&str>)> = vec![
        ("animated.glb".into(), build(&animated), vec![]),
        ("plain.glb".into(), build(&plain), vec![]),
        ("siblings.glb".into(), build(&siblings), vec![]),
        ("rigify.glb".into(), build(&rigify), vec![]),
    ];
    let webxr = manifest_dir().join("data/rigs/webxr-generic-hand/right.glb");
    if let Ok(bytes) = std::fs::read(&webxr) {
        cases.push(("webxr.glb".into(), bytes, vec!["--tip", "skin"]));
    }
    let mut files = Vec::new();
    for (name, bytes, extra) in &cases {
        wd.write(name, bytes);
        let fixed = format!("fixed-{name}");
        let mut args = vec!["audit", name.as_str(), "--fix", fixed.as_str()];
        args.extend(extra.iter().copied());
        // The fix holds joints that sit at their skin bends (and MCPs), so a
        // re-audit may still find fingers outside; what matters here is that
        // the file written is valid and the fixed file was audited again. A fix
        // that moves nothing writes nothing: the rig as given stands for it.
        let fixed = written_or(&wd, &args, &fixed, name);
        // And a second fix, which must add nothing either.
        let again = format!("again-{name}");
        let mut args = vec!["audit", fixed.as_str(), "--fix", again.as_str()];
        args.extend(extra.iter().copied());
        let again = written_or(&wd, &args, &again, &fixed);
        files.extend([name.clone(), fixed, again].map(|f| wd.path().join(f)));
    }
    let reports = issues(&tools, &files);
    assert_eq!(reports.len(), files.len());
    for (k, (name, ..)) in cases.iter().enumerate() {
        let input = &reports[3 * k];
        // The fixtures this suite builds are valid glTF themselves: no error
        // (severity 0) or warning (1); infos and hints are allowed. The WebXR
        // hand is a vendor's file and is only held to the fix adding nothing.
        if name != "webxr.glb" {
            let bad: Vec<_> = input.keys().filter(|(_, sev)| *sev <= 1).collect();
            assert!(
                bad.is_empty(),
                "{name}: the fixture has {bad:?}; all {input:?}"
            );
        }
        for out in &reports[3 * k + 1..3 * k + 3] {
            for (key, &n) in out {
                let had = input.get(key).copied().unwrap_or(0);
                assert!(
                    n <= had,
                    "{name}: the fix adds {key:?} ({had} -> {n}); input {input:?}, fixed {out:?}"
                );
            }
        }
        eprintln!("{name}: input {input:?}; fixed {:?}", reports[3 * k + 1]);
    }
    // The files the editor writes for a rig it makes (phalanx::rig::fix::Edit)
    // add no issue either.
    let edited = edited(&wd);
    let files: Vec<_> = edited
        .iter()
        .flat_map(|(a, b)| [wd.path().join(a), wd.path().join(b)])
        .collect();
    let reports = issues(&tools, &files);
    for (k, (name, _)) in edited.iter().enumerate() {
        let (input, out) = (&reports[2 * k], &reports[2 * k + 1]);
        let bad: Vec<_> = input.keys().filter(|(_, sev)| *sev <= 1).collect();
        assert!(bad.is_empty(), "{name}: the input has {bad:?}");
        for (key, &n) in out {
            let had = input.get(key).copied().unwrap_or(0);
            assert!(
                n <= had,
                "{name}: the editor adds {key:?} ({had} -> {n}); input {input:?}, output {out:?}"
            );
        }
        eprintln!("{name}: input {input:?}; edited {out:?}");
    }
}

/// Finishes `edit` as a GLB written to `name` in `wd`, and reads it back
/// (its new nodes found by their names).
fn write(wd: &Workdir, name: &str, edit: Edit<'_>, names: &[&str]) -> GltfFile {
    let (bytes, _) = edit.finish(true).unwrap();
    wd.write(name, &bytes);
    let file = phalanx::rig::open(&wd.path().join(name)).unwrap();
    let found = file.node_names();
    for n in names {
        assert!(found.iter().any(|f| f == n), "{name}: no node {n}");
    }
    file
}

/// The rest positions of every skinned vertex of a file.
fn rest(file: &GltfFile) -> Vec<DVec3> {
    SkinWeights::read(file, &file.buffer_data().unwrap())
        .primitives
        .iter()
        .flat_map(|p| p.rest.clone())
        .collect()
}

fn close(a: &[DVec3], b: &[DVec3]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert!(x.distance(*y) <= 1e-5, "{x} rests at {y}");
    }
}

/// A GLB's binary chunk, buffer views and accessors, as the files below build them.
#[derive(Default)]
struct Parts {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Parts {
    /// `bytes` as a view (with `target` when given) and an accessor of it; the accessor's index.
    fn add(&mut self, bytes: Vec<u8>, target: Option<u64>, mut accessor: Value) -> usize {
        let mut view =
            json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.bin.extend(bytes);
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(view);
        accessor["bufferView"] = json!(self.views.len() - 1);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A unit quad's positions and indices as a mesh.
    fn quad(&mut self) -> Value {
        let corners = [[0f32, 0., 0.], [0.1, 0., 0.], [0.1, 0.1, 0.], [0., 0.1, 0.]];
        let pos = self.add(
            corners.iter().flatten().flat_map(|x| x.to_le_bytes()).collect(),
            Some(34962),
            json!({"componentType": 5126, "count": 4, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [0.1, 0.1, 0.0]}),
        );
        let idx = self.add(
            [0u16, 1, 2, 0, 2, 3]
                .iter()
                .flat_map(|x| x.to_le_bytes())
                .collect(),
            Some(34963),
            json!({"componentType": 5123, "count": 6, "type": "SCALAR"}),
        );
        json!({"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]})
    }

    /// The GLB of `doc` with these parts.
    fn glb(self, mut doc: Value) -> Vec<u8> {
        doc["asset"] = json!({"version": "2.0"});
        doc["accessors"] = json!(self.accessors);
        doc["bufferViews"] = json!(self.views);
        doc["buffers"] = json!([{"byteLength": self.bin.len()}]);
        glb(&doc, self.bin)
    }
}

/// Three files the editor writes, each beside its input (names in `wd`): a
/// built hand with a joint added inside a finger, its weights shared with
/// it and another joint moved; two unskinned quads under transformed nodes
/// bound to a new skin of new nodes; and a quad whose byte joints widen to
/// shorts for a skin of 300 joints. Each keeps its rest shape.
fn edited(wd: &Workdir) -> Vec<(String, String)> {
    let mut out = Vec::new();

    let mut spec = HandSpec::new(Naming::Mixamo);
    spec.animate = true;
    wd.write("to-edit.glb", build(&spec));
    let f = Rig::load(&wd.path().join("to-edit.glb"), None)
        .unwrap()
        .file;
    let node = |name: &str| f.node_names().iter().position(|n| n == name).unwrap();
    let (pip, dip, tip) = (
        node("mixamorig:RightHandIndex2"),
        node("mixamorig:RightHandIndex3"),
        node("mixamorig:RightHandIndex4"),
    );
    let at = |n: usize| f.world[n].w_axis.truncate();
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let mid = edit
        .add_node("RightHandIndex3_mid", Some(dip), (at(dip) + at(tip)) / 2.0)
        .unwrap();
    edit.add_joints(0, &[mid]).unwrap();
    let weights = SkinWeights::read(&f, &f.buffer_data().unwrap());
    for p in &weights.primitives {
        let split: Vec<Vec<(usize, f64)>> = p
            .influences
            .iter()
            .map(|infl| {
                infl.iter()
                    .flat_map(|&(n, w)| {
                        if n == dip {
                            vec![(n, w / 2.0), (mid, w / 2.0)]
                        } else {
                            vec![(n, w)]
                        }
                    })
                    .collect()
            })
            .collect();
        edit.set_weights(p.mesh, p.primitive, &split).unwrap();
    }
    edit.move_nodes(&[(pip, at(pip) + DVec3::new(0.0, 0.002, 0.0))])
        .unwrap();
    let g = write(wd, "edited-joints.glb", edit, &["RightHandIndex3_mid"]);
    close(&rest(&g), &rest(&f));
    let rig = Rig::load(&wd.path().join("edited-joints.glb"), None).unwrap();
    assert_eq!(rig.chains.len(), 5);
    out.push(("to-edit.glb".to_string(), "edited-joints.glb".to_string()));

    let mut parts = Parts::default();
    let meshes = [parts.quad(), parts.quad(), parts.quad()];
    let turned = [0.0, 0.258_819_045_102_520_74, 0.0, 0.965_925_826_289_068_3];
    wd.write(
        "unskinned.glb",
        parts.glb(json!({
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [
                {"name": "body", "mesh": 0, "rotation": turned, "scale": [2.0, 2.0, 2.0],
                 "translation": [0.1, 0.2, 0.3], "children": [1, 2]},
                {"name": "quad", "mesh": 1, "translation": [0.0, 0.05, 0.0]},
                {"name": "shell", "mesh": 2, "translation": [0.1, 0.0, 0.0], "scale": [1.0, 3.0, 1.0], "children": [3]},
                {"name": "shell tip", "mesh": 0, "translation": [0.0, 0.1, 0.0]}
            ],
            "meshes": meshes
        })),
    );
    let f = phalanx::rig::open(&wd.path().join("unskinned.glb")).unwrap();
    let drawn = |n: usize| -> Vec<DVec3> {
        [[0., 0., 0.], [0.1, 0., 0.], [0.1, 0.1, 0.], [0., 0.1, 0.]]
            .iter()
            .map(|p| f.world[n].transform_point3(DVec3::from_array(*p)))
            .collect()
    };
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    let hand = edit
        .add_node("hand", None, DVec3::new(0.1, 0.2, 0.3))
        .unwrap();
    let finger = edit
        .add_node("finger", Some(hand), DVec3::new(0.2, 0.3, 0.3))
        .unwrap();
    let weights = [
        vec![(hand, 1.0)],
        vec![(hand, 0.5), (finger, 0.5)],
        vec![(finger, 1.0)],
        vec![(finger, 0.25), (hand, 0.75)],
    ];
    for (mesh_node, mesh) in [(1, 1), (2, 2)] {
        edit.new_skin(mesh_node, &[hand, finger], Some(hand))
            .unwrap();
        edit.set_weights(mesh, 0, &weights).unwrap();
    }
    let g = write(
        wd,
        "edited-skin.glb",
        edit,
        &["hand", "finger", "shell (skinned)"],
    );
    let mut want = drawn(1);
    want.extend(drawn(2));
    close(&rest(&g), &want);
    out.push(("unskinned.glb".to_string(), "edited-skin.glb".to_string()));

    let mut parts = Parts::default();
    let mut mesh = parts.quad();
    let mut nodes = vec![json!({"name": "j0", "children": (1..300).collect::<Vec<_>>()})];
    let mut ibm: Vec<u8> = DMat4::IDENTITY
        .as_mat4()
        .to_cols_array()
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    for k in 1..300 {
        let t = DVec3::new(0.001 * k as f64, 0.0, 0.0);
        nodes.push(json!({"name": format!("j{k}"), "translation": t.to_array()}));
        let b = DMat4::from_translation(-t).as_mat4().to_cols_array();
        ibm.extend(b.iter().flat_map(|x| x.to_le_bytes()));
    }
    let ibm = parts.add(
        ibm,
        None,
        json!({"componentType": 5126, "count": 300, "type": "MAT4"}),
    );
    for (set, (j, w)) in [([1u8, 2, 0, 0], [200u8, 55, 0, 0]), ([0; 4], [0; 4])]
        .into_iter()
        .enumerate()
    {
        let js = parts.add(
            j.repeat(4),
            Some(34962),
            json!({"componentType": 5121, "count": 4, "type": "VEC4"}),
        );
        let ws = parts.add(
            w.repeat(4),
            Some(34962),
            json!({"componentType": 5121, "normalized": true, "count": 4, "type": "VEC4"}),
        );
        mesh["primitives"][0]["attributes"][format!("JOINTS_{set}")] = json!(js);
        mesh["primitives"][0]["attributes"][format!("WEIGHTS_{set}")] = json!(ws);
    }
    nodes.push(json!({"name": "skinned", "mesh": 0, "skin": 0}));
    wd.write(
        "bytes.glb",
        parts.glb(json!({
            "scene": 0,
            "scenes": [{"nodes": [0, 300]}],
            "nodes": nodes,
            "meshes": [mesh],
            "skins": [{"joints": (0..300).collect::<Vec<_>>(), "inverseBindMatrices": ibm, "skeleton": 0}]
        })),
    );
    let f = phalanx::rig::open(&wd.path().join("bytes.glb")).unwrap();
    let mut edit = Edit::new(&f, Path::new(".")).unwrap();
    edit.set_weights(
        0,
        0,
        &[
            vec![(299, 0.6), (298, 0.4)],
            vec![(1, 1.0)],
            vec![(150, 0.5), (2, 0.5)],
            vec![(299, 1.0)],
        ],
    )
    .unwrap();
    let g = write(wd, "edited-bytes.glb", edit, &["j299"]);
    let attrs = &g.json["meshes"][0]["primitives"][0]["attributes"];
    let joints = attrs["JOINTS_0"].as_u64().unwrap() as usize;
    assert_eq!(g.json["accessors"][joints]["componentType"], json!(5123));
    close(&rest(&g), &rest(&f));
    out.push(("bytes.glb".to_string(), "edited-bytes.glb".to_string()));
    out
}

/// Runs a `--fix` into `out`: `out` when the fix wrote it (the fixed file audited
/// again), else `given`, the rig the fix left as it stands, when the fix says it
/// moved nothing and wrote no file.
fn written_or(wd: &Workdir, args: &[&str], out: &str, given: &str) -> String {
    let run = wd.run(args);
    run.ok();
    if run.stderr.contains("nothing to fix: no joint moves") {
        assert!(
            !wd.path().join(out).exists(),
            "{args:?}: says nothing moved but wrote {out}"
        );
        given.to_string()
    } else {
        run.stderr_has("re-audited, ");
        out.to_string()
    }
}
