//! Landmark import: the atlas against independently computed distances, the three layouts
//! against each other, and every bad annotation with its place.

use super::*;
use serde_json::json;

use crate::dataset::vendored::{self, ATLAS_LANDMARKS as ATLAS};

/// The atlas's text, or `None` (with the skip printed) when the file is absent.
fn atlas_text() -> Option<String> {
    vendored::text(ATLAS)
}

fn opts() -> ImportOptions {
    ImportOptions::default()
}

fn ok(layout: Layout, text: &str, o: &ImportOptions) -> Import {
    match import(layout, "in", text.as_bytes(), o) {
        Ok(i) => i,
        Err(e) => panic!("{e}"),
    }
}

fn problems(layout: Layout, text: &str) -> Vec<Problem> {
    match import(layout, "in", text.as_bytes(), &opts()) {
        Ok(i) => panic!("expected problems, got {} rows", i.rows.len()),
        Err(e) => e.problems,
    }
}

/// Asserts exactly one problem, at `line`/`column`/`field`, whose message has every needle.
fn one(p: &[Problem], line: Option<u64>, column: Option<usize>, field: &str, needles: &[&str]) {
    assert_eq!(p.len(), 1, "{p:#?}");
    assert_eq!((p[0].line, p[0].column), (line, column), "{p:#?}");
    assert_eq!(p[0].field.as_deref(), Some(field), "{p:#?}");
    for n in needles {
        assert!(p[0].message.contains(n), "{:?} lacks {n:?}", p[0].message);
    }
}

#[test]
fn the_atlas_gives_the_distances_computed_from_its_raw_coordinates() {
    let Some(text) = atlas_text() else { return };
    let import = ok(Layout::Atlas37, &text, &opts());
    assert_eq!(import.hands, 910);
    assert_eq!(import.rows.len(), 910 * 5, "{:?}", import.notes);
    assert!(import.notes.is_empty(), "{:?}", import.notes);
    // Independently: split each line on commas, read landmark k at fields 1 + 2k and 2 + 2k,
    // and take sqrt(dx^2 + dy^2) between the atlas's landmark numbers (data/atlas/README.md).
    let chains: [(Finger, [usize; 5]); 5] = [
        (Finger::Thumb, [17, 18, 19, 20, usize::MAX]),
        (Finger::Index, [16, 21, 22, 23, 24]),
        (Finger::Middle, [15, 25, 26, 27, 28]),
        (Finger::Ring, [14, 29, 30, 31, 32]),
        (Finger::Little, [13, 33, 34, 35, 36]),
    ];
    let mut rows = import.rows.iter();
    let mut checked = 0;
    for line in text.lines() {
        let f: Vec<&str> = line.split(',').collect();
        let xy = |k: usize| -> (f64, f64) {
            (
                f[1 + 2 * k].trim().parse().unwrap(),
                f[2 + 2 * k].trim().parse().unwrap(),
            )
        };
        let d = |a: usize, b: usize| {
            let ((ax, ay), (bx, by)) = (xy(a), xy(b));
            ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)).sqrt()
        };
        for (finger, ch) in chains {
            let r = rows.next().expect("a row per finger");
            assert_eq!((&*r.image, r.finger), (f[0], finger));
            let n = finger.segments();
            for k in 0..n {
                let want = d(ch[1 + k], ch[2 + k]);
                assert!((r.lengths[k] - want).abs() <= 1e-9 * want, "{line}");
            }
            let mc = r.mc.expect("the atlas marks every CMC");
            assert!((mc - d(ch[0], ch[1])).abs() <= 1e-9 * mc);
            assert_eq!(r.side, Some(Side::Left));
            assert_eq!(r.tip, Some(TipKind::Bone));
            assert_eq!(&*r.unit, "px");
            checked += 1;
        }
    }
    assert_eq!(checked, 4550);
    // By hand, first line (image 3142): index MCP (21) = (711, 900), PIP (22) = (720, 559):
    // J1 = sqrt(9^2 + 341^2) = sqrt(116362) = 341.1187 (341.12^2 = 116362.85); DIP (23) =
    // (729, 349): J2 = sqrt(9^2 + 210^2) = sqrt(44181) = 210.1928; thumb CMC (17) = (738,
    // 1517), MCP (18) = (934, 1166): mc = sqrt(196^2 + 351^2) = sqrt(161617) = 402.0162.
    let r = &import.rows[1];
    assert_eq!((&*r.image, r.finger), ("3142", Finger::Index));
    assert!((r.lengths[0] - 341.1187).abs() < 1e-4 && (r.lengths[1] - 210.1928).abs() < 1e-4);
    assert!((import.rows[0].mc.unwrap() - 402.0162).abs() < 1e-4);
    // Last line (image 7293): thumb MCP (18) = (1023, 1104), IP (19) = (1089, 846):
    // J1 = sqrt(66^2 + 258^2) = sqrt(70920) = 266.3081; IP to tip (1149, 673):
    // J2 = sqrt(60^2 + 173^2) = sqrt(33529) = 183.1093.
    let r = &import.rows[909 * 5];
    assert_eq!((&*r.image, r.finger), ("7293", Finger::Thumb));
    assert!((r.lengths[0] - 266.3081).abs() < 1e-4 && (r.lengths[1] - 183.1093).abs() < 1e-4);
}

/// The first `n` lines of the atlas as (id, landmarks) pairs.
fn atlas_points(text: &str, n: usize) -> Vec<(String, Vec<(f64, f64)>)> {
    text.lines()
        .take(n)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let pts = (0..37)
                .map(|k| (f[1 + 2 * k].parse().unwrap(), f[2 + 2 * k].parse().unwrap()))
                .collect();
            (f[0].to_string(), pts)
        })
        .collect()
}

/// The atlas landmark number of a landmark (the wrist: the radius, landmark 0).
fn atlas_number(l: Landmark) -> usize {
    match l {
        Landmark::Wrist => 0,
        Landmark::Joint(f, j) => {
            let chain = atlas37::CHAINS[f.index()].1;
            chain[names::chain(f).iter().position(|&c| c == j).unwrap()]
        }
    }
}

/// Every landmark of the atlas's fingers with a name, in a scrambled order and mixed styles.
fn all_names() -> Vec<(Landmark, String)> {
    let mut v: Vec<(Landmark, String)> = Vec::new();
    for (i, f) in Finger::ALL.into_iter().enumerate() {
        for (k, &j) in names::chain(f).iter().enumerate() {
            let l = Landmark::Joint(f, j);
            let name = match (i + k) % 3 {
                0 => l.plain_name(),
                1 => l.plain_name().to_uppercase().replace('_', "-"),
                _ => format!("{} finger {}", f.name(), j.name()),
            };
            v.push((l, name));
        }
    }
    v.push((Landmark::Wrist, "WRIST".into()));
    v.reverse();
    v
}

#[test]
fn coco_and_long_files_give_the_atlas_rows_for_the_same_points() {
    let Some(text) = atlas_text() else { return };
    let hands = atlas_points(&text, 4);
    let four: String = text.lines().take(4).map(|l| format!("{l}\n")).collect();
    let atlas = ok(Layout::Atlas37, &four, &opts());
    assert_eq!(atlas.rows.len(), 20);
    let same = ImportOptions {
        side: Some(Side::Left),
        tip: Some(TipKind::Bone),
        ..opts()
    };
    // Long CSV: every landmark of the fingers (CMCs included), hands interleaved.
    let names = all_names();
    let mut long = String::from("image,landmark,x,y\n");
    for (l, name) in &names {
        for (id, pts) in &hands {
            let (x, y) = pts[atlas_number(*l)];
            long.push_str(&format!("{id},{name},{x},{y}\n"));
        }
    }
    assert_eq!(ok(Layout::Long, &long, &same).rows, atlas.rows);
    // COCO with the same names in a category.
    let images: Vec<_> = hands
        .iter()
        .enumerate()
        .map(|(i, (id, _))| json!({"id": 100 + i, "file_name": id}))
        .collect();
    let anns = |names: &[(Landmark, String)]| -> Vec<serde_json::Value> {
        hands
            .iter()
            .enumerate()
            .map(|(i, (_, pts))| {
                let kp: Vec<f64> = names
                    .iter()
                    .flat_map(|(l, _)| {
                        let (x, y) = pts[atlas_number(*l)];
                        [x, y, 2.0]
                    })
                    .collect();
                json!({"id": i, "image_id": 100 + i, "category_id": 1, "keypoints": kp})
            })
            .collect()
    };
    let named: Vec<&str> = names.iter().map(|(_, n)| n.as_str()).collect();
    let coco = json!({"images": images, "annotations": anns(&names),
        "categories": [{"id": 1, "name": "hand", "keypoints": named}]});
    assert_eq!(ok(Layout::Coco, &coco.to_string(), &same).rows, atlas.rows);
    // COCO without names: the standard 21-point order, whose only CMC is the thumb's.
    let standard: Vec<(Landmark, String)> = names::STANDARD_21
        .iter()
        .map(|l| (*l, String::new()))
        .collect();
    let coco = json!({"images": images, "annotations": anns(&standard),
        "categories": [{"id": 1, "name": "hand"}]});
    let rows = ok(Layout::Coco, &coco.to_string(), &same).rows;
    assert_eq!(rows.len(), atlas.rows.len());
    for (r, a) in rows.iter().zip(&atlas.rows) {
        let mc = if r.finger == Finger::Thumb {
            a.mc
        } else {
            None
        };
        assert_eq!(r, &LandmarkRow { mc, ..a.clone() });
    }
    // COCO-WholeBody: the same points as left hands, rows named IMAGE:left, side from the key.
    let wb: Vec<_> = anns(&standard)
        .into_iter()
        .map(|mut a| {
            let kp = a["keypoints"].take();
            json!({"image_id": a["image_id"], "category_id": 1, "keypoints": [1, 2, 2],
                "lefthand_kpts": kp, "righthand_kpts": vec![0; 63], "righthand_valid": false})
        })
        .collect();
    let coco = json!({"images": images, "annotations": wb,
        "categories": [{"id": 1, "name": "person", "keypoints": ["nose"]}]});
    let rows = ok(Layout::Coco, &coco.to_string(), &opts()).rows;
    assert_eq!(rows.len(), 20);
    for (r, a) in rows.iter().zip(&atlas.rows) {
        assert_eq!(*r.image, format!("{}:left", a.image));
        assert_eq!(
            (r.side, r.lengths, r.tip),
            (Some(Side::Left), a.lengths, None)
        );
    }
}

/// A long-layout hand: rows `image,name,x,y` for the given joints of the index finger and
/// a complete thumb, so each test changes one thing.
fn long_hand(image: &str, index: &[(&str, f64, f64)]) -> String {
    let mut s = String::new();
    for (name, x, y) in [
        ("thumb_mcp", 300.0, 600.0),
        ("thumb_ip", 330.0, 450.0),
        ("thumb_tip", 350.0, 350.0),
    ]
    .iter()
    .chain(index)
    {
        s.push_str(&format!("{image},{name},{x},{y}\n"));
    }
    s
}

const INDEX: [(&str, f64, f64); 4] = [
    ("index_mcp", 200.0, 600.0),
    ("index_pip", 200.0, 300.0),
    ("index_dip", 205.0, 120.0),
    ("index_tip", 208.0, 20.0),
];

fn long(hands: &[String]) -> String {
    format!("image,landmark,x,y\n{}", hands.concat())
}

#[test]
fn long_layout_measures_and_notes_missing_fingers() {
    let text = long(&[long_hand("a", &INDEX), long_hand("b", &[])]);
    let i = ok(Layout::Long, &text, &opts());
    assert_eq!(i.hands, 2);
    let got: Vec<(&str, Finger)> = i.rows.iter().map(|r| (&*r.image, r.finger)).collect();
    assert_eq!(
        got,
        [
            ("a", Finger::Thumb),
            ("a", Finger::Index),
            ("b", Finger::Thumb)
        ]
    );
    // Index of a: J1 = 300, J2 = sqrt(5^2 + 180^2), J3 = sqrt(3^2 + 100^2); no CMC, no mc.
    let r = &i.rows[1];
    assert_eq!(r.lengths[0], 300.0);
    assert!((r.lengths[1] - 180.069_431).abs() < 1e-6);
    assert!((r.lengths[2] - 100.044_990).abs() < 1e-6);
    assert_eq!((r.mc, r.side, r.tip, &*r.unit), (None, None, None, "px"));
    assert_eq!(i.notes.len(), 4, "{:?}", i.notes);
    assert!(i.notes[0].starts_with("index finger: not annotated in 1 image ('b')"));
    assert!(i.notes[3].starts_with("little finger: not annotated in 2 images ('a', 'b')"));
}

#[test]
fn options_scale_and_label_the_rows() {
    let text = long(&[long_hand("a", &INDEX)]);
    let o = ImportOptions {
        pixel_spacing: Some(0.1),
        source: Some("lab 3".into()),
        side: Some(Side::Right),
        tip: Some(TipKind::Skin),
        ..opts()
    };
    let i = ok(Layout::Long, &text, &o);
    let r = &i.rows[1];
    assert!((r.lengths[0] - 30.0).abs() < 1e-12);
    assert_eq!(&*r.unit, "mm");
    assert_eq!(r.source.as_deref(), Some("lab 3"));
    assert_eq!((r.side, r.tip), (Some(Side::Right), Some(TipKind::Skin)));
    let named = ImportOptions {
        unit: Some("image units".into()),
        ..opts()
    };
    assert_eq!(
        &*ok(Layout::Long, &text, &named).rows[0].unit,
        "image units"
    );
    for bad in [
        ImportOptions {
            pixel_spacing: Some(0.0),
            ..opts()
        },
        ImportOptions {
            pixel_spacing: Some(f64::NAN),
            ..opts()
        },
        ImportOptions {
            pixel_spacing: Some(0.1),
            unit: Some("mm".into()),
            ..opts()
        },
        ImportOptions {
            source: Some("=cmd()".into()),
            ..opts()
        },
    ] {
        assert!(bad.validate().is_err(), "{bad:?}");
        let e = import(Layout::Long, "in", text.as_bytes(), &bad).unwrap_err();
        assert_eq!(e.problems[0].line, None);
    }
}

#[test]
fn the_writer_puts_mc_after_j3_and_tip_last() {
    let Some(text) = atlas_text() else { return };
    let first: String = text.lines().take(1).collect();
    let i = ok(
        Layout::Atlas37,
        &first,
        &ImportOptions {
            source: Some("Digital Hand Atlas, Payer et al.".into()),
            ..opts()
        },
    );
    let mut out = Vec::new();
    write_csv(&i.rows, &mut out).unwrap();
    let out = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        "xray,finger,j1,j2,j3,mc,sex,age,side,source,unit,tip"
    );
    // Values from the hand computation in the atlas test above (6 decimals).
    assert_eq!(
        lines[1],
        "3142,thumb,278.454664,188.743212,,402.016169,,,left,\"Digital Hand Atlas, Payer et al.\",px,bone"
    );
    assert!(lines[2].starts_with("3142,index,341.118748,210.192769,144.013888,603.367218,"));
    assert_eq!(lines.len(), 6);
    assert!(!out.contains('\r'));
    assert_eq!(crate::format::measured(339.96), "339.96");
    assert_eq!(crate::format::measured(12.0), "12");
    assert_eq!(crate::format::measured(0.012_345_678_9), "0.01234568");
    assert_eq!(crate::format::measured(2.0 / 3.0), "0.6666667");
}

// ---- bad annotations: each named with its place ----

#[test]
fn a_missing_landmark_is_named_with_the_image_line() {
    let text = long(&[
        long_hand("a", &INDEX),
        long_hand("b", &[INDEX[0], INDEX[1], INDEX[3]]),
    ]);
    let p = problems(Layout::Long, &text);
    // Hand b starts on line 9 (header, 7 lines of a); its id is column 1.
    one(
        &p,
        Some(9),
        Some(1),
        "image",
        &[
            "image 'b'",
            "index DIP is missing",
            "MCP, PIP, tip",
            "'index_dip'",
        ],
    );
    // The atlas: an empty coordinate is a missing landmark, at its column.
    let Some(text) = atlas_text() else { return };
    let mut f: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    f[1 + 2 * 23] = "";
    let p = problems(Layout::Atlas37, &f.join(","));
    one(
        &p,
        Some(1),
        Some(48),
        "x23",
        &[
            "image '3142', landmark 23 (index DIP)",
            "x is empty",
            "missing",
        ],
    );
}

#[test]
fn a_duplicated_landmark_names_both_places() {
    let mut text = long(&[long_hand("a", &INDEX)]);
    text.push_str("a,INDEX_FINGER_PIP,1,2\n");
    let p = problems(Layout::Long, &text);
    one(
        &p,
        Some(9),
        Some(2),
        "landmark",
        &["image 'a'", "index PIP is given twice", "line 6"],
    );
    let coco = json!({"images": [{"id": 1}], "annotations": [],
        "categories": [{"id": 1, "keypoints": ["wrist", "index_pip", "Index-Finger-PIP"]}]})
    .to_string();
    // The category is only read when an annotation uses it.
    let mut v: serde_json::Value = serde_json::from_str(&coco).unwrap();
    v["annotations"] = json!([{"image_id": 1, "category_id": 1, "keypoints": vec![1; 9]}]);
    let p = problems(Layout::Coco, &v.to_string());
    one(
        &p,
        None,
        None,
        "categories[0].keypoints[2]",
        &[
            "'Index-Finger-PIP' names the index PIP again",
            "keypoints[1]",
        ],
    );
}

#[test]
fn non_finite_and_negative_coordinates() {
    let mut index = INDEX;
    index[2].1 = -5.0;
    let p = problems(Layout::Long, &long(&[long_hand("a", &index)]));
    one(
        &p,
        Some(7),
        Some(3),
        "x",
        &["image 'a', index DIP", "'-5' is negative"],
    );
    let text = long(&[long_hand("a", &INDEX)]).replace("208,20", "208,NaN");
    one(
        &problems(Layout::Long, &text),
        Some(8),
        Some(4),
        "y",
        &["index tip", "'NaN' is not a finite number"],
    );
    let text = long(&[long_hand("a", &INDEX)]).replace("208,20", "208,1e400");
    one(
        &problems(Layout::Long, &text),
        Some(8),
        Some(4),
        "y",
        &["'1e400' is not a finite number"],
    );
    // COCO: a string, a negative number, and null where numbers belong.
    let mut kp = standard_keypoints();
    kp[3 * 6] = json!("NaN");
    kp[3 * 7 + 1] = json!(-1.5);
    kp[3 * 8] = json!(null);
    let p = problems(Layout::Coco, &coco_one(kp).to_string());
    assert_eq!(p.len(), 3, "{p:#?}");
    let at: Vec<&str> = p.iter().map(|p| p.field.as_deref().unwrap()).collect();
    assert_eq!(
        at,
        [
            "annotations[0].keypoints[18]",
            "annotations[0].keypoints[22]",
            "annotations[0].keypoints[24]"
        ]
    );
    assert!(
        p[0].message.contains(
            "image 'x.png', keypoint 6 'index_pip' (index PIP): x is 'NaN', not a number"
        )
    );
    assert!(p[1].message.contains("y -1.5 is negative"));
    assert!(p[2].message.contains("x is null, not a number"));
}

/// A 21-point hand in the standard order (a plausible right hand, y down), visibility 2.
fn standard_keypoints() -> Vec<serde_json::Value> {
    let mut kp = Vec::new();
    let base = [(0.0, 0.0), (150.0, -50.0), (200.0, -150.0), (230.0, -250.0)];
    kp.extend([json!(500.0), json!(900.0), json!(2)]); // wrist
    for (i, &(bx, by)) in [(600.0, 850.0)]
        .iter()
        .chain(&[
            (560.0, 600.0),
            (500.0, 590.0),
            (440.0, 600.0),
            (380.0, 620.0),
        ])
        .enumerate()
    {
        let pts: Vec<(f64, f64)> = if i == 0 {
            base.iter().map(|&(x, y)| (bx + x, by + y)).collect()
        } else {
            (0..4).map(|k| (bx, by - 120.0 * k as f64)).collect()
        };
        for (x, y) in pts {
            kp.extend([json!(x), json!(y), json!(2)]);
        }
    }
    kp
}

fn coco_one(kp: Vec<serde_json::Value>) -> serde_json::Value {
    json!({"images": [{"id": 7, "file_name": "x.png"}],
        "annotations": [{"image_id": 7, "category_id": 1, "keypoints": kp}],
        "categories": [{"id": 1, "name": "hand"}]})
}

#[test]
fn the_standard_hand_imports_and_visibility_zero_leaves_a_finger_out() {
    let i = ok(
        Layout::Coco,
        &coco_one(standard_keypoints()).to_string(),
        &opts(),
    );
    assert_eq!(i.rows.len(), 5);
    assert_eq!(i.rows[1].lengths, [120.0, 120.0, 120.0]);
    // Thumb: CMC (600, 850), MCP (750, 800): mc = sqrt(150^2 + 50^2) = 158.1139.
    assert!((i.rows[0].mc.unwrap() - 158.113_883).abs() < 1e-6);
    let mut kp = standard_keypoints();
    kp[3 * 11 + 2] = json!(0); // middle DIP not labelled
    let i = ok(Layout::Coco, &coco_one(kp).to_string(), &opts());
    assert_eq!(i.rows.len(), 4);
    assert!(i.rows.iter().all(|r| r.finger != Finger::Middle));
    assert_eq!(
        i.notes,
        [
            "middle finger: not imported from 1 image where a joint is marked as not labelled ('x.png' at annotations[0].keypoints[33])"
        ]
    );
}

#[test]
fn a_repeated_image_id() {
    let Some(text) = atlas_text() else { return };
    let lines: Vec<&str> = text.lines().take(3).collect();
    let again = format!("{}\n{}\n{}\n{}\n", lines[0], lines[1], lines[2], lines[0]);
    one(
        &problems(Layout::Atlas37, &again),
        Some(4),
        Some(1),
        "image_id",
        &["image '3142' is repeated: line 1"],
    );
}

#[test]
fn a_repeated_coco_image_or_hand() {
    let mut v = coco_one(standard_keypoints());
    v["images"] = json!([{"id": 7, "file_name": "x.png"}, {"id": 7, "file_name": "y.png"}]);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "images[1].id",
        &["image id '7' is repeated: images[0]"],
    );
    let mut v = coco_one(standard_keypoints());
    let a = v["annotations"][0].clone();
    v["annotations"] = json!([a.clone(), a]);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "annotations[1]",
        &["image 'x.png' already has a hand in annotations[0]"],
    );
}

#[test]
fn two_joints_at_the_same_point() {
    let mut index = INDEX;
    index[2] = ("index_dip", 200.0, 300.0);
    one(
        &problems(Layout::Long, &long(&[long_hand("a", &index)])),
        Some(7),
        Some(2),
        "landmark",
        &[
            "image 'a': the index DIP ('index_dip') is at the same point (200, 300) as the index PIP ('index_pip')",
            "zero length",
        ],
    );
}

#[test]
fn joints_out_of_order() {
    // PIP and DIP swapped: the DIP is nearer the MCP than the PIP.
    let index = [
        INDEX[0],
        ("index_pip", 205.0, 120.0),
        ("index_dip", 200.0, 300.0),
        INDEX[3],
    ];
    one(
        &problems(Layout::Long, &long(&[long_hand("a", &index)])),
        Some(7),
        Some(2),
        "landmark",
        &[
            "the index DIP ('index_dip') is no farther from the index MCP (300.0 px) than the index PIP ('index_pip') is (480.0 px)",
            "swapped",
        ],
    );
    // Farther each time, but turning by 101 degrees at the PIP: (0, -100) then (100, 20).
    let index = [
        ("index_mcp", 200.0, 600.0),
        ("index_pip", 200.0, 500.0),
        ("index_dip", 300.0, 520.0),
        ("index_tip", 350.0, 540.0),
    ];
    one(
        &problems(Layout::Long, &long(&[long_hand("a", &index)])),
        Some(6),
        Some(2),
        "landmark",
        &[
            "the index finger folds back by 101 degrees at the index PIP ('index_pip') (between its MCP-PIP and PIP-DIP segments)",
        ],
    );
}

#[test]
fn a_finger_whose_segments_are_no_finger() {
    let index = [
        INDEX[0],
        ("index_pip", 200.0, 500.0),
        ("index_dip", 200.0, 20.0),
        ("index_tip", 200.0, 0.0),
    ];
    one(
        &problems(Layout::Long, &long(&[long_hand("a", &index)])),
        Some(2),
        Some(1),
        "image",
        &[
            "the index finger's segments (J1 = 100.0, J2 = 480.0, J3 = 20.0 px)",
            "J2 is 24.0 times J3",
        ],
    );
}

#[test]
fn unknown_keypoint_names() {
    let mut text = long(&[long_hand("a", &INDEX)]);
    text.push_str("a,index_pop,1,2\n");
    one(
        &problems(Layout::Long, &text),
        Some(9),
        Some(2),
        "landmark",
        &[
            "image 'a': unknown landmark 'index_pop'",
            "INDEX_FINGER_PIP",
        ],
    );
    let mut v = coco_one(standard_keypoints());
    let mut names: Vec<String> = names::STANDARD_21.iter().map(|l| l.plain_name()).collect();
    names[10] = "MIDDLE_FINGER_PIPP".into();
    v["categories"][0]["keypoints"] = json!(names);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "categories[0].keypoints[10]",
        &["unknown keypoint name 'MIDDLE_FINGER_PIPP'"],
    );
}

#[test]
fn coco_annotations_that_point_at_nothing() {
    let mut v = coco_one(standard_keypoints());
    let mut a = v["annotations"][0].clone();
    a["image_id"] = json!(8);
    v["annotations"] = json!([v["annotations"][0].clone(), a.clone()]);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "annotations[1].image_id",
        &["8 points at no image"],
    );
    a["image_id"] = json!(7);
    a["category_id"] = json!(2);
    v["annotations"] = json!([a]);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "annotations[0].category_id",
        &["2 points at no category"],
    );
}

#[test]
fn coco_structure_problems() {
    let p = problems(Layout::Coco, "{\"images\": [}");
    assert_eq!((p[0].line, p[0].column), (Some(1), Some(13)), "{p:#?}");
    assert!(p[0].message.starts_with("is not valid JSON"));
    let p = problems(Layout::Coco, "[1, 2]");
    assert!(p[0].message.contains("top level must be an object"));
    let mut v = coco_one(standard_keypoints());
    v["annotations"][0]["keypoints"] = json!([1, 2, 2]);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "annotations[0].keypoints",
        &["has 3 numbers", "63 expected"],
    );
    // A category naming some joints of a finger but not all.
    let mut v = coco_one(standard_keypoints()[..60].to_vec());
    let names: Vec<String> = names::STANDARD_21[..20]
        .iter()
        .map(|l| l.plain_name())
        .collect();
    v["categories"][0]["keypoints"] = json!(names);
    one(
        &problems(Layout::Coco, &v.to_string()),
        None,
        None,
        "categories[0].keypoints",
        &["some joints of the little finger but not 'little_tip'"],
    );
}

#[test]
fn every_problem_of_a_file_together() {
    let Some(text) = atlas_text() else { return };
    let mut lines: Vec<String> = text.lines().take(5).map(String::from).collect();
    let mut f: Vec<&str> = lines[1].split(',').collect();
    f[1 + 2 * 30] = "-1";
    lines[1] = f.join(",");
    lines[3] = lines[3].replacen(',', ",x,", 1);
    lines.push(lines[0].clone());
    let p = problems(Layout::Atlas37, &lines.join("\n"));
    let at: Vec<(Option<u64>, Option<usize>)> = p.iter().map(|p| (p.line, p.column)).collect();
    assert_eq!(
        at,
        [(Some(2), Some(62)), (Some(4), None), (Some(6), Some(1))]
    );
    assert!(p[1].message.starts_with("has 76 fields"));
    let shown = DataError {
        file: "atlas.csv".into(),
        problems: p,
    }
    .to_string();
    assert!(
        shown.contains(
            "atlas.csv:2:62: x30: image '3143', landmark 30 (ring PIP): x '-1' is negative"
        ),
        "{shown}"
    );
}

#[test]
fn nothing_importable_is_a_problem() {
    let p = problems(Layout::Long, "image,landmark,x,y\na,wrist,1,2\n");
    assert!(
        p[0].message
            .starts_with("has no hand with a complete finger (1 hand read)")
    );
    let p = problems(Layout::Long, "");
    assert!(p[0].message.starts_with("is empty"));
    let p = problems(Layout::Long, "image,landmark,x\n");
    assert!(p[0].message.contains("lacks the required column 'y'"));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// No input makes the importer panic: it returns rows or problems.
    #[test]
    fn any_input_gives_rows_or_problems(
        text in "[\\[\\]{}\":,0-9a-z_. -]{0,200}",
        cut in 0usize..400,
    ) {
        for layout in Layout::ALL {
            let _ = import(layout, "in", text.as_bytes(), &opts());
        }
        // Truncated and perturbed valid files of each layout.
        let coco = coco_one(standard_keypoints()).to_string();
        let long_text = long(&[long_hand("a", &INDEX)]);
        for (layout, full) in [(Layout::Coco, coco), (Layout::Long, long_text)] {
            let k = cut.min(full.len());
            let mut bytes = full.as_bytes()[..k].to_vec();
            bytes.extend_from_slice(text.as_bytes());
            bytes.extend_from_slice(&full.as_bytes()[k..]);
            let _ = import(layout, "in", &bytes, &opts());
        }
    }
}
