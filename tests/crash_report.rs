//! A `phalanx report` killed (SIGKILL) at random moments never leaves a torn file:
//! every report file is, each on its own, the previous or the new complete version.

use crate::common;

use common::*;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    for sub in ["", "plots"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().to_string();
            if e.path().is_file() && !name.starts_with(".phalanx-") {
                out.insert(format!("{sub}/{name}"), std::fs::read(e.path()).unwrap());
            }
        }
    }
    out
}

#[test]
#[ignore = "slow: 30 reports killed at random moments (run by .ci/run)"]
fn a_killed_report_leaves_each_file_old_or_new() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let bin = assert_cmd::cargo::cargo_bin("phalanx");
    let report = |out: &str, length: &str| {
        let mut c = std::process::Command::new(&bin);
        c.current_dir(wd.path())
            .args([
                "report",
                "--out",
                out,
                // A small coverage simulation keeps each report short, so the 30 kills
                // are spread over a run whose writing is a larger share of it.
                "--sims",
                "200",
                "--model-length",
                length,
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null());
        c
    };
    // The two complete versions: model length 1000 (old) and 2000 (new).
    assert!(report("old", "1000").output().unwrap().status.success());
    assert!(report("new", "2000").output().unwrap().status.success());
    let (old, new) = (files(&wd.path().join("old")), files(&wd.path().join("new")));
    assert_ne!(old["/index.html"], new["/index.html"]);
    let t0 = Instant::now();
    assert!(report("timing", "2000").output().unwrap().status.success());
    let full = t0.elapsed().max(Duration::from_millis(5));

    let mut lcg: u64 = 0x9E37_79B9;
    let (mut saw_old, mut saw_new) = (0, 0);
    for round in 0..30 {
        // Start each round from the old report.
        let site = wd.path().join("site");
        let _ = std::fs::remove_dir_all(&site);
        std::fs::create_dir_all(site.join("plots")).unwrap();
        for (name, bytes) in &old {
            std::fs::write(site.join(name.trim_start_matches('/')), bytes).unwrap();
        }
        lcg = lcg
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let delay = full.mul_f64((lcg >> 11) as f64 / (1u64 << 53) as f64 * 1.2);
        let mut child = report("site", "2000").spawn().unwrap();
        std::thread::sleep(delay);
        let _ = child.kill();
        let _ = child.wait();
        let now = files(&site);
        for (name, bytes) in &now {
            let is_old = old.get(name) == Some(bytes);
            let is_new = new.get(name) == Some(bytes);
            assert!(
                is_old || is_new,
                "round {round}: {name} is neither version (torn)"
            );
            if is_new {
                saw_new += 1;
            } else {
                saw_old += 1;
            }
        }
        // Nothing of the old report went missing.
        for name in old.keys() {
            assert!(now.contains_key(name), "round {round}: {name} disappeared");
        }
    }
    assert!(saw_old > 0, "every kill came too late to test anything");
    eprintln!("files seen old: {saw_old}, new: {saw_new}");
}
