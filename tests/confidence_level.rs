//! A confidence level reads the same in every output: the report (Markdown,
//! HTML, every plot), the terminal tables of `stats`, `place`, `coverage` and
//! `audit`. At 0.9999 that is "99.99%", never "100.0%" or "100%".

use crate::common;

use common::*;

const LEVEL: &str = "0.9999";
const SHOWN: &str = "99.99%";

/// `text` without the part from `start` to `end` (both markers must be there).
fn without(text: &str, start: &str, end: &str) -> String {
    let a = text.find(start).unwrap_or_else(|| panic!("no {start:?}"));
    let b = a + text[a..].find(end).unwrap_or_else(|| panic!("no {end:?}"));
    format!("{}{}", &text[..a], &text[b..])
}

/// Fails when `text` shows a level of 100% (with or without a decimal).
fn assert_no_hundred(text: &str, what: &str) {
    for bad in ["100.0%", "100%"] {
        assert!(!text.contains(bad), "{what} shows {bad}:\n{text}");
    }
}

#[test]
fn a_level_of_0_9999_reads_99_99_percent_everywhere() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let rigs = manifest_dir().join("data/rigs");
    let rigs = rigs.to_str().unwrap();
    // Two snapshots (a snapshot of unchanged data and settings writes nothing, so the
    // second has another seed), so the report has its tracking plots too.
    for seed in ["1", "2"] {
        wd.run(&["snapshot", "-q", "--confidence", LEVEL, "--seed", seed])
            .ok();
    }
    wd.run(&[
        "report",
        "-q",
        "--out",
        "out",
        "--confidence",
        LEVEL,
        "--sims",
        "200",
        "--rigs",
        rigs,
    ])
    .ok();

    // The coverage section (8) shows simulated coverages, which may well be
    // 100.0% at this level, and the key results quote them and shares of a
    // finger's length; everywhere else a 100 would be the level misprinted.
    let md = String::from_utf8(wd.read("out/report.md")).unwrap();
    assert!(md.contains(&format!("nominal {SHOWN}")), "{md}");
    assert!(md.matches(SHOWN).count() >= 10, "{md}");
    let md_rest = without(&md, "## 8. ", "## 9. ");
    let md_rest = without(&md_rest, "> ## Key results", "**Contents:**");
    // The joint region's calibration shows simulated rates too.
    // (The rigs' section follows the methods, numbered by the sections present.)
    let md_rest = without(
        &md_rest,
        "- **Joint region of a rig's finger**",
        ". Popular rigs against the X-rays\n",
    );
    assert!(md_rest.contains(&format!("the {SHOWN} Student-t")), "{md}");
    assert!(
        md_rest.contains(&format!("| Confidence | `{SHOWN}` |")),
        "{md}"
    );
    assert_no_hundred(&md_rest, "report.md");

    let html = String::from_utf8(wd.read("out/index.html")).unwrap();
    assert!(html.matches(SHOWN).count() >= 10);
    // (The style sheet's "max-width: 100%" is no level.)
    let html_rest = without(&html, "<h2>8. ", "<h2>9. ");
    let html_rest = without(&html_rest, "id=\"key-results\"", "<nav");
    let html_rest = without(
        &html_rest,
        "<strong>Joint region of a rig's finger</strong>",
        ". Popular rigs against the X-rays</h2>",
    );
    assert_no_hundred(&without(&html_rest, "<style>", "</style>"), "index.html");

    let plots: Vec<_> = std::fs::read_dir(wd.path().join("out/plots"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    // 5 fingers, hand, forest, rigs, coverage, 5 tracking plots.
    assert_eq!(plots.len(), 14, "{plots:?}");
    for p in &plots {
        let svg = std::fs::read_to_string(p).unwrap();
        assert!(svg.contains(SHOWN), "{} lacks {SHOWN}", p.display());
        // The coverage plot's axis runs to 100% coverage, as section 9 may.
        if !p.ends_with("coverage.svg") {
            assert_no_hundred(&svg, &p.display().to_string());
        }
    }

    // The terminal tables.
    let stats = wd.run(&["stats", "--confidence", LEVEL]);
    let header = stats.ok().stdout.lines().next().unwrap().to_string();
    assert!(
        header.contains(&format!("confidence {SHOWN}, seed")),
        "{header}"
    );
    assert_no_hundred(&stats.stdout, "stats");
    let place = wd.run(&[
        "place",
        "--finger",
        "index",
        "--length",
        "1000",
        "--confidence",
        LEVEL,
    ]);
    place.ok().stdout_has(&format!("t CI {SHOWN}"));
    assert_no_hundred(&place.stdout, "place");
    let coverage = wd.run(&["coverage", "--sims", "50", "--confidence", LEVEL]);
    coverage
        .ok()
        .stdout_has(&format!("nominal {SHOWN} intervals"));
    let first = coverage.stdout.lines().next().unwrap_or("");
    assert_no_hundred(first, "coverage heading");
    let glb = manifest_dir().join("docs/examples/hand.glb");
    let audit = wd.run(&[
        "audit",
        "--explain",
        glb.to_str().unwrap(),
        "--confidence",
        LEVEL,
        "--wide",
    ]);
    audit
        .ok()
        .stdout_has(&format!("{SHOWN} prediction intervals"))
        .stdout_has(&format!("prediction {SHOWN}"));
    assert_no_hundred(&audit.stdout, "audit");
}

#[test]
fn the_default_level_reads_95_percent_in_the_terminal_as_in_the_report() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let stats = wd.run(&["stats"]);
    let header = stats.ok().stdout.lines().next().unwrap().to_string();
    assert!(header.contains("confidence 95%, seed"), "{header}");
    wd.run(&["place", "--finger", "index", "--length", "1000"])
        .ok()
        .stdout_has("t CI 95% ");
}
