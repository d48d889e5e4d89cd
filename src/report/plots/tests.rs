//! Tests of the plots on the paper's data and on synthetic extremes.

use super::*;
use crate::analysis::placement::place_all;
use crate::analysis::{
    DatasetInfo, Quantity, Segments, Settings, XrayValues, analyse, quantity_stats,
};
use crate::dataset::{Dataset, Finger};
use crate::stats::bootstrap::Plan;
use crate::stats::describe;
use std::path::Path;
use std::sync::Arc;

const SCRIPT: &str = "<script>alert(1)</script>";

fn paper_csv() -> String {
    std::fs::read_to_string("data/measurements.csv").unwrap()
}

fn paper() -> Analysis {
    let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
    analyse(&d, &Settings::default())
}

fn analysis_of(csv: &str) -> Analysis {
    let d = Dataset::from_bytes("test.csv", csv.as_bytes()).unwrap();
    analyse(&d, &Settings::default())
}

fn count(svg: &str, needle: &str) -> usize {
    svg.matches(needle).count()
}

/// Checks that `svg` is well-formed XML as far as the SVG backend can produce
/// it: tags nest and close, `&` only starts an entity, no stray `<` or `>`.
fn assert_well_formed(svg: &str) {
    let mut stack: Vec<&str> = Vec::new();
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        assert_text(&rest[..start]);
        let end = rest[start..].find('>').expect("unclosed tag") + start;
        let tag = &rest[start + 1..end];
        assert!(!tag.contains('<'), "'<' inside a tag: {tag}");
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop(), Some(name), "mismatched </{name}>");
        } else if !tag.ends_with('/') {
            stack.push(tag.split_whitespace().next().unwrap());
        }
        assert_attributes(tag);
        rest = &rest[end + 1..];
    }
    assert_text(rest);
    assert!(stack.is_empty(), "unclosed elements: {stack:?}");
}

/// Text content: no `>` and only known entities.
fn assert_text(text: &str) {
    assert!(!text.contains('>'), "stray '>' in {text:?}");
    for (i, _) in text.match_indices('&') {
        let entity = &text[i..];
        assert!(
            ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
                .iter()
                .any(|e| entity.starts_with(e)),
            "bad entity at {entity:?}"
        );
    }
}

/// Attribute values are quoted and carry no raw `"` or `&`.
fn assert_attributes(tag: &str) {
    assert_eq!(count(tag, "\"") % 2, 0, "unbalanced quotes in {tag}");
    for value in tag.split('"').skip(1).step_by(2) {
        assert_text(value);
    }
}

/// The accessibility contract: root `role="img"` labelled by a first-child
/// `<title>` and `<desc>` whose ids start with the plot id.
fn assert_accessible(p: &Plot) {
    let svg = &p.svg;
    assert!(svg.starts_with("<svg "), "{}", &svg[..40]);
    assert!(svg.trim_end().ends_with("</svg>"));
    assert_well_formed(svg);
    let root_end = svg.find('>').unwrap();
    let root = &svg[..root_end];
    assert!(root.contains(" role=\"img\""));
    assert!(root.contains(&format!(" aria-labelledby=\"{}-title\"", p.id)));
    assert!(root.contains(&format!(" aria-describedby=\"{}-desc\"", p.id)));
    assert_eq!(count(svg, "<title"), 1);
    assert_eq!(count(svg, "<desc"), 1);
    let after = svg[root_end + 1..].trim_start();
    let title = format!("<title id=\"{}-title\">", p.id);
    assert!(after.starts_with(&title), "title is not the first child");
    let after_title = after[after.find("</title>").unwrap() + 8..].trim_start();
    assert!(after_title.starts_with(&format!("<desc id=\"{}-desc\">", p.id)));
    assert!(!p.title.is_empty() && !p.description.is_empty());
}

#[test]
fn every_plot_of_the_paper_is_accessible_well_formed_svg() {
    let a = paper();
    let plots = all(&a, &place_all(&a, 1000.0)).unwrap();
    let ids: Vec<&str> = plots.iter().map(|p| p.id.as_str()).collect();
    assert_eq!(
        ids,
        [
            "finger-thumb",
            "finger-index",
            "finger-middle",
            "finger-ring",
            "finger-little",
            "hand",
            "forest"
        ]
    );
    for p in &plots {
        assert_accessible(p);
        // The title is drawn in the picture as well.
        assert!(p.svg.contains(&draw::escape(&p.title)), "{}", p.id);
        assert!(p.svg.len() < 100_000, "{} is {} bytes", p.id, p.svg.len());
    }
    let kinds: Vec<PlotKind> = plots.iter().map(|p| p.kind).collect();
    assert_eq!(kinds[0], PlotKind::Finger);
    assert_eq!(kinds[5..], [PlotKind::Hand, PlotKind::Forest]);
}

#[test]
fn finger_plot_has_one_marker_per_xray_and_quantity() {
    let a = paper();
    for f in &a.fingers {
        let p = finger_plot(f, 0.95).unwrap();
        let quantities = if f.finger == Finger::Thumb { 2 } else { 3 };
        // One circle per X-ray and quantity, and the legend's.
        assert_eq!(count(&p.svg, "<circle"), f.n * quantities + 1, "{}", p.id);
        // Every X-ray's id labels its point in every panel.
        assert_eq!(count(&p.svg, "\n1a\n</text>"), quantities);
        for label in [
            "J~1 = J1/J: relative value (fraction of the finger&apos;s total length J, unitless)",
            "J~2 = J2/J: relative value",
            "X-rays\n</text>",
            "n = 5 X-rays.",
            "t CI\n",
            "percentile CI\n",
            "BCa CI\n",
            "prediction\n",
            "one X-ray",
            "mean",
            "95% CI of the mean (Student t)",
            "95% CI (bootstrap percentile)",
            "95% CI (bootstrap BCa)",
            "95% prediction interval (one new X-ray)",
        ] {
            assert!(p.svg.contains(label), "{} lacks {label:?}", p.id);
        }
        let has_j3 = p.svg.contains("J~3 = J3/J: relative value");
        assert_eq!(has_j3, f.finger != Finger::Thumb);
    }
}

#[test]
fn finger_plot_describes_every_value_and_interval() {
    let a = paper();
    let p = finger_plot(a.finger(Finger::Index).unwrap(), 0.95).unwrap();
    assert_eq!(p.id, "finger-index");
    assert!(
        p.title
            .contains("index finger (the paper's 'grooming' finger)")
    );
    for text in [
        "J~1 = J1/J: mean 0.4846",
        "1d: J~1 0.5047",
        "BCa CI [",
        "from 5 X-rays",
    ] {
        assert!(p.description.contains(text), "{text}");
    }
    // The plain-text description is escaped once inside the SVG.
    assert!(
        p.svg
            .contains("the paper&apos;s &apos;grooming&apos; finger")
    );
    assert!(!p.svg.contains("&amp;apos;"));
}

#[test]
fn hand_diagram_marks_every_joint_with_range_and_prediction() {
    let a = paper();
    let p = hand_diagram(&place_all(&a, 1000.0), 0.95).unwrap();
    assert_eq!((p.id.as_str(), p.kind), ("hand", PlotKind::Hand));
    // One mean diamond per inner joint (1 thumb + 4 x 2), and the legend's.
    assert_eq!(count(&p.svg, "<polygon"), 9 + 1);
    // Root and tip of five fingers, and the legend's joint.
    assert_eq!(count(&p.svg, "<circle"), 10 + 1);
    // The worked example: index PIP at 484.6 of 1000.
    for label in [
        "PIP 484.6",
        "IP ",
        "DIP ",
        "MCP\n",
        "tip\n",
        "distance from the root joint MCP (model units)",
        "finger (each drawn at the model length L = 1000)",
        "root (MCP) and tip",
        "mean joint position",
        "observed range (min to max)",
        "95% prediction interval (one new hand)",
        "Joint positions on a model hand (L = 1000 model units)",
    ] {
        assert!(p.svg.contains(label), "lacks {label:?}");
    }
    for finger in ["thumb", "index", "middle", "ring", "little"] {
        assert!(p.svg.contains(&format!("\n{finger}\n</text>")), "{finger}");
    }
    assert!(
        p.description
            .contains("index (5 X-rays): PIP at mean 484.6 (observed 472.8 to 504.7")
    );
}

#[test]
fn forest_plot_has_a_row_per_relative_quantity() {
    let a = paper();
    let p = forest_plot(&a).unwrap();
    assert_eq!((p.id.as_str(), p.kind), ("forest", PlotKind::Forest));
    // 2 thumb rows + 4 x 3: one mean diamond each, and the legend's.
    assert_eq!(count(&p.svg, "<polygon"), 14 + 1);
    for label in [
        "thumb J~1",
        "thumb J~2",
        "index J~3",
        "little J~3",
        "relative value J~k = Jk/J (fraction of the finger&apos;s total length J, unitless)",
        "finger and segment",
        "95% CI (bootstrap BCa)",
        "95% prediction interval (one new X-ray)",
    ] {
        assert!(p.svg.contains(label), "lacks {label:?}");
    }
    assert!(!p.svg.contains("thumb J~3"));
    assert!(p.description.contains("index J~1 = J1/J: mean 0.4846"));
}

#[test]
fn rig_plot_marks_every_rig_value_against_the_xray_ratios() {
    let a = paper();
    let rigs = vec![
        RigRatios {
            name: "Circle rig".into(),
            values: vec![
                (Finger::Index, Quantity::RatioJ2J1, 0.5),
                (Finger::Thumb, Quantity::RatioJ2J1, 0.9),
            ],
        },
        RigRatios {
            name: "Square <rig>".into(),
            values: vec![
                (Finger::Little, Quantity::RatioJ3J2, 1.0),
                (Finger::Ring, Quantity::RatioJ2J1, f64::NAN),
            ],
        },
    ];
    let p = rigs_plot(&a, &rigs).unwrap();
    assert_eq!((p.id.as_str(), p.kind), ("rigs", PlotKind::Rigs));
    assert_accessible(&p);
    assert_well_formed(&p.svg);
    // Thumb J2/J1 and four fingers x 2 ratios: 9 rows, each a mean diamond (the
    // legend adds one); circles: the first rig's 2 values and its legend swatch;
    // squares cannot be told from the range bands by tag, so count the rows' labels.
    assert_eq!(count(&p.svg, "<circle"), 2 + 1);
    assert_eq!(count(&p.svg, "<polygon"), 9 + 1);
    for label in [
        "thumb J2/J1",
        "index J3/J2",
        "little J3/J2",
        "ratio of adjacent segment lengths (unitless)",
    ] {
        assert!(p.svg.contains(label), "lacks {label:?}");
    }
    assert!(!p.svg.contains("thumb J3/J2"));
    assert!(p.svg.contains("Square &lt;rig&gt;"));
    assert!(p.description.contains("index J2/J1: X-ray mean 0.563"));
    assert!(p.description.contains("Circle rig 0.5"));
    // A non-finite value is left out, not drawn.
    assert!(!p.description.contains("NaN"));
}

#[test]
fn user_text_is_escaped_exactly_once() {
    let csv = paper_csv()
        .replace("\n1a,", &format!("\n{SCRIPT},"))
        .replace("\n1b,", "\n\"O'Brien & \"\"Co\"\"\",");
    let a = analysis_of(&csv);
    let plots = all(&a, &place_all(&a, 1000.0)).unwrap();
    for p in &plots {
        assert_accessible(p);
        assert!(!p.svg.contains("<script"), "{}", p.id);
        assert!(!p.svg.contains("&amp;lt;") && !p.svg.contains("&amp;amp;"));
    }
    let index = &plots[1];
    assert!(index.description.contains(SCRIPT));
    // Whole in the description, clipped in the point labels.
    assert!(index.svg.contains("&lt;script&gt;alert(1)&lt;/script&gt;"));
    assert!(
        index
            .svg
            .contains("\n&lt;script&gt;alert(1\u{2026}\n</text>")
    );
    assert!(index.svg.contains("O&apos;Brien &amp; &quot;Co&quot;"));
}

#[test]
fn renders_are_byte_identical() {
    let render = || {
        let a = paper();
        let p = all(&a, &place_all(&a, 1000.0)).unwrap();
        p.into_iter().map(|p| p.svg).collect::<Vec<_>>()
    };
    assert_eq!(render(), render());
}

/// A middle finger of `n` synthetic X-rays, without running the bootstrap.
fn synthetic(n: usize) -> FingerAnalysis {
    let xrays: Vec<XrayValues> = (0..n)
        .map(|i| {
            let t = i as f64;
            let lengths = vec![
                40.0 + 3.0 * (0.37 * t).sin(),
                25.0 + 2.0 * (0.71 * t).cos(),
                20.0 + (1.13 * t).sin(),
            ];
            let total: f64 = lengths.iter().sum();
            XrayValues {
                xray: Arc::from(format!("x{i}")),
                relative: Segments::new(&lengths.iter().map(|l| l / total).collect::<Vec<_>>()),
                lengths: Segments::new(&lengths),
                total,
                mc: None,
                unit: None,
            }
        })
        .collect();
    let settings = Settings::default();
    let quantities = Quantity::of(Finger::Middle)
        .iter()
        .map(|&q| {
            let values: Vec<f64> = xrays.iter().filter_map(|x| x.value(q)).collect();
            // A stand-in bootstrap distribution: means of 64 interleaved subsamples.
            let boot: Vec<f64> = (0..64)
                .map(|k| {
                    let sub: Vec<f64> = values.iter().skip(k).step_by(64).copied().collect();
                    describe::mean(&sub).unwrap_or(0.0)
                })
                .collect();
            quantity_stats(q, &values, Some((&boot, &[1.0 / 64.0; 64])), &settings)
        })
        .collect();
    FingerAnalysis {
        finger: Finger::Middle,
        n,
        xrays,
        quantities,
        bootstrap: Plan::Random { resamples: 64 },
    }
}

#[test]
fn a_hundred_thousand_xrays_give_a_small_histogram() {
    let f = synthetic(100_000);
    let p = finger_plot(&f, 0.95).unwrap();
    assert_accessible(&p);
    assert!(p.svg.len() < 200_000, "{} bytes", p.svg.len());
    // Binned: no point of its own but the few worth naming (thousands lie outside the
    // prediction interval; each panel names the farthest NAMED_MAX) and their legend entry.
    assert_eq!(count(&p.svg, "<circle"), 3 * finger::NAMED_MAX + 1);
    assert!(p.svg.contains("X-rays per bin (histogram)"));
    assert!(p.svg.contains("n = 100000 X-rays."));
    assert!(!p.description.contains("x99999"));
    assert_eq!(p.svg, finger_plot(&f, 0.95).unwrap().svg);
}

#[test]
fn points_are_drawn_one_by_one_up_to_the_limit() {
    let f = synthetic(finger::POINTS_MAX);
    let p = finger_plot(&f, 0.9).unwrap();
    assert_accessible(&p);
    // Every point once (a named one drawn as such), the legend's point and named entry.
    assert_eq!(count(&p.svg, "<circle"), 3 * finger::POINTS_MAX + 2);
    assert!(p.svg.len() < 1_000_000, "{} bytes", p.svg.len());
    assert!(p.svg.contains("90% CI (bootstrap BCa)"));
    // Past the labelled limit, only the X-rays worth naming carry their ids: here those
    // outside the prediction interval, at most NAMED_MAX per panel.
    let ids = (0..finger::POINTS_MAX)
        .filter(|i| p.svg.contains(&format!("\nx{i}\n</text>")))
        .count();
    assert!((1..=3 * finger::NAMED_MAX).contains(&ids), "{ids} ids");
    assert!(
        p.svg
            .contains("named: flagged, outside the prediction interval, or newest")
    );
}

#[test]
fn a_single_xray_draws_without_intervals() {
    let csv = "xray,finger,j1,j2,j3\nonly,index,40,25,20\nonly,thumb,30,25,\n";
    let a = analysis_of(csv);
    let plots = all(&a, &place_all(&a, 50.0)).unwrap();
    assert_eq!(plots.len(), 4);
    for p in &plots {
        assert_accessible(p);
    }
    assert!(plots[0].svg.contains("not available (1 X-ray)"));
    assert!(plots[2].svg.contains("L = 50 model units"));
    assert!(plots[3].svg.contains("no intervals (1 X-ray)"));
    assert!(plots[0].description.contains("from 1 X-ray."));
}

#[test]
fn empty_and_non_finite_inputs_render_without_panicking() {
    let hand = hand_diagram(&[], 0.95).unwrap();
    assert_accessible(&hand);
    assert!(hand.svg.contains("no finger in the data"));
    let mut a = paper();
    a.fingers.clear();
    a.dataset = DatasetInfo {
        xrays: 0,
        rows: 0,
        ..a.dataset
    };
    let forest = forest_plot(&a).unwrap();
    assert_accessible(&forest);
    assert!(forest.svg.contains("no finger in the data"));
    let mut f = synthetic(20);
    f.xrays[3].relative[0] = f64::NAN;
    f.quantities[0].mean = f64::INFINITY;
    f.quantities[1].intervals.ci_t = None;
    let p = finger_plot(&f, 0.95).unwrap();
    assert_accessible(&p);
}

#[test]
fn escape_handles_every_special_character() {
    assert_eq!(
        draw::escape("a<b>&\"c\"'d'\u{1}"),
        "a&lt;b&gt;&amp;&quot;c&quot;&apos;d&apos; "
    );
    assert_eq!(crate::format::level(0.95), "95%");
    assert_eq!(crate::format::level(0.975), "97.5%");
    assert_eq!(crate::format::trimmed(1000.0, 4), "1000");
    assert_eq!(draw::clip("abcdef", 4), "abc\u{2026}");
}

// ---- Tracking plot ----

/// A snapshot as `(number of X-rays, mean, interval)`; snapshots numbered from 1.
type Snapshot = (usize, f64, Option<(f64, f64)>);

/// A series from its snapshots.
fn track(label: &str, points: &[Snapshot]) -> TrackSeries {
    TrackSeries {
        label: label.to_string(),
        points: points
            .iter()
            .enumerate()
            .map(|(i, &(xrays, mean, ci))| TrackPoint {
                snapshot: i + 1,
                removal: false,
                flagged: 0,
                xrays,
                mean,
                ci,
            })
            .collect(),
    }
}

/// Index-finger history: ties at 5 X-rays, a snapshot without an interval.
fn index_history() -> Vec<TrackSeries> {
    vec![
        track(
            "J~1 = J1/J",
            &[
                (3, 0.4800, Some((0.4600, 0.5000))),
                (5, 0.4850, Some((0.4700, 0.5000))),
                (5, 0.4820, Some((0.4720, 0.4920))),
                (8, 0.4840, None),
                (10, 0.4846, Some((0.4728, 0.4964))),
            ],
        ),
        track(
            "J~2 = J2/J",
            &[
                (3, 0.2900, Some((0.2700, 0.3100))),
                (5, 0.2870, Some((0.2750, 0.2990))),
                (8, 0.2880, Some((0.2800, 0.2960))),
                (10, 0.2875, Some((0.2810, 0.2940))),
            ],
        ),
        track("J~3 = J3/J", &[(10, 0.2279, Some((0.2201, 0.2357)))]),
    ]
}

#[test]
fn tracking_plot_draws_every_snapshot() {
    let p = tracking_plot(Finger::Index, &index_history(), 0.95).unwrap();
    assert_eq!(
        (p.id.as_str(), p.kind),
        ("tracking-index", PlotKind::Tracking)
    );
    assert_accessible(&p);
    assert!(p.svg.contains(&draw::escape(&p.title)));
    // One diamond per snapshot (5 + 4 + 1, ties included), the legend's, and one
    // band per run of two or more neighbouring intervals (J~1 at 3..5, J~2).
    assert_eq!(count(&p.svg, "<polygon"), 10 + 1 + 2);
    for label in [
        "snapshot (record of the history, in order)",
        "removal (rows taken out)",
        "flagged rows added",
        "fraction of total length J",
        "\nmean\n</text>",
        "95% t confidence interval",
        "J~1 = J1/J",
        "J~3 = J3/J",
        "5 snapshots, 3 to 10 X-rays, 1 without an interval",
        "\n5\n</text>",
    ] {
        assert!(p.svg.contains(label), "lacks {label:?}");
    }
    assert!(!p.svg.contains("no snapshots yet"));
    for text in [
        "J~1 = J1/J: 5 snapshots; first at snapshot 1 (3 X-rays): mean 0.4800, 95% t confidence \
         interval from 0.4600 to 0.5000; last at snapshot 5 (10 X-rays): mean 0.4846, 95% t \
         confidence interval from 0.4728 to 0.4964.",
        "J~3 = J3/J: 1 snapshot at snapshot 1 (10 X-rays): mean 0.2279",
        "the index finger (the paper's 'grooming' finger)",
    ] {
        assert!(p.description.contains(text), "{text}");
    }
    let again = tracking_plot(Finger::Index, &index_history(), 0.95).unwrap();
    assert_eq!(p.svg, again.svg);
    let p90 = tracking_plot(Finger::Index, &index_history(), 0.9).unwrap();
    assert!(p90.svg.contains("90% t confidence interval"));
}

#[test]
fn tracking_plot_draws_one_point_and_empty_series() {
    let series = [
        track("J~1 = J1/J", &[(1, 0.55, None)]),
        track("J~2 = J2/J", &[]),
    ];
    let p = tracking_plot(Finger::Thumb, &series, 0.95).unwrap();
    assert_eq!(p.id, "tracking-thumb");
    assert_accessible(&p);
    assert_eq!(count(&p.svg, "<polygon"), 1 + 1);
    assert_eq!(count(&p.svg, "\nno snapshots yet\n</text>"), 1);
    assert!(p.svg.contains("1 snapshot, 1 X-ray, 1 without an interval"));
    assert!(p.description.contains(
        "J~1 = J1/J: 1 snapshot at snapshot 1 (1 X-ray): mean 0.5500, no confidence interval."
    ));
    assert!(p.description.contains("J~2 = J2/J: no snapshots yet."));

    for series in [Vec::new(), vec![track("J~1", &[]), track("J~2", &[])]] {
        let p = tracking_plot(Finger::Ring, &series, 0.95).unwrap();
        assert_accessible(&p);
        assert!(p.svg.contains("\nno snapshots yet\n</text>"));
        // Only the legend's diamond.
        assert_eq!(count(&p.svg, "<polygon"), 1);
    }
    let none = tracking_plot(Finger::Ring, &[], 0.95).unwrap();
    assert!(none.description.ends_with("No snapshots yet."));

    // Non-finite values are left out, never drawn at a bogus pixel.
    let odd = [track(
        "J~1",
        &[
            (2, f64::NAN, None),
            (3, 0.5, Some((f64::NEG_INFINITY, 0.6))),
            (3, 0.51, Some((0.52, 0.49))),
        ],
    )];
    let p = tracking_plot(Finger::Middle, &odd, 0.95).unwrap();
    assert_accessible(&p);
    assert_eq!(count(&p.svg, "<polygon"), 2 + 1);
}

#[test]
fn tracking_labels_are_escaped_exactly_once() {
    let series = [track(
        SCRIPT,
        &[(4, 0.3, Some((0.2, 0.4))), (6, 0.31, None)],
    )];
    let p = tracking_plot(Finger::Little, &series, 0.95).unwrap();
    assert_accessible(&p);
    assert!(!p.svg.contains("<script"));
    assert!(!p.svg.contains("&amp;lt;"));
    assert!(p.description.contains(SCRIPT));
    // In the panel heading and in the description.
    assert_eq!(count(&p.svg, "&lt;script&gt;alert(1)&lt;/script&gt;"), 2);
}

#[test]
fn beyond_a_dozen_only_the_xrays_worth_naming_are_labelled() {
    let f = synthetic(30);
    // Without names: only X-rays outside a prediction interval (none in this smooth set).
    let plain = finger::plot(&f, 0.95, &Named::default()).unwrap();
    let labelled = |svg: &str| -> Vec<usize> {
        (0..30)
            .filter(|i| svg.contains(&format!("\n{}\n</text>", format_args!("x{i}"))))
            .collect()
    };
    let outside: Vec<usize> = (0..30)
        .filter(|&i| {
            f.quantities
                .iter()
                .filter(|q| q.name.is_relative())
                .any(|q| {
                    let k = match q.name {
                        Quantity::RelJ1 => 0,
                        Quantity::RelJ2 => 1,
                        _ => 2,
                    };
                    q.intervals
                        .pi
                        .is_some_and(|pi| !pi.contains(f.xrays[i].relative[k]))
                })
        })
        .collect();
    assert_eq!(labelled(&plain.svg), outside);
    // A flagged row and a small newest batch are named in every panel, highlighted.
    let named = Named {
        flagged: vec![("x3".to_string(), Finger::Middle)],
        newest: vec!["x5".to_string(), "x6".to_string()],
    };
    let p = finger::plot(&f, 0.95, &named).unwrap();
    let mut expect = outside.clone();
    expect.extend([3, 5, 6]);
    expect.sort_unstable();
    expect.dedup();
    assert_eq!(labelled(&p.svg), expect);
    assert!(
        p.svg
            .contains("named: flagged, outside the prediction interval, or newest")
    );
    assert!(
        p.description.contains("Named in the J~1 panel: "),
        "{}",
        p.description
    );
    // A flag of another finger names nothing here; a large newest batch is not named.
    let other = Named {
        flagged: vec![("x3".to_string(), Finger::Index)],
        newest: (0..10).map(|i| format!("x{i}")).collect(),
    };
    assert_eq!(
        labelled(&finger::plot(&f, 0.95, &other).unwrap().svg),
        outside
    );
}

#[test]
fn tracking_runs_against_the_snapshot_number_with_removals_and_flags_marked() {
    use crate::analysis::{analyse, tracking};
    use crate::dataset::history::{ChangeRecord, Event, FlaggedRow};
    let full = Dataset::load(Path::new("data/measurements.csv")).unwrap();
    let mut less = full.clone();
    let last = less.rows.last().unwrap().xray.clone();
    less.rows.retain(|r| r.xray != last);
    let s = Settings {
        resamples: 200,
        ..Settings::default()
    };
    let (a_full, a_less) = (analyse(&full, &s), analyse(&less, &s));
    let mut added = tracking::snapshot(&a_full, "t1".into(), Event::Add);
    added.change = Some(ChangeRecord {
        file: None,
        xrays: vec![last.to_string()],
        rows: 5,
        flagged: vec![FlaggedRow {
            xray: last.to_string(),
            finger: Finger::Index,
            reason: "typo".into(),
        }],
    });
    let history = vec![
        tracking::snapshot(&a_less, "t0".into(), Event::Snapshot),
        added.clone(),
        tracking::snapshot(&a_less, "t2".into(), Event::Remove),
        added,
    ];
    let series = track_series(&history, Finger::Index);
    assert_eq!(series.len(), 3, "J~1, J~2, J~3");
    let p = &series[0].points;
    // x is the snapshot number: 1, 2, 3, 4, though the X-rays go 4, 5, 4, 5.
    let xs: Vec<(usize, usize)> = p.iter().map(|p| (p.snapshot, p.xrays)).collect();
    assert_eq!(xs, [(1, 4), (2, 5), (3, 4), (4, 5)]);
    let marks: Vec<(bool, usize)> = p.iter().map(|p| (p.removal, p.flagged)).collect();
    assert_eq!(marks, [(false, 0), (false, 1), (true, 0), (false, 1)]);
    // The thumb had no flagged row.
    assert!(
        track_series(&history, Finger::Thumb)[0]
            .points
            .iter()
            .all(|p| p.flagged == 0)
    );
    let plot = tracking_plot(Finger::Index, &series, 0.95).unwrap();
    for label in [
        "snapshot (record of the history, in order)",
        "4 snapshots, 4 to 5 X-rays, 1 with a removal, 2 adding flagged rows",
        "removal (rows taken out)",
    ] {
        assert!(plot.svg.contains(label), "lacks {label:?}");
    }
    assert!(
        plot.description
            .contains("at snapshot 4 (5 X-rays, adding flagged rows)")
    );
    assert!(!plot.svg.contains("number of X-rays"));
}
