//! `phalanx deform`, the real binary in temporary directories: synthetic tube
//! hands built here (with the library's synthetic module, whose joints and
//! weights are known exactly) and the WebXR generic hands when present.

use crate::common;

use common::*;
use phalanx::rig::deform::synthetic::HandSpec;
use phalanx::rig::naming::Side;
use serde_json::Value;
use std::path::PathBuf;

/// The measures of `finger` `joint` of the first hand of `rig` ("rig" or "against").
fn joint<'a>(doc: &'a Value, rig: &str, finger: &str, joint: &str) -> &'a Value {
    doc[rig]["hands"][0]["measures"]["fingers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["finger"] == finger)
        .unwrap_or_else(|| panic!("no {finger} in {rig}"))["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["joint"] == joint)
        .unwrap_or_else(|| panic!("no {finger} {joint}"))
}

/// The verdict of `finger` `joint` of the first hand.
fn verdict<'a>(doc: &'a Value, finger: &str, joint: &str) -> &'a Value {
    doc["verdicts"][0]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["finger"] == finger && j["joint"] == joint)
        .unwrap_or_else(|| panic!("no verdict for {finger} {joint}"))
}

fn measure_call<'a>(v: &'a Value, measure: &str) -> &'a Value {
    v["measures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["measure"] == measure)
        .unwrap()
}

/// A work directory holding the default tube hand as `right.glb`.
fn default_hand() -> Workdir {
    let wd = Workdir::new();
    write_hand(&wd, "right.glb", &HandSpec::default());
    wd
}

#[test]
fn the_table_fits_and_the_closed_forms_hold_for_lbs_and_dqs() {
    let wd = default_hand();
    let run = wd.run(&["deform", "right.glb"]);
    run.ok().stdout_has("right hand").stdout_has("| index ");
    for line in run.stdout.lines() {
        assert!(line.chars().count() <= 100, "too wide: {line}");
    }
    // The fist bends every PIP 90 degrees. A tube's ring weighted 1/2 to each
    // bone keeps cos(theta/2) of its area under LBS (by hand: 1 - cos 45 deg =
    // 0.2929 lost) and all of it under DQS, which turns each ring rigidly.
    let lbs = wd
        .run(&["deform", "right.glb", "--format", "json"])
        .ok()
        .json();
    let dqs = wd
        .run(&[
            "deform",
            "right.glb",
            "--skinning",
            "dqs",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert_eq!(lbs["schema_version"], 6);
    assert_eq!(lbs["rig"]["hands"][0]["side"], "right");
    for finger in ["index", "middle", "ring", "little"] {
        let l = num(&joint(&lbs, "rig", finger, "PIP")["volume_loss"]);
        let d = num(&joint(&dqs, "rig", finger, "PIP")["volume_loss"]);
        assert_close(l, 1.0 - 45f64.to_radians().cos(), 0.02, finger);
        assert!(d.abs() < 0.02 && d < l, "{finger}: DQS {d}, LBS {l}");
    }
}

#[test]
fn dqs_loses_less_volume_than_lbs_at_90_degrees() {
    let wd = default_hand();
    let at = |method: &str| {
        let doc = wd
            .run(&[
                "deform",
                "right.glb",
                "--angles",
                "0,90,0",
                "--skinning",
                method,
                "--format",
                "json",
            ])
            .ok()
            .json();
        num(&joint(&doc, "rig", "middle", "PIP")["volume_loss"])
    };
    let (lbs, dqs) = (at("lbs"), at("dqs"));
    assert!(dqs < lbs - 0.2, "DQS {dqs}, LBS {lbs}");
}

#[test]
fn weights_centred_on_the_joint_beat_weights_5mm_off() {
    // A: every joint's weights blend 5 mm distal of it; B: centred on it.
    let wd = Workdir::new();
    write_hand(
        &wd,
        "off-right.glb",
        &HandSpec {
            weight_shift: 0.005,
            ..HandSpec::default()
        },
    );
    write_hand(&wd, "centred-right.glb", &HandSpec::default());
    let doc = wd
        .run(&[
            "deform",
            "off-right.glb",
            "--against",
            "centred-right.glb",
            "--angles",
            "0,90,0",
            "--format",
            "json",
        ])
        .ok()
        .json();
    let v = verdict(&doc, "index", "PIP");
    // Less strain and the fold at the joint: B wins on both, by how much said.
    assert_eq!(measure_call(v, "strain_p95")["better"], "b", "{v}");
    let crease = measure_call(v, "crease_offset");
    assert_eq!(crease["better"], "b", "{v}");
    // The fold sits where the weights blend: 5 mm distal for A (by construction), at the joint for B.
    assert_close(num(&crease["a"]), 0.005, 0.001, "A's crease");
    assert_close(num(&crease["b"]), 0.0, 1e-6, "B's crease");
    // The truth, not the wish: under LBS the section collapses by the same
    // 1 - cos 45 deg wherever the blend sits, so volume loss calls them the same.
    assert_eq!(measure_call(v, "volume_loss")["better"], "same", "{v}");
    // Nor does the joint 5 mm off lose on every count: its palm-side skin folds
    // over a wider band, and fewer triangle pairs pass through each other at 90
    // degrees (59 against 71 on the index here). So the joint is mixed, and the
    // disagreement is named rather than averaged away.
    assert_eq!(measure_call(v, "self_intersections")["better"], "a", "{v}");
    assert_eq!(v["overall"], "mixed");
    let d = v["disagreement"].as_str().unwrap();
    assert!(
        d.contains("A is better by self-intersections") && d.contains("B is better by strain p95"),
        "{d}"
    );
    // The table says so too.
    let table = wd.run(&[
        "deform",
        "off-right.glb",
        "--against",
        "centred-right.glb",
        "--angles",
        "0,90,0",
    ]);
    table
        .ok()
        .stdout_has("index PIP: mixed; A better by self-intersections")
        .stdout_has("Verdict: B deforms better at");
}

#[test]
fn a_fold_onto_itself_crosses_the_skin() {
    let wd = default_hand();
    let folded = wd
        .run(&[
            "deform",
            "right.glb",
            "--angles",
            "0,170,0",
            "--format",
            "json",
        ])
        .ok()
        .json();
    let straight = wd
        .run(&[
            "deform",
            "right.glb",
            "--angles",
            "0,0,0",
            "--format",
            "json",
        ])
        .ok()
        .json();
    for finger in ["index", "middle", "ring", "little"] {
        assert!(
            joint(&folded, "rig", finger, "PIP")["self_intersections"]
                .as_u64()
                .unwrap()
                > 0,
            "{finger}"
        );
        assert_eq!(
            joint(&straight, "rig", finger, "PIP")["self_intersections"],
            0
        );
    }
}

#[test]
fn a_left_hand_deforms_as_the_mirror_image_of_the_right() {
    let wd = default_hand();
    write_hand(
        &wd,
        "left.glb",
        &HandSpec {
            side: Side::Left,
            ..HandSpec::default()
        },
    );
    let r = wd
        .run(&["deform", "right.glb", "--out", "r", "--format", "json"])
        .ok()
        .json();
    let l = wd
        .run(&["deform", "left.glb", "--out", "l", "--format", "json"])
        .ok()
        .json();
    assert_eq!(l["rig"]["hands"][0]["side"], "left");
    for finger in ["thumb", "index", "little"] {
        for j in ["MCP", "PIP", "DIP", "IP"] {
            if finger == "thumb" && (j == "PIP" || j == "DIP") || finger != "thumb" && j == "IP" {
                continue;
            }
            let (a, b) = (joint(&r, "rig", finger, j), joint(&l, "rig", finger, j));
            assert_close(num(&a["volume_loss"]), num(&b["volume_loss"]), 1e-4, finger);
            assert_eq!(a["self_intersections"], b["self_intersections"]);
        }
    }
    // Drawn mirrored: from above, each tip is as far left of the panel's
    // middle (x = 210) in the left hand as right of it in the right hand.
    let tips = |doc: &Value| -> Vec<(String, f64)> {
        let p = doc["renders"][0]["panels"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["view"] == "above")
            .unwrap();
        p["tips"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| (t["finger"].as_str().unwrap().to_string(), num(&t["x"])))
            .collect()
    };
    for ((fr, xr), (fl, xl)) in tips(&r).iter().zip(&tips(&l)) {
        assert_eq!(fr, fl);
        assert!(((xr - 210.0) + (xl - 210.0)).abs() < 0.5, "{fr}: {xr} {xl}");
        assert!((xr - 210.0).abs() > 5.0 || fr == "middle", "{fr}: {xr}");
    }
}

/// The pixel (r, g, b) at (x, y).
fn pixel(img: &tiny_skia::Pixmap, x: f64, y: f64) -> [u8; 3] {
    let p = img
        .pixel(x.round() as u32, y.round() as u32)
        .expect("inside the image");
    [p.red(), p.green(), p.blue()]
}

#[test]
fn the_figure_draws_the_mesh_where_it_projects() {
    let wd = default_hand();
    let doc = wd
        .run(&[
            "deform",
            "right.glb",
            "--pose",
            "point",
            "--out",
            "renders",
            "--format",
            "json",
        ])
        .ok()
        .json();
    let render = &doc["renders"][0];
    assert_eq!(render["file"], "deform-right.png");
    let img = tiny_skia::Pixmap::decode_png(&wd.read("renders/deform-right.png")).unwrap();
    assert_eq!(u64::from(img.width()), render["width"].as_u64().unwrap());
    // Not blank, not constant: background between 20% and 95%, many colours.
    let white = img
        .pixels()
        .iter()
        .filter(|p| p.red() == 255 && p.green() == 255 && p.blue() == 255)
        .count();
    let share = white as f64 / img.pixels().len() as f64;
    assert!((0.2..0.95).contains(&share), "{share}");
    let colours: std::collections::BTreeSet<[u8; 3]> = img
        .pixels()
        .iter()
        .map(|p| [p.red(), p.green(), p.blue()])
        .collect();
    assert!(colours.len() > 20, "{} colours", colours.len());
    // The pointing index finger is straight; from above it points up the image.
    // Its tip is drawn where its projection says: the pixel just inside is the
    // mesh, and walking up the column from there the mesh ends within 2 pixels
    // (the tip is the end of the tube), then white.
    let above = render["panels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["view"] == "above" && p["rig"] == "a")
        .unwrap();
    let tip = above["tips"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["finger"] == "index")
        .unwrap();
    let (x, y) = (num(&tip["x"]), num(&tip["y"]));
    assert_ne!(
        pixel(&img, x, y + 2.0),
        [255, 255, 255],
        "no mesh at the index tip ({x}, {y})"
    );
    let mut top = y + 2.0;
    while top > 0.0 && pixel(&img, x, top - 1.0) != [255, 255, 255] {
        top -= 1.0;
    }
    assert!(
        (top - y).abs() <= 2.0,
        "the mesh ends at y = {top}, the tip projects to {y}"
    );
    // An unbent finger does not strain: its tip is drawn in the ramp's grey (shaded).
    let [r, g, b] = pixel(&img, x, y + 3.0);
    assert!(
        b >= r && b >= g,
        "the straight tip is not grey-blue: {r} {g} {b}"
    );
}

#[test]
fn fix_compares_with_what_audit_fix_writes_without_writing_it() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    write_hand(&wd, "right.glb", &HandSpec::default());
    let before: Vec<_> = std::fs::read_dir(wd.path())
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    let fix = wd
        .run(&["deform", "right.glb", "--fix", "--format", "json"])
        .ok()
        .json();
    let after: Vec<_> = std::fs::read_dir(wd.path())
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert_eq!(before, after, "--fix wrote a file");
    assert!(
        fix["against"]["label"]
            .as_str()
            .unwrap()
            .contains("audit --fix")
    );
    // The built hand's weight bands are centred on its joints: with its
    // weights left as painted (--keep-weights) every joint the X-rays would
    // move sits at its skin bend and the fix holds it (the MCPs as every MCP
    // is without --fix-mcp atlas), so nothing moves, and the audit says why
    // for each; with the weights carried (the default) the index PIP moves,
    // its weights with it.
    let kept = wd
        .run(&[
            "deform",
            "right.glb",
            "--fix",
            "--keep-weights",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert_eq!(kept["moved"], serde_json::json!([]), "{}", kept["moved"]);
    let audit = wd
        .run(&["audit", "right.glb", "--keep-weights", "--format", "json"])
        .ok()
        .json();
    let mut held = 0;
    for f in audit["rig"]["fingers"].as_array().unwrap() {
        for j in f["audit"]["joints"].as_array().unwrap() {
            if j["explains"] == true {
                assert!(j["held"]["words"].is_string(), "{j}");
                held += 1;
            }
        }
    }
    assert!(
        held > 0,
        "the X-rays move no joint of the built hand: {audit}"
    );
    let moved: Vec<&str> = fix["moved"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["node"].as_str().unwrap())
        .collect();
    assert_eq!(
        moved,
        ["index-finger-phalanx-intermediate"],
        "{}",
        fix["moved"]
    );
    // The same as deforming the file audit --fix writes.
    wd.run(&[
        "audit",
        "--explain",
        "right.glb",
        "--fix",
        "fixed-right.glb",
    ])
    .ok();
    let against = wd
        .run(&[
            "deform",
            "right.glb",
            "--against",
            "fixed-right.glb",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert_eq!(fix["against"]["hands"], against["against"]["hands"]);
    assert_eq!(fix["verdicts"], against["verdicts"]);
    wd.run(&["deform", "right.glb", "--fix"])
        .ok()
        .stdout_has("B: right.glb (as audit --fix would write it)");
}

#[test]
fn bad_input_is_refused_naming_the_file_and_nothing_is_written() {
    let wd = default_hand();
    wd.write("junk.glb", b"glTF not really");
    // A skeleton without a skin.
    wd.write(
        "bare-right.gltf",
        r#"{"asset":{"version":"2.0"},"nodes":[
            {"name":"wrist","children":[1,4,7,10,13]},
            {"name":"thumb-phalanx-proximal","translation":[-0.03,0.04,0],"children":[2]},{"name":"thumb-phalanx-distal","translation":[0,0.03,0],"children":[3]},{"name":"thumb-tip","translation":[0,0.03,0]},
            {"name":"index-finger-phalanx-proximal","translation":[-0.02,0.09,0],"children":[5]},{"name":"index-finger-phalanx-intermediate","translation":[0,0.04,0],"children":[6]},{"name":"index-finger-phalanx-distal","translation":[0,0.025,0]},
            {"name":"middle-finger-phalanx-proximal","translation":[0,0.09,0],"children":[8]},{"name":"middle-finger-phalanx-intermediate","translation":[0,0.045,0],"children":[9]},{"name":"middle-finger-phalanx-distal","translation":[0,0.028,0]},
            {"name":"ring-finger-phalanx-proximal","translation":[0.015,0.088,0],"children":[11]},{"name":"ring-finger-phalanx-intermediate","translation":[0,0.042,0],"children":[12]},{"name":"ring-finger-phalanx-distal","translation":[0,0.027,0]},
            {"name":"pinky-finger-phalanx-proximal","translation":[0.03,0.08,0],"children":[14]},{"name":"pinky-finger-phalanx-intermediate","translation":[0,0.033,0],"children":[15]},{"name":"pinky-finger-phalanx-distal","translation":[0,0.02,0]}
        ],"scenes":[{"nodes":[0]}],"scene":0}"#,
    );
    for (args, words) in [
        (
            &["deform", "missing.glb", "--out", "out"][..],
            "missing.glb",
        ),
        (&["deform", "junk.glb", "--out", "out"], "junk.glb"),
        (&["deform", "bare-right.gltf", "--out", "out"], "no skin"),
        (
            &[
                "deform",
                "right.glb",
                "--against",
                "junk.glb",
                "--out",
                "out",
            ],
            "junk.glb",
        ),
        (
            &["deform", "right.glb", "--angles", "0,200,0", "--out", "out"],
            "from -30 to 180",
        ),
        (
            &["deform", "right.glb", "--angles", "NaN,0,0", "--out", "out"],
            "from -30 to 180",
        ),
        (
            &["deform", "right.glb", "--angles", "1,2", "--out", "out"],
            "from -30 to 180",
        ),
        (
            &["deform", "right.glb", "--pose", "wave", "--out", "out"],
            "wave",
        ),
        (
            &["deform", "right.glb", "--fix", "--against", "right.glb"],
            "cannot be used with",
        ),
        (
            &[
                "deform",
                "right.glb",
                "--fix",
                "--data",
                "none.csv",
                "--out",
                "out",
            ],
            "none.csv",
        ),
    ] {
        wd.run(args).data_error().stderr_has(words);
        assert!(!wd.path().join("out").exists(), "{args:?} wrote its output");
    }
    // A hand whose names carry no side, in a file whose name does not say either.
    std::fs::copy(wd.path().join("right.glb"), wd.path().join("hand.glb")).unwrap();
    wd.run(&["deform", "hand.glb"])
        .data_error()
        .stderr_has("--side");
    wd.run(&["deform", "hand.glb", "--side", "right"]).ok();
}

#[test]
fn angles_beyond_the_normal_range_are_noted_not_refused() {
    let wd = default_hand();
    // AAOS normal active ranges: finger MCP -45 (hyperextension) to 90, PIP 0 to
    // 100; thumb MCP 0 to 50, IP -20 to 80. The thumb takes half the MCP and PIP
    // angles: -12.5 and 85 here, both beyond; the fingers' MCP -25 is not.
    let args = ["deform", "right.glb", "--angles", "-25,170,60"];
    wd.run(&args)
        .ok()
        .stdout_has("note: the fingers' PIP at 170 degrees")
        .stdout_has("note: the thumb's MCP at -12.5 degrees")
        .stdout_has("note: the thumb's IP at 85 degrees");
    let doc = wd
        .run(&[&args[..], &["--format", "json"]].concat())
        .ok()
        .json();
    let notes: Vec<&str> = doc["notes"]
        .as_array()
        .expect("notes")
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert_eq!(notes.len(), 3, "{notes:?}");
    assert!(
        notes.iter().any(|n| n.starts_with(
            "the fingers' PIP at 170 degrees is beyond its normal active range (0 to 100 degrees"
        )),
        "{notes:?}"
    );
    assert!(
        notes.iter().all(|n| n.contains("not one a hand makes")),
        "{notes:?}"
    );
    // The edges of the ranges and the named poses are anatomical: no note.
    for extra in [
        &["--angles", "90,100,90"][..],
        &["--angles", "0,0,-10"],
        &["--pose", "grip"],
        &[],
    ] {
        let doc = wd
            .run(&[&["deform", "right.glb", "--format", "json"][..], extra].concat())
            .ok()
            .json();
        assert_eq!(doc["notes"], serde_json::json!([]), "{extra:?}");
    }
}

/// The WebXR generic hands: vendored, or beside the repository.
fn webxr_dir() -> Option<PathBuf> {
    let root = manifest_dir();
    [
        root.join("data/rigs/webxr-generic-hand"),
        root.join("../shared/rigs/webxr-generic-hand"),
    ]
    .into_iter()
    .find(|d| d.join("left.glb").is_file() && d.join("right.glb").is_file())
}

#[test]
fn the_webxr_hands_deform_and_draw() {
    let Some(dir) = webxr_dir() else {
        skip(
            "the WebXR generic hands are in neither data/rigs/webxr-generic-hand nor ../shared/rigs/webxr-generic-hand",
        );
        return;
    };
    let wd = Workdir::new();
    wd.copy_paper_data();
    for side in ["left", "right"] {
        let rig = dir.join(format!("{side}.glb"));
        let rig = rig.to_str().unwrap();
        let out = format!("r-{side}");
        let doc = wd
            .run(&["deform", rig, "--out", &out, "--format", "json"])
            .ok()
            .json();
        let hand = &doc["rig"]["hands"][0];
        assert_eq!(hand["side"], side);
        // The file's own counts (accessors 0 and 5 of its JSON).
        assert_eq!(hand["vertices"], 1360);
        assert_eq!(hand["triangles"], 6942 / 3);
        // Every finger's PIP (thumb: IP) is bent, so LBS loses some area there.
        for f in hand["measures"]["fingers"].as_array().unwrap() {
            let j = &f["joints"][1];
            assert!(num(&j["volume_loss"]) > 0.0, "{f}");
        }
        let png = wd.read(&format!("{out}/deform-{side}.png"));
        let img = tiny_skia::Pixmap::decode_png(&png).unwrap();
        let white = img
            .pixels()
            .iter()
            .filter(|p| p.red() == 255 && p.green() == 255 && p.blue() == 255)
            .count();
        let share = white as f64 / img.pixels().len() as f64;
        assert!((0.2..0.95).contains(&share), "{side}: {share}");
        let table = wd.run(&["deform", rig]);
        table.ok().stdout_has(&format!("{side} hand"));
        eprintln!("{}", table.stdout);
        let fix = wd.run(&["deform", rig, "--fix", "--out", &format!("f-{side}")]);
        fix.ok().stdout_has("B: ").stdout_has("Verdict:");
        eprintln!("{}", fix.stdout);
        if side == "right" {
            // The rigger's guide's --fix table is what the command prints.
            let guide = std::fs::read_to_string(manifest_dir().join("docs/rigger.md")).unwrap();
            let rows: Vec<&str> = fix.stdout.lines().filter(|l| l.starts_with('|')).collect();
            assert_eq!(rows.len(), 16, "{}", fix.stdout);
            for line in rows.iter().chain(
                fix.stdout
                    .lines()
                    .find(|l| l.starts_with("Verdict:"))
                    .iter(),
            ) {
                assert!(
                    guide.contains(line),
                    "docs/rigger.md lacks the --fix line:\n{line}"
                );
            }
        }
    }
}

/// A VRM 0.x avatar's right hand as VRoid exports it, made from the tube hand:
/// `J_Bip_R_Hand` with every finger's first bone hanging from it (no
/// metacarpals: their weights go to the hand bone, their nodes become
/// unweighted leaves of it), the thumb `J_Bip_R_Thumb1..3` (VRM 0.x reads its
/// Proximal as the CMC), no tip nodes, and the humanoid table (`extensions.VRM`)
/// naming every bone. The file name says no side; the table does.
fn vrm0_avatar() -> Vec<u8> {
    use phalanx::dataset::Finger;
    let mut rig = phalanx::rig::deform::synthetic::tube_hand(&HandSpec::default());
    let wrist = rig.chains.wrist.unwrap();
    rig.names[wrist] = "J_Bip_R_Hand".into();
    let mut bones = vec![serde_json::json!({"bone": "rightHand", "node": wrist})];
    let mut merged_into_hand = Vec::new();
    for (k, f) in rig.chains.fingers.iter().enumerate() {
        let mc = f.metacarpal.unwrap();
        let (vrm, vroid) = match f.finger {
            Finger::Thumb => ("Thumb", "Thumb"),
            Finger::Index => ("Index", "Index"),
            Finger::Middle => ("Middle", "Middle"),
            Finger::Ring => ("Ring", "Ring"),
            Finger::Little => ("Little", "Little"),
        };
        let mut nodes = f.joints.clone();
        if f.finger == Finger::Thumb {
            nodes.insert(0, mc);
        } else {
            rig.names[mc] = format!("J_Sec_R_Palm{k}");
            merged_into_hand.push(mc);
            rig.skeleton.parent[f.joints[0]] = Some(wrist);
        }
        for (i, &n) in nodes.iter().enumerate() {
            rig.names[n] = format!("J_Bip_R_{vroid}{}", i + 1);
            let part = ["Proximal", "Intermediate", "Distal"][i];
            bones.push(serde_json::json!({"bone": format!("right{vrm}{part}"), "node": n}));
        }
        rig.names[f.tip.unwrap()] = format!("J_Sec_R_Nail{k}");
    }
    // Skin slots are node - 1 (every node but the Armature is a joint).
    let slot = |n: usize| (n - 1) as u16;
    let hand_slot = slot(wrist);
    let merged: Vec<u16> = merged_into_hand.iter().map(|&n| slot(n)).collect();
    let mesh = &mut rig.mesh;
    let mut flat = Vec::new();
    let mut start = Vec::new();
    for v in 0..mesh.positions.len() {
        start.push(flat.len());
        let mut infl: Vec<(u16, f64)> = Vec::new();
        for &(j, w) in mesh.influences_of(v) {
            let j = if merged.contains(&j) { hand_slot } else { j };
            match infl.iter_mut().find(|x| x.0 == j) {
                Some(x) => x.1 += w,
                None => infl.push((j, w)),
            }
        }
        infl.sort_by(|a, b| b.1.total_cmp(&a.1));
        flat.extend(infl);
    }
    start.push(flat.len());
    mesh.influences = flat;
    mesh.influence_start = start;
    let glb = rig.to_glb().unwrap();
    let (mut doc, bin) = crate::audit::hand::read_glb(&glb);
    doc["extensionsUsed"] = serde_json::json!(["VRM"]);
    doc["extensions"] =
        serde_json::json!({"VRM": {"specVersion": "0.0", "humanoid": {"humanBones": bones}}});
    crate::audit::hand::glb(&doc, bin)
}

#[test]
fn a_vrm0_avatar_whose_fingers_hang_from_the_hand_bone_is_posed() {
    let wd = Workdir::with_paper_data();
    wd.write("avatar.vrm", vrm0_avatar());
    // The audit reads it (a thumb CMC, four fingers from the hand bone)...
    let audit = wd.run(&["audit", "avatar.vrm", "--format", "json"]);
    let doc: Value = serde_json::from_str(&audit.ok().stdout).unwrap();
    assert_eq!(doc["rig"]["fingers"].as_array().unwrap().len(), 5);
    // ...and deform poses it: the hand bone is the wrist, no finger's metacarpal.
    let run = wd.run(&["deform", "avatar.vrm", "--format", "json"]);
    let doc: Value = serde_json::from_str(&run.ok().stdout).unwrap();
    let hand = &doc["rig"]["hands"][0];
    assert_eq!(hand["side"], "right", "{hand}");
    let fingers = hand["measures"]["fingers"].as_array().unwrap();
    assert_eq!(fingers.len(), 5);
    // Every finger is curled at every joint of its own (before, the shared hand
    // bone was refused as the metacarpal of four fingers and the wrist at once).
    for f in fingers {
        let joints = f["joints"].as_array().unwrap();
        let want = if f["finger"] == "thumb" { 2 } else { 3 };
        assert_eq!(joints.len(), want, "{}", f["finger"]);
        for j in joints {
            assert!(num(&j["angle"]) >= 30.0 - 1e-9, "{j}");
            assert!(num(&j["volume_loss"]) > 0.0, "{j}");
        }
    }
}

/// A side-less copy of the WebXR right hand (`copy.glb`: neither its joint
/// names nor its file name say which hand it is): audit and deform go by one
/// rule, and say the same of its side.
#[test]
fn audit_and_deform_agree_on_the_side_of_a_sideless_copy() {
    let Some(dir) = webxr_dir() else {
        skip("the WebXR generic hands are not there");
        return;
    };
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write("copy.glb", std::fs::read(dir.join("right.glb")).unwrap());
    wd.write("right.glb", std::fs::read(dir.join("right.glb")).unwrap());
    // No side known: the audit judges (proportions do not depend on it) and says
    // deform needs --side; deform refuses, saying the same.
    let audit = wd.run(&["audit", "--explain", "copy.glb"]);
    audit
        .ok()
        .stdout_has("neither the joint names nor the file name say which hand this is");
    audit.stdout_has("but deform needs --side left or");
    wd.run(&["deform", "copy.glb", "-q"])
        .expect_code(2)
        .stderr_has("give --side left or --side right");
    // Given --side, deform curls it; named in the file name, both take that side.
    wd.run(&["deform", "copy.glb", "-q", "--side", "right"])
        .ok()
        .stdout_has("right hand");
    wd.run(&["audit", "--explain", "right.glb"])
        .ok()
        .stdout_has("the file name says right");
    wd.run(&["deform", "right.glb", "-q"])
        .ok()
        .stdout_has("right hand");
}

/// Over every rig in ../shared/rigs (skipped with the reason when absent),
/// `deform --fix` in the fist with LBS (the fix `audit --fix` writes, with the
/// MCPs judged from their rays' bases against the repository's atlas): the
/// fixed rig deforms worse at no more joints than it deforms better, per file.
/// Each joint's verdict is read from the JSON's `overall` ("a": the rig as it
/// was is better; "b": the fixed rig).
#[test]
fn the_fix_deforms_worse_at_no_more_joints_than_better_on_every_shared_rig() {
    let Some(rigs) = shared_rig_files() else {
        return;
    };
    assert!(!rigs.is_empty(), "no rigs in ../shared/rigs");
    let wd = Workdir::new();
    // Each rig against what `audit --fix` writes, in the fist and the grip,
    // skinned by linear blend and by dual quaternions, the verdicts of the
    // four counted together.
    for rig in &rigs {
        let (mut a, mut b) = (0, 0);
        for pose in ["fist", "grip"] {
            for skinning in ["lbs", "dqs"] {
                let run = wd
                    .command(&[
                        "deform",
                        &rig.display().to_string(),
                        "--fix",
                        "--pose",
                        pose,
                        "--skinning",
                        skinning,
                        "--format",
                        "json",
                    ])
                    .current_dir(manifest_dir())
                    .output()
                    .unwrap();
                assert!(run.status.success(), "{}: {:?}", rig.display(), run);
                let doc: Value = serde_json::from_slice(&run.stdout).unwrap();
                for hand in doc["verdicts"].as_array().unwrap() {
                    for j in hand["joints"].as_array().unwrap() {
                        match j["overall"].as_str() {
                            Some("a") => a += 1,
                            Some("b") => b += 1,
                            _ => {}
                        }
                    }
                }
            }
        }
        eprintln!(
            "{}: fixed better at {b} joints, worse at {a}",
            rig.display()
        );
        assert!(
            a <= b,
            "{}: the fixed rig is worse at {a} joints and better at {b}",
            rig.display()
        );
    }
}
