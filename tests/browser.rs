//! Opens the published report (`reports/index.html`) in headless Chromium and checks,
//! from the rendered page, that every table and plot is there and visible.
//!
//! The report has no script of its own; the test copies it and appends one that
//! measures the rendered elements into a `<pre>`, then reads Chromium's
//! `--dump-dom`. Skipped, with the reason printed, when no browser is found
//! (`.ci/run` installs Debian's `chromium`).

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Measures the page after layout and writes a JSON summary into the DOM.
const PROBE: &str = r#"<script>
window.addEventListener('load', () => {
  const visible = (el) => {
    const r = el.getBoundingClientRect();
    const s = getComputedStyle(el);
    return r.width > 0 && r.height > 0 && s.display !== 'none' && s.visibility !== 'hidden'
      && r.bottom > 0 && r.top < document.documentElement.scrollHeight;
  };
  const tables = [...document.querySelectorAll('table')].map((t) => ({
    id: t.id,
    visible: visible(t),
    caption: (t.querySelector('caption') || {}).textContent || '',
    rows: t.querySelectorAll('tbody tr').length,
  }));
  const plots = [...document.querySelectorAll('figure')].map((f) => {
    const svg = f.querySelector('svg');
    return {
      id: f.id,
      visible: !!svg && visible(svg),
      title: svg && svg.querySelector('title') ? svg.querySelector('title').textContent : '',
      width: svg ? svg.getBoundingClientRect().width : 0,
    };
  });
  const out = document.createElement('pre');
  out.id = 'phalanx-test-result';
  out.textContent = JSON.stringify({
    tables, plots,
    h1: (document.querySelector('h1') || {}).textContent || '',
    bodyScrollWidth: document.body.scrollWidth,
    innerWidth: window.innerWidth,
  });
  document.body.appendChild(out);
});
</script>"#;

/// The browser to use: `PHALANX_CHROMIUM`, else the first of the usual names on PATH.
fn browser() -> Option<PathBuf> {
    find_browser(
        std::env::var_os("PHALANX_CHROMIUM"),
        std::env::var_os("PATH"),
    )
}

/// `explicit` when it names a file (and nothing when it names none), else a search of `path`.
fn find_browser(
    explicit: Option<std::ffi::OsString>,
    path: Option<std::ffi::OsString>,
) -> Option<PathBuf> {
    if let Some(p) = explicit {
        let p = PathBuf::from(p);
        return p.is_file().then_some(p);
    }
    let path = path?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |d| d.join(name)))
        .find(|p| p.is_file())
}

/// Runs the browser on `page` and returns the dumped DOM, killing it after 60 s.
fn dump_dom(browser: &Path, page: &Path, profile: &Path) -> Result<String, String> {
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--window-size=1366,900",
            "--virtual-time-budget=5000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", page.display()))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", browser.display()))?;
    let stdout = child.stdout.take().ok_or("no stdout")?;
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut std::io::BufReader::new(stdout), &mut s);
        s
    });
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if start.elapsed() > Duration::from_secs(60) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err("the browser did not finish within 60 s".into());
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => return Err(e.to_string()),
        }
    }
    reader
        .join()
        .map_err(|_| "reader thread failed".to_string())
}

#[test]
fn the_rendered_report_shows_every_table_and_plot() {
    let Some(browser) = browser() else {
        eprintln!(
            "skipped: no Chromium found (set PHALANX_CHROMIUM or install the Debian package chromium; .ci/run installs it)"
        );
        return;
    };
    let report = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports/index.html");
    let html = std::fs::read_to_string(&report).expect("reports/index.html is committed");
    assert!(
        !html.contains("<script"),
        "the published report must need no script"
    );
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("index.html");
    let probed = html.replacen("</body>", &format!("{PROBE}</body>"), 1);
    std::fs::write(&page, probed).unwrap();
    let profile = dir.path().join("profile");
    let dom = match dump_dom(&browser, &page, &profile) {
        Ok(dom) => dom,
        Err(e) => panic!("{e}"),
    };
    let start = dom
        .find("<pre id=\"phalanx-test-result\">")
        .expect("the probe wrote its result")
        + "<pre id=\"phalanx-test-result\">".len();
    let end = start + dom[start..].find("</pre>").expect("end of the result");
    let text = dom[start..end]
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    let v: Value = serde_json::from_str(&text).expect("probe JSON");

    assert!(v["h1"].as_str().unwrap().contains("phalanx"), "{}", v["h1"]);
    let tables = v["tables"].as_array().unwrap();
    assert!(tables.len() >= 15, "{} tables", tables.len());
    for t in tables {
        assert_eq!(t["visible"], true, "table {} not visible", t["id"]);
        assert!(
            !t["caption"].as_str().unwrap().trim().is_empty(),
            "table {} has no caption",
            t["id"]
        );
        assert!(
            t["rows"].as_u64().unwrap() >= 1,
            "table {} is empty",
            t["id"]
        );
    }
    let plots = v["plots"].as_array().unwrap();
    for prefix in ["plot-finger-", "plot-hand", "plot-forest"] {
        let found: Vec<&Value> = plots
            .iter()
            .filter(|p| p["id"].as_str().unwrap().starts_with(prefix))
            .collect();
        assert!(!found.is_empty(), "no plot {prefix}*");
        for p in found {
            assert_eq!(p["visible"], true, "plot {} not visible", p["id"]);
            assert!(
                !p["title"].as_str().unwrap().is_empty(),
                "plot {} has no <title>",
                p["id"]
            );
            assert!(
                p["width"].as_f64().unwrap() > 200.0,
                "plot {} too small",
                p["id"]
            );
        }
    }
    // Fits a laptop screen: wide tables scroll inside their own box, the page does not.
    let (scroll, inner) = (
        v["bodyScrollWidth"].as_f64().unwrap(),
        v["innerWidth"].as_f64().unwrap(),
    );
    assert!(
        scroll <= inner,
        "the page scrolls sideways: {scroll} > {inner}"
    );
}

#[test]
fn a_browser_that_is_not_there_means_skip() {
    let dir = tempfile::tempdir().unwrap();
    // An explicit path to nothing is "no browser", even when PATH has one.
    let fake = dir.path().join("chromium");
    std::fs::write(&fake, "").unwrap();
    let path = Some(dir.path().as_os_str().to_owned());
    assert_eq!(
        find_browser(Some("/nonexistent/chromium".into()), path.clone()),
        None
    );
    // Without the variable, PATH is searched.
    assert_eq!(find_browser(None, path), Some(fake));
    assert_eq!(
        find_browser(None, Some(std::ffi::OsString::from("/nonexistent"))),
        None
    );
}
