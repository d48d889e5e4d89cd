//! `phalanx import`: the atlas against distances computed here from its raw coordinates,
//! the three layouts against each other through the binary, every bad annotation exiting 2
//! with its place and nothing written (with `--out` and with `--into`), and the example COCO
//! file of docs/examples kept current.

use crate::common::{self, Workdir};
use serde_json::{Value, json};
use std::path::PathBuf;

/// The atlas's landmarks, or `None` (with the reason printed) when they are absent (a
/// package of the crate leaves the GPL-3.0 data out).
fn atlas() -> Option<String> {
    common::vendored("data/atlas/landmarks.csv")
        .map(|bytes| String::from_utf8(bytes).expect("the atlas is UTF-8"))
}

/// The atlas's landmark numbers of each finger: CMC, MCP, PIP (thumb IP), DIP, tip
/// (data/atlas/README.md), with the finger names of the measurement format.
const CHAINS: [(&str, &[usize]); 5] = [
    ("thumb", &[17, 18, 19, 20]),
    ("index", &[16, 21, 22, 23, 24]),
    ("middle", &[15, 25, 26, 27, 28]),
    ("ring", &[14, 29, 30, 31, 32]),
    ("little", &[13, 33, 34, 35, 36]),
];

/// The plain landmark names of each chain joint, in the chain's order.
fn joint_names(finger: &str) -> Vec<String> {
    let joints: &[&str] = if finger == "thumb" {
        &["cmc", "mcp", "ip", "tip"]
    } else {
        &["cmc", "mcp", "pip", "dip", "tip"]
    };
    joints.iter().map(|j| format!("{finger}_{j}")).collect()
}

/// An imported measurement file as (xray, finger, [j1, j2, j3], mc, unit, side, tip) rows,
/// read with the csv crate (not phalanx).
type Parsed = (
    String,
    String,
    Vec<f64>,
    Option<f64>,
    String,
    String,
    String,
);

fn parse_rows(text: &str) -> Vec<Parsed> {
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let h = r.headers().unwrap().clone();
    assert_eq!(
        h.iter().collect::<Vec<_>>(),
        [
            "xray", "finger", "j1", "j2", "j3", "mc", "sex", "age", "side", "source", "unit", "tip"
        ]
    );
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            let num = |i: usize| (!rec[i].is_empty()).then(|| rec[i].parse::<f64>().unwrap());
            (
                rec[0].to_string(),
                rec[1].to_string(),
                (2..5).filter_map(num).collect(),
                num(5),
                rec[10].to_string(),
                rec[8].to_string(),
                rec[11].to_string(),
            )
        })
        .collect()
}

#[test]
fn the_atlas_imports_to_the_distances_between_its_raw_coordinates() {
    let Some(text) = atlas() else { return };
    let wd = Workdir::new();
    wd.write("atlas.csv", &text);
    let run = wd.run(&["import", "atlas.csv", "--layout", "atlas37"]);
    run.ok().stderr_has("imported 4550 rows from 910 hands");
    let rows = parse_rows(&run.stdout);
    assert_eq!(rows.len(), 910 * 5);
    // Independently: each line split on commas, landmark k at fields 1 + 2k and 2 + 2k;
    // J_k = sqrt(dx^2 + dy^2) between consecutive joints from the MCP, mc from the CMC.
    let mut it = rows.iter();
    for line in text.lines() {
        let f: Vec<&str> = line.split(',').collect();
        let p = |k: usize| -> (f64, f64) {
            (f[1 + 2 * k].parse().unwrap(), f[2 + 2 * k].parse().unwrap())
        };
        let d = |a: usize, b: usize| {
            let ((ax, ay), (bx, by)) = (p(a), p(b));
            ((bx - ax).powi(2) + (by - ay).powi(2)).sqrt()
        };
        for (finger, chain) in CHAINS {
            let (xray, name, js, mc, unit, side, tip) = it.next().unwrap();
            assert_eq!((xray.as_str(), name.as_str()), (f[0], finger));
            let want: Vec<f64> = chain[1..].windows(2).map(|w| d(w[0], w[1])).collect();
            assert_eq!(js.len(), want.len());
            for (got, want) in js.iter().zip(&want) {
                // Written with 6 decimals: within 5e-7 pixels.
                assert!(
                    (got - want).abs() <= 5.1e-7,
                    "{xray} {finger}: {got} vs {want}"
                );
            }
            assert!((mc.unwrap() - d(chain[0], chain[1])).abs() <= 5.1e-7);
            assert_eq!(
                (unit.as_str(), side.as_str(), tip.as_str()),
                ("px", "left", "bone")
            );
        }
    }
    // The committed measurement file is this import (with its source), as CI checks.
    let committed =
        std::fs::read_to_string(common::manifest_dir().join("data/atlas/measurements.csv"))
            .expect("data/atlas/measurements.csv is committed with the atlas");
    let run = wd.run(&[
        "import",
        "atlas.csv",
        "--layout",
        "atlas37",
        "--source",
        "Digital Hand Atlas",
    ]);
    assert!(
        run.ok().stdout == committed,
        "data/atlas/measurements.csv is not the import of data/atlas/landmarks.csv; re-import it"
    );
}

#[test]
fn coco_and_long_files_built_here_give_the_atlas_rows() {
    let Some(text) = atlas() else { return };
    let lines: Vec<&str> = text.lines().take(3).collect();
    let wd = Workdir::new();
    wd.write("three.csv", lines.join("\n"));
    let atlas_rows = wd
        .run(&["import", "three.csv", "--layout", "atlas37"])
        .ok()
        .stdout
        .clone();
    // The same points as a long CSV (every finger joint, CMCs included) and as COCO
    // keypoints with a category naming them.
    let mut long = String::from("image,landmark,x,y\n");
    let mut names: Vec<String> = Vec::new();
    let mut images = Vec::new();
    let mut annotations = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let mut kp: Vec<Value> = Vec::new();
        for (finger, chain) in CHAINS {
            for (name, &k) in joint_names(finger).iter().zip(chain) {
                let (x, y) = (f[1 + 2 * k], f[2 + 2 * k]);
                long.push_str(&format!("{},{name},{x},{y}\n", f[0]));
                if i == 0 {
                    names.push(name.to_uppercase());
                }
                let v = |s: &str| json!(s.parse::<f64>().unwrap());
                kp.extend([v(x), v(y), json!(2)]);
            }
        }
        images.push(json!({"id": 10 + i, "file_name": f[0]}));
        annotations.push(json!({"id": i, "image_id": 10 + i, "category_id": 1, "keypoints": kp}));
    }
    let coco = json!({"images": images, "annotations": annotations,
        "categories": [{"id": 1, "name": "hand", "keypoints": names}]});
    wd.write("hands.csv", long);
    wd.write("hands.json", coco.to_string());
    let same = ["--side", "left", "--tip", "bone"];
    let from = |file: &str, layout: &str| {
        let mut args = vec!["import", file, "--layout", layout];
        args.extend(same);
        wd.run(&args).ok().stdout.clone()
    };
    assert_eq!(from("hands.csv", "long"), atlas_rows);
    assert_eq!(from("hands.json", "coco"), atlas_rows);
    assert_eq!(parse_rows(&atlas_rows).len(), 15);
}

/// A long-layout hand with a complete thumb and the given index joints.
fn long_hand(image: &str, index: &[(&str, f64, f64)]) -> String {
    let thumb = [
        ("thumb_mcp", 300.0, 600.0),
        ("thumb_ip", 330.0, 450.0),
        ("thumb_tip", 350.0, 350.0),
    ];
    thumb
        .iter()
        .chain(index)
        .map(|(n, x, y)| format!("{image},{n},{x},{y}\n"))
        .collect()
}

const INDEX: [(&str, f64, f64); 4] = [
    ("index_mcp", 200.0, 600.0),
    ("index_pip", 200.0, 300.0),
    ("index_dip", 205.0, 120.0),
    ("index_tip", 208.0, 20.0),
];

fn with_index(f: impl Fn(&mut Vec<(&'static str, f64, f64)>)) -> String {
    let mut index = INDEX.to_vec();
    f(&mut index);
    format!(
        "image,landmark,x,y\n{}{}",
        long_hand("ok", &INDEX),
        long_hand("b", &index)
    )
}

/// A COCO file of one standard 21-point hand (no names: the standard order).
fn coco_hand(edit: impl Fn(&mut Value)) -> String {
    let mut kp = vec![json!(500), json!(900), json!(2)];
    kp.extend(
        [600, 850, 750, 800, 800, 700, 830, 600]
            .chunks(2)
            .flat_map(|p| [json!(p[0]), json!(p[1]), json!(2)]),
    );
    for x in [560, 500, 440, 380] {
        for k in 0..4 {
            kp.extend([json!(x), json!(600 - 120 * k), json!(2)]);
        }
    }
    let mut v = json!({"images": [{"id": 7, "file_name": "x.png"}],
        "annotations": [{"image_id": 7, "category_id": 1, "keypoints": kp}],
        "categories": [{"id": 1, "name": "hand"}]});
    edit(&mut v);
    v.to_string()
}

/// Every bad-annotation case of the issue: (what, file name, layout, contents, needles
/// naming the place and the problem).
fn bad_cases() -> Vec<(
    &'static str,
    &'static str,
    &'static str,
    String,
    Vec<&'static str>,
)> {
    let mut cases = vec![
        (
            "missing landmark",
            "m.csv",
            "long",
            with_index(|i| {
                i.remove(2);
            }),
            vec!["m.csv:9:1: image: image 'b': the index DIP is missing"],
        ),
        (
            "duplicated landmark",
            "d.csv",
            "long",
            with_index(|i| i.push(("INDEX_FINGER_PIP", 1.0, 2.0))),
            vec![
                "d.csv:16:2: landmark: image 'b': the index PIP is given twice, here and on line 13",
            ],
        ),
        (
            "non-finite coordinate",
            "n.csv",
            "long",
            with_index(|i| i[3].2 = f64::NAN),
            vec!["n.csv:15:4: y: image 'b', index tip: 'NaN' is not a finite number"],
        ),
        (
            "negative coordinate",
            "g.csv",
            "long",
            with_index(|i| i[1].1 = -3.0),
            vec!["g.csv:13:3: x: image 'b', index PIP: '-3' is negative"],
        ),
        (
            "zero-length segment",
            "z.csv",
            "long",
            with_index(|i| i[2] = ("index_dip", 200.0, 300.0)),
            vec![
                "z.csv:14:2: landmark: image 'b': the index DIP ('index_dip') is at the same point (200, 300) as the index PIP",
            ],
        ),
        (
            "joints out of order",
            "o.csv",
            "long",
            with_index(|i| {
                i[1] = ("index_pip", 205.0, 120.0);
                i[2] = ("index_dip", 200.0, 300.0);
            }),
            vec![
                "o.csv:14:2: landmark: image 'b': the index DIP ('index_dip') is no farther from the index MCP",
                "swapped",
            ],
        ),
        (
            "fold back over 90 degrees",
            "f.csv",
            "long",
            with_index(|i| {
                i[1] = ("index_pip", 200.0, 500.0);
                i[2] = ("index_dip", 300.0, 520.0);
                i[3] = ("index_tip", 350.0, 540.0);
            }),
            vec![
                "f.csv:13:2: landmark: image 'b': the index finger folds back by 101 degrees at the index PIP",
            ],
        ),
        (
            "implausible finger",
            "p.csv",
            "long",
            with_index(|i| {
                i[1] = ("index_pip", 200.0, 500.0);
                i[2] = ("index_dip", 200.0, 20.0);
                i[3] = ("index_tip", 200.0, 0.0);
            }),
            vec![
                "p.csv:9:1: image: image 'b': the index finger's segments (J1 = 100.0, J2 = 480.0, J3 = 20.0 px) make no plausible finger",
            ],
        ),
        (
            "unknown keypoint name",
            "u.csv",
            "long",
            with_index(|i| i.push(("index_knuckle", 1.0, 2.0))),
            vec!["u.csv:16:2: landmark: image 'b': unknown landmark 'index_knuckle'"],
        ),
        (
            "unknown COCO keypoint name",
            "u.json",
            "coco",
            coco_hand(|v| {
                let mut names: Vec<Value> = (0..21).map(|k| json!(format!("k{k}"))).collect();
                names[0] = json!("WRIST");
                v["categories"][0]["keypoints"] = json!(names);
            }),
            vec!["u.json: categories[0].keypoints[1]: unknown keypoint name 'k1'"],
        ),
        (
            "annotation pointing at no image",
            "a.json",
            "coco",
            coco_hand(|v| v["annotations"][0]["image_id"] = json!(8)),
            vec!["a.json: annotations[0].image_id: 8 points at no image"],
        ),
    ];
    if let Some(text) = atlas() {
        let lines: Vec<&str> = text.lines().take(2).collect();
        cases.push((
            "repeated image id",
            "r.csv",
            "atlas37",
            format!("{}\n{}\n{}\n", lines[0], lines[1], lines[0]),
            vec!["r.csv:3:1: image_id: image '3142' is repeated: line 1 has it already"],
        ));
    }
    cases
}

#[test]
fn every_bad_annotation_exits_2_with_its_place_and_writes_nothing() {
    let wd = Workdir::with_paper_data();
    let dataset = wd.read("data/measurements.csv");
    for (what, name, layout, contents, needles) in bad_cases() {
        wd.write(name, &contents);
        let run = wd.run(&["import", name, "--layout", layout, "--out", "out.csv"]);
        run.data_error();
        for n in &needles {
            assert!(
                run.stderr.contains(n),
                "{what}: stderr lacks {n:?}:\n{}",
                run.stderr
            );
        }
        assert!(
            !wd.path().join("out.csv").exists(),
            "{what}: --out was written"
        );
        // Through --into: the dataset and its history stay as they were.
        let run = wd.run(&[
            "import",
            name,
            "--layout",
            layout,
            "--into",
            "data/measurements.csv",
        ]);
        run.data_error().stderr_has(needles[0]);
        assert_eq!(
            wd.read("data/measurements.csv"),
            dataset,
            "{what}: dataset changed"
        );
        assert!(
            !wd.path().join("data/history.jsonl").exists(),
            "{what}: history written"
        );
    }
}

#[test]
fn import_into_a_dataset_goes_through_add() {
    let wd = Workdir::new();
    // The lab's file has a 'flagged' column already, so accepted rows leave its bytes be.
    let header = "xray,finger,j1,j2,j3,mc,sex,age,side,source,unit,tip,flagged\n";
    let base: String = (0..6)
        .map(|i| {
            let j1 = 300.0 + 3.0 * i as f64;
            format!(
                "{header_free}x{i},thumb,{},{},,{},,,right,lab,px,skin,\nx{i},index,{j1},{},{},,,,right,lab,px,skin,\n",
                250.0 + i as f64,
                230.0 - i as f64,
                430.0 + i as f64,
                180.0 + i as f64,
                150.0 + 2.0 * i as f64,
                header_free = ""
            )
        })
        .collect();
    wd.write("lab.csv", format!("{header}{base}"));
    let hand = format!("image,landmark,x,y\n{}", long_hand("new", &INDEX));
    wd.write("marks.csv", &hand);
    wd.write("lab-mm.csv", format!("{header}{base}"));
    // The new hand's proportions are far from the lab's near-identical ones: flagged, and
    // let in on purpose (the refusal itself is tested with 'add').
    let import_into = |into: &str, extra: &[&str]| {
        let mut args = vec![
            "import",
            "marks.csv",
            "--layout",
            "long",
            "--into",
            into,
            "--accept-flagged",
        ];
        args.extend_from_slice(extra);
        args.extend(["--side", "right", "--tip", "skin", "--source", "lab"]);
        wd.run(&args)
    };
    let import = |extra: &[&str]| import_into("lab.csv", extra);
    // The lab's rows are in px: lengths in mm go in beside them, their relative values
    // pooled, their lengths never averaged with the px ones (nor checked against them).
    let before = wd.read("lab.csv");
    import_into("lab-mm.csv", &["--unit", "mm"])
        .ok()
        .stdout_has("6 -> 7 X-rays")
        .stderr_has("no current X-ray gives thumb and index lengths in 'mm', so the new rows in 'mm' are checked on their relative values only");
    let mm = String::from_utf8(wd.read("lab-mm.csv")).unwrap();
    let last = mm.lines().last().unwrap();
    assert!(
        last.starts_with("new,index,300,180.069431,100.04499,,,,right,lab,mm,skin,\"J~1 = "),
        "{mm}"
    );
    let run = import(&[]);
    run.ok()
        .stdout_has("imported 2 rows from 1 hand in marks.csv into lab.csv: 6 -> 7 X-rays");
    let text = String::from_utf8(wd.read("lab.csv")).unwrap();
    assert!(text.starts_with(std::str::from_utf8(&before).unwrap()));
    assert!(
        text.lines()
            .last()
            .unwrap()
            .starts_with("new,index,300,180.069431,100.04499,,,,right,lab,px,skin,\"J~1 = "),
        "{text}"
    );
    // A snapshot of the statistics is appended, as for 'add'.
    assert!(wd.path().join("history.jsonl").exists());
    // Importing it again repeats its rows: refused, nothing changes.
    let after = wd.read("lab.csv");
    import(&[])
        .data_error()
        .stderr_has("2 rows already present in lab.csv (its lines 14-15): X-ray new (thumb, index); existing rows are never replaced");
    assert_eq!(wd.read("lab.csv"), after);
}

#[test]
fn usage_errors_and_notes() {
    let wd = Workdir::new();
    wd.write(
        "m.csv",
        format!("image,landmark,x,y\n{}", long_hand("a", &INDEX)),
    );
    wd.run(&[
        "import",
        "m.csv",
        "--layout",
        "long",
        "--pixel-spacing",
        "0",
    ])
    .data_error()
    .stderr_has("the pixel spacing must be a positive number of millimetres per pixel");
    wd.run(&["import", "m.csv", "--layout", "long", "--source", "=cmd()"])
        .data_error()
        .stderr_has("starts like a spreadsheet formula");
    wd.run(&[
        "import",
        "m.csv",
        "--layout",
        "long",
        "--pixel-spacing",
        "0.1",
        "--unit",
        "mm",
    ])
    .expect_code(2);
    wd.run(&["import", "m.csv", "--layout", "nope"])
        .expect_code(2);
    // Fingers the file does not annotate are left out with a note; mm with a spacing.
    let run = wd.run(&[
        "import",
        "m.csv",
        "--layout",
        "long",
        "--pixel-spacing",
        "0.1",
    ]);
    run.ok().stderr_has(
        "note: middle finger: not annotated in 1 image ('a'); imported the fingers they have",
    );
    let rows = parse_rows(&run.stdout);
    assert_eq!(rows.len(), 2);
    assert!((rows[1].2[0] - 30.0).abs() < 1e-9);
    assert_eq!(rows[1].4, "mm");
}

/// The example COCO file of docs/lab.md: X-rays 1a and 1b of the paper's Table 1 laid out
/// as straight right hands (thumb on the image's left), MediaPipe's keypoint names, y in
/// hundredths of a pixel so every segment is its Table 1 length. The thumb's CMC is not
/// labelled (no metacarpal: the paper has none), and in 1b the little fingertip is marked
/// not labelled (visibility 0), so that finger is left out with a note.
fn example_coco() -> String {
    let rows = common::paper_rows();
    let fingers = ["thumb", "index", "middle", "ring", "little"];
    let names = [
        "WRIST",
        "THUMB_CMC",
        "THUMB_MCP",
        "THUMB_IP",
        "THUMB_TIP",
        "INDEX_FINGER_MCP",
        "INDEX_FINGER_PIP",
        "INDEX_FINGER_DIP",
        "INDEX_FINGER_TIP",
        "MIDDLE_FINGER_MCP",
        "MIDDLE_FINGER_PIP",
        "MIDDLE_FINGER_DIP",
        "MIDDLE_FINGER_TIP",
        "RING_FINGER_MCP",
        "RING_FINGER_PIP",
        "RING_FINGER_DIP",
        "RING_FINGER_TIP",
        "PINKY_MCP",
        "PINKY_PIP",
        "PINKY_DIP",
        "PINKY_TIP",
    ];
    // x of each finger and y of its MCP, in pixels.
    let base = [
        (700, 1700),
        (900, 1300),
        (1050, 1280),
        (1200, 1300),
        (1350, 1380),
    ];
    let mut images = Vec::new();
    let mut annotations = Vec::new();
    for (i, xray) in ["1a", "1b"].iter().enumerate() {
        let mut kp = vec![
            json!(1050),
            json!(2200),
            json!(2),
            json!(650),
            json!(2050),
            json!(0),
        ];
        for (f, &(x, mcp)) in fingers.iter().zip(&base) {
            let row = rows
                .iter()
                .find(|r| r.xray == *xray && r.finger == *f)
                .expect("Table 1 row");
            let mut y = mcp * 100;
            kp.extend([json!(x), json!(mcp), json!(2)]);
            for (k, l) in row.lengths.iter().enumerate() {
                y -= (l * 100.0).round() as i64;
                let last = k + 1 == row.lengths.len();
                let v = if *f == "little" && *xray == "1b" && last {
                    0
                } else {
                    2
                };
                kp.extend([json!(x), json!(y as f64 / 100.0), json!(v)]);
            }
        }
        images.push(json!({"id": i + 1, "file_name": format!("figure-{xray}.png"), "width": 2000, "height": 2400}));
        annotations.push(json!({"id": i + 1, "image_id": i + 1, "category_id": 1, "num_keypoints": 21, "keypoints": kp}));
    }
    let doc = json!({
        "info": {"description": "phalanx example: X-rays 1a and 1b of the paper's Table 1 as COCO hand keypoints (straight fingers; built by tests/import.rs)"},
        "images": images,
        "annotations": annotations,
        "categories": [{"id": 1, "name": "hand", "supercategory": "person", "keypoints": names}]
    });
    format!("{}\n", serde_json::to_string_pretty(&doc).unwrap())
}

#[test]
fn the_example_coco_file_is_current_and_imports_table_1() {
    let path: PathBuf = common::manifest_dir().join("docs/examples/hands-coco.json");
    let want = example_coco();
    if std::fs::read_to_string(&path).ok().as_deref() != Some(want.as_str()) {
        std::fs::write(&path, &want).expect("write the example");
        panic!(
            "{} was out of date and has been rewritten: commit it",
            path.display()
        );
    }
    let wd = Workdir::new();
    wd.write("hands.json", &want);
    let run = wd.run(&[
        "import",
        "hands.json",
        "--layout",
        "coco",
        "--side",
        "right",
        "--tip",
        "skin",
    ]);
    run.ok().stderr_has(
        "note: little finger: not imported from 1 image where a joint is marked as not labelled ('figure-1b.png' at annotations[1].keypoints[60])",
    );
    let rows = parse_rows(&run.stdout);
    assert_eq!(rows.len(), 9);
    // Every imported J is Table 1's (to the 6 decimals written).
    for (xray, finger, js, mc, unit, side, tip) in &rows {
        let id = xray.trim_start_matches("figure-").trim_end_matches(".png");
        let t = common::paper_rows()
            .into_iter()
            .find(|r| r.xray == id && &r.finger == finger)
            .unwrap();
        assert_eq!(js.len(), t.lengths.len());
        for (a, b) in js.iter().zip(&t.lengths) {
            assert!((a - b).abs() < 1e-6, "{xray} {finger}: {a} vs {b}");
        }
        assert_eq!(
            (mc, unit.as_str(), side.as_str(), tip.as_str()),
            (&None, "px", "right", "skin")
        );
    }
}
