//! The JSON Schemas in `docs/schema/`: current (what `phalanx schema` writes
//! now), valid JSON Schema, and satisfied by the real output of every command
//! that writes JSON, while a broken copy of each document is refused.

use crate::common;

use common::*;
use jsonschema::Validator;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The committed schemas directory.
fn schema_dir() -> PathBuf {
    manifest_dir().join("docs/schema")
}

/// The committed schema of `name` (`docs/schema/<name>.schema.json`), checked
/// against the JSON Schema meta-schema and compiled.
fn validator(name: &str) -> Validator {
    let path = schema_dir().join(format!("{name}.schema.json"));
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let schema: Value = serde_json::from_str(&text).expect("a schema is JSON");
    jsonschema::meta::validate(&schema)
        .unwrap_or_else(|e| panic!("{name}.schema.json is not a valid JSON Schema: {e}"));
    jsonschema::validator_for(&schema)
        .unwrap_or_else(|e| panic!("{name}.schema.json does not compile: {e}"))
}

/// Asserts that `doc` satisfies the schema of `name`, listing every violation.
#[track_caller]
fn assert_valid(v: &Validator, name: &str, doc: &Value) {
    let errors: Vec<String> = v
        .iter_errors(doc)
        .map(|e| format!("  at {}: {e}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "a real {name} document fails docs/schema/{name}.schema.json:\n{}",
        errors.join("\n")
    );
}

/// Asserts that `doc` changed by `break_it` no longer satisfies the schema.
#[track_caller]
fn assert_refused(
    v: &Validator,
    name: &str,
    doc: &Value,
    what: &str,
    break_it: impl FnOnce(&mut Value),
) {
    let mut broken = doc.clone();
    break_it(&mut broken);
    assert_ne!(&broken, doc, "{name}: '{what}' changed nothing");
    assert!(
        !v.is_valid(&broken),
        "{name}: the schema accepts a document with {what}"
    );
}

/// The breakage every document with a `schema_version` must be refused for.
#[track_caller]
fn assert_version_pinned(v: &Validator, name: &str, doc: &Value) {
    assert_refused(v, name, doc, "schema_version 7", |d| {
        d["schema_version"] = json!(7)
    });
    assert_refused(v, name, doc, "no schema_version", |d| {
        d.as_object_mut().unwrap().remove("schema_version");
    });
}

#[test]
fn committed_schemas_are_what_the_code_writes() {
    let wd = Workdir::new();
    wd.run(&["schema", "--out", "schema"]).ok();
    let files = |dir: &Path| -> BTreeMap<String, Vec<u8>> {
        std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .map(|p| {
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                (name, std::fs::read(&p).unwrap())
            })
            .collect()
    };
    let now = files(&wd.path().join("schema"));
    let committed = files(&schema_dir());
    assert!(now.len() >= 7, "too few schemas written: {:?}", now.keys());
    assert_eq!(
        now.keys().collect::<Vec<_>>(),
        committed.keys().collect::<Vec<_>>(),
        "docs/schema/ holds other files than `phalanx schema` writes: run `cargo run -- schema` \
         (it writes docs/schema/), delete the files of documents that are gone, and commit docs/schema/"
    );
    for (name, bytes) in &now {
        assert!(
            committed[name] == *bytes,
            "docs/schema/{name} is stale: run `cargo run -- schema` and commit docs/schema/"
        );
    }
}

#[test]
fn stats_documents_satisfy_the_stats_schema() {
    let v = validator("stats");
    let wd = Workdir::new();
    wd.copy_paper_data();
    let doc = wd.run(&["stats", "--format", "json"]).ok().json();
    assert_valid(&v, "stats", &doc);

    // The published reports/stats.json, and a grouped document (--group-by).
    let published: Value =
        serde_json::from_slice(&std::fs::read(manifest_dir().join("reports/stats.json")).unwrap())
            .unwrap();
    assert_valid(&v, "stats", &published);
    wd.run(&[
        "add",
        "--xray",
        "2c",
        "--finger",
        "index",
        "--lengths",
        "361.2,199.9,181.3",
        "--sex",
        "female",
    ])
    .ok();
    let grouped = wd
        .run(&["stats", "--group-by", "sex", "--format", "json"])
        .ok()
        .json();
    assert_eq!(grouped["groups"]["groups"].as_array().unwrap().len(), 2);
    assert_valid(&v, "stats", &grouped);

    assert_version_pinned(&v, "stats", &doc);
    let q = "/fingers/0/quantities/0";
    assert_refused(&v, "stats", &doc, "an interval of three numbers", |d| {
        d.pointer_mut(&format!("{q}/ci_t"))
            .unwrap()
            .as_array_mut()
            .unwrap()
            .push(json!(1.0));
    });
    assert_refused(
        &v,
        "stats",
        &doc,
        "no prediction interval key (flattened)",
        |d| {
            d.pointer_mut(q)
                .unwrap()
                .as_object_mut()
                .unwrap()
                .remove("pi");
        },
    );
    assert_refused(&v, "stats", &doc, "an unknown quantity", |d| {
        *d.pointer_mut(&format!("{q}/name")).unwrap() = json!("rel_j4");
    });
    assert_refused(&v, "stats", &doc, "a finger called toe", |d| {
        d["fingers"][0]["finger"] = json!("toe");
    });
    assert_refused(&v, "stats", &doc, "a bootstrap method 'jackknife'", |d| {
        d["fingers"][0]["bootstrap"]["method"] = json!("jackknife");
    });
    assert_refused(&v, "stats", &grouped, "a group without fingers", |d| {
        d["groups"]["groups"][0]
            .as_object_mut()
            .unwrap()
            .remove("fingers");
    });
}

#[test]
fn check_and_coverage_documents_satisfy_their_schemas() {
    let wd = Workdir::new();
    wd.copy_paper_data();

    let v = validator("check");
    let doc = wd.run(&["check", "--format", "json"]).ok().json();
    assert!(!doc["claims"].as_array().unwrap().is_empty());
    assert_valid(&v, "check", &doc);
    assert_version_pinned(&v, "check", &doc);
    assert_refused(&v, "check", &doc, "a verdict 'close enough'", |d| {
        d["claims"][0]["verdict"] = json!("close enough");
    });
    assert_refused(&v, "check", &doc, "a count that is text", |d| {
        d["summary"]["claims"] = json!("all");
    });

    let v = validator("coverage");
    let doc = wd
        .run(&["coverage", "--sims", "50", "--format", "json"])
        .ok()
        .json();
    assert_valid(&v, "coverage", &doc);
    assert_version_pinned(&v, "coverage", &doc);
    assert_refused(&v, "coverage", &doc, "a method without its coverage", |d| {
        let m = d.pointer_mut("/quantities/0/coverage/methods/0").unwrap();
        m.as_object_mut().unwrap().remove("coverage");
    });
}

#[test]
fn place_documents_satisfy_the_place_schema() {
    let v = validator("place");
    let wd = Workdir::new();
    wd.copy_paper_data();
    for args in [
        &[
            "place", "--finger", "index", "--length", "1000", "--format", "json",
        ][..],
        &[
            "place",
            "--hand",
            "thumb=60,index=80,little=55",
            "--format",
            "json",
        ][..],
    ] {
        let doc = wd.run(args).ok().json();
        assert_valid(&v, "place", &doc);
        assert_version_pinned(&v, "place", &doc);
        assert_refused(&v, "place", &doc, "a joint called knuckle", |d| {
            d["placements"][0]["joints"][0]["joint"] = json!("knuckle");
        });
        assert_refused(&v, "place", &doc, "a position without its mean", |d| {
            let p = d.pointer_mut("/placements/0/joints/0/position").unwrap();
            p.as_object_mut().unwrap().remove("mean");
        });
    }
}

#[test]
fn audit_documents_satisfy_the_audit_schema() {
    let v = validator("audit");
    let wd = Workdir::new();
    wd.copy_paper_data();
    let examples = manifest_dir().join("docs/examples");
    let hand = examples.join("hand.glb");
    let avatar = examples.join("avatar.vrm");
    let (hand, avatar) = (hand.to_str().unwrap(), avatar.to_str().unwrap());

    // With tips (hand.glb), without (a VRM avatar), and with --fix.
    let with_tips = wd.run(&["audit", hand, "--format", "json"]).ok().json();
    let vrm = wd.run(&["audit", avatar, "--format", "json"]).ok().json();
    let fixed = wd
        .run(&["audit", hand, "--fix", "fixed.glb", "--format", "json"])
        .ok()
        .json();
    assert!(fixed["fix"]["moved"].is_array(), "no fix block: {fixed}");
    // A real rig: siblings read by name, skin weights (bends), the skin's end
    // as its tip, and the MCP and the tip judged with their own standing.
    let webxr = manifest_dir().join("data/rigs/webxr-generic-hand/right.glb");
    let webxr = webxr.to_str().unwrap();
    let real = wd.run(&["audit", webxr, "--format", "json"]).ok().json();
    let real_fixed = wd
        .run(&["audit", webxr, "--fix", "webxr.glb", "--format", "json"])
        .ok()
        .json();
    for finger in real["rig"]["fingers"].as_array().unwrap() {
        let joints = finger["audit"]["joints"].as_array().unwrap();
        let names: Vec<&str> = joints
            .iter()
            .map(|j| j["joint"].as_str().unwrap())
            .collect();
        assert_eq!(names.first(), Some(&"MCP"), "{names:?}");
        assert_eq!(names.last(), Some(&"tip"), "{names:?}");
        assert!(
            joints.iter().all(|j| j["standing"].is_string()),
            "{joints:?}"
        );
        assert!(!finger["bends"].as_array().unwrap().is_empty());
    }
    assert_refused(&v, "audit", &real, "an MCP without its standing", |d| {
        d["rig"]["fingers"][0]["audit"]["joints"][0]
            .as_object_mut()
            .unwrap()
            .remove("standing");
    });
    for doc in [&real, &real_fixed] {
        assert_valid(&v, "audit", doc);
    }
    for doc in [&with_tips, &vrm, &fixed] {
        assert!(!doc["rig"]["fingers"].as_array().unwrap().is_empty());
        assert_valid(&v, "audit", doc);
    }
    // Every standing is written somewhere, so each branch of the schema is used.
    let text = format!("{with_tips}{vrm}");
    for s in ["\"in_range\"", "\"above\"", "\"below\""] {
        assert!(text.contains(s), "no standing {s} in the example audits");
    }

    assert_version_pinned(&v, "audit", &with_tips);
    let joint = "/rig/fingers/0/audit/joints/0";
    assert_refused(&v, "audit", &with_tips, "a standing 'sideways'", |d| {
        *d.pointer_mut(&format!("{joint}/standing")).unwrap() = json!("sideways");
    });
    assert_refused(
        &v,
        "audit",
        &with_tips,
        "a suggested point of two numbers",
        |d| {
            d.pointer_mut(&format!("{joint}/suggested"))
                .unwrap()
                .as_array_mut()
                .unwrap()
                .pop();
        },
    );
    assert_refused(
        &v,
        "audit",
        &with_tips,
        "a finger without its side (flattened chain)",
        |d| {
            d["rig"]["fingers"][0]
                .as_object_mut()
                .unwrap()
                .remove("side");
        },
    );
    // The example hand's skin is too coarse to carry its weights, so its fix
    // holds every joint; the WebXR hand's moves its thumb's IP.
    assert_refused(
        &v,
        "audit",
        &real_fixed,
        "a moved node without its shift",
        |d| {
            d["fix"]["moved"][0]
                .as_object_mut()
                .unwrap()
                .remove("shift");
        },
    );
}

/// The standing of an audit joint outside the interval needs its distance `by`.
#[test]
fn an_outside_standing_needs_its_distance() {
    let v = validator("audit");
    let wd = Workdir::new();
    wd.copy_paper_data();
    let hand = manifest_dir().join("docs/examples/hand.glb");
    let doc = wd
        .run(&["audit", hand.to_str().unwrap(), "--format", "json"])
        .ok()
        .json();
    let fingers = doc["rig"]["fingers"].as_array().unwrap();
    let (f, j) = fingers
        .iter()
        .enumerate()
        .find_map(|(f, finger)| {
            let joints = finger["audit"]["joints"].as_array().unwrap();
            let j = joints.iter().position(|j| j.get("by").is_some())?;
            Some((f, j))
        })
        .expect("hand.glb has a joint outside its interval");
    assert_refused(&v, "audit", &doc, "an 'above'/'below' without 'by'", |d| {
        let joint = &mut d["rig"]["fingers"][f]["audit"]["joints"][j];
        joint.as_object_mut().unwrap().remove("by");
    });
}

#[test]
fn history_documents_and_records_satisfy_their_schemas() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.run(&[
        "add",
        "--xray",
        "2c",
        "--finger",
        "index",
        "--lengths",
        "361.2,199.9,181.3",
    ])
    .ok();
    // A snapshot of unchanged data writes nothing; one with a note and another seed does.
    wd.run(&["snapshot"]).ok();
    wd.run(&["snapshot", "--seed", "3", "--note", "re-seeded"])
        .ok();
    wd.run(&["remove", "--xray", "2c"]).ok();

    // The history file's lines: one per snapshot (an add, a snapshot, a removal).
    let v = validator("history-record");
    let history = String::from_utf8(wd.read("data/history.jsonl")).unwrap();
    let records: Vec<Value> = history
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(records.len(), 3, "{history}");
    assert_eq!(records[0]["event"], "add");
    assert_eq!(records[0]["change"]["xrays"], json!(["2c"]));
    assert_eq!(records[1]["event"], "snapshot");
    assert_eq!(records[1]["note"], "re-seeded");
    assert_eq!(records[2]["event"], "remove");
    for r in &records {
        assert_valid(&v, "history-record", r);
    }
    // And the shipped history.
    let shipped = std::fs::read_to_string(manifest_dir().join("data/history.jsonl")).unwrap();
    for line in shipped.lines().filter(|l| !l.trim().is_empty()) {
        assert_valid(&v, "history-record", &serde_json::from_str(line).unwrap());
    }
    assert_refused(&v, "history-record", &records[0], "an event 'edit'", |d| {
        d["event"] = json!("edit");
    });
    assert_refused(
        &v,
        "history-record",
        &records[0],
        "a record without its t interval",
        |d| {
            d["quantities"][0].as_object_mut().unwrap().remove("ci_t");
        },
    );

    let v = validator("history");
    let doc = wd.run(&["history", "--format", "json"]).ok().json();
    assert_eq!(doc["snapshots"], 3);
    assert_eq!(doc["series"][0]["points"].as_array().unwrap().len(), 3);
    assert_eq!(doc["records"][2]["change"]["rows"], 1);
    assert_valid(&v, "history", &doc);
    assert_version_pinned(&v, "history", &doc);
    assert_refused(&v, "history", &doc, "a change without its rows", |d| {
        d["records"][0]["change"]
            .as_object_mut()
            .unwrap()
            .remove("rows");
    });
    assert_refused(&v, "history", &doc, "a point without its record", |d| {
        d["series"][0]["points"][0]
            .as_object_mut()
            .unwrap()
            .remove("record");
    });
}

#[test]
fn compare_and_population_documents_satisfy_their_schemas() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let atlas = manifest_dir().join("data/atlas/measurements.csv");
    let atlas = atlas.to_str().unwrap();

    let v = validator("compare");
    let doc = wd
        .run(&[
            "compare",
            "data/measurements.csv",
            atlas,
            "--resamples",
            "200",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert!(!doc["fingers"].as_array().unwrap().is_empty());
    assert_valid(&v, "compare", &doc);
    assert_version_pinned(&v, "compare", &doc);
    assert_refused(&v, "compare", &doc, "a finger without its sentence", |d| {
        let f = d.pointer_mut("/fingers/0").unwrap();
        f.as_object_mut().unwrap().remove("summary");
    });

    let v = validator("coverage-population");
    let doc = wd
        .run(&[
            "coverage",
            "--population",
            atlas,
            "--n",
            "3,5",
            "--sims",
            "50",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert_valid(&v, "coverage-population", &doc);
    assert_version_pinned(&v, "coverage-population", &doc);
    assert_refused(
        &v,
        "coverage-population",
        &doc,
        "a sample size that is text",
        |d| {
            d["sizes"][0] = json!("five");
        },
    );
}

#[test]
fn deform_documents_satisfy_the_deform_schema() {
    use phalanx::rig::deform::synthetic::{HandSpec, tube_hand};
    let v = validator("deform");
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.write(
        "right.glb",
        tube_hand(&HandSpec::default()).to_glb().unwrap(),
    );
    // One rig, and with --fix and figures.
    let one = wd
        .run(&["deform", "right.glb", "--format", "json"])
        .ok()
        .json();
    let two = wd
        .run(&[
            "deform",
            "right.glb",
            "--fix",
            "--out",
            "r",
            "--format",
            "json",
        ])
        .ok()
        .json();
    assert!(two["verdicts"][0]["joints"].is_array() && two["renders"][0]["panels"].is_array());
    for doc in [&one, &two] {
        assert_valid(&v, "deform", doc);
    }
    assert_version_pinned(&v, "deform", &one);
    assert_refused(&v, "deform", &two, "a verdict 'both'", |d| {
        d["verdicts"][0]["joints"][0]["overall"] = json!("both");
    });
    assert_refused(&v, "deform", &one, "a joint without its volume loss", |d| {
        d["rig"]["hands"][0]["measures"]["fingers"][0]["joints"][0]
            .as_object_mut()
            .unwrap()
            .remove("volume_loss");
    });
    assert_refused(&v, "deform", &one, "a skinning 'blend'", |d| {
        d["skinning"] = json!("blend");
    });
}
