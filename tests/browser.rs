//! The committed report (`reports/index.html`) as a browser renders it.
//!
//! The other report tests look at the HTML text; this one asks headless
//! Chromium what a reader actually sees. The report has no JavaScript, so the
//! test copies it into a temporary directory, injects a small probe script
//! before `</body>`, loads the copy with `chromium --dump-dom` in a 1366 px wide
//! window and reads the probe's JSON summary back out of the dumped DOM. The
//! probe first opens every collapsed part (`<details>`), so what is checked is
//! what a reader sees once they open it:
//!
//! * the committed report itself has no `<script>`;
//! * at least 15 tables, each with a non-empty caption, a body row, non-zero
//!   size, not hidden (`display`, `visibility`, `checkVisibility()`), and
//!   inside the document's scroll area (a table wider than the page must
//!   scroll inside its `.table-wrap`);
//! * every `figure svg` visible, at least 200 px wide and with a `<title>`,
//!   and at least one visible plot of each kind (`plot-finger-*`,
//!   `plot-hand`, `plot-forest`);
//! * every `figure img` (the deformation figure, a PNG data URI) decoded,
//!   visible, at least 200 px wide and with alt text, and one `plot-deform-*`;
//! * a visible `<h1>`;
//! * no horizontal scrolling of the page at 1366 px
//!   (`document.body.scrollWidth` and the root's `scrollWidth` are at most
//!   `window.innerWidth`).
//!
//! The browser is `$PHALANX_CHROMIUM`, else `chromium`, `chromium-browser` or
//! `google-chrome` on `PATH`. Without one the test says why on stderr and
//! passes (`.ci/run` installs the Debian package `chromium`). Chromium is
//! killed if it runs longer than [`TIMEOUT`]. Starting it takes seconds, so a
//! plain `cargo test` skips the test and `.ci/run` runs it
//! (`cargo test -- --ignored`).

use scraper::{Html, Selector};
use serde_json::Value;
use std::ffi::OsStr;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long Chromium may take before it is killed and the test fails.
const TIMEOUT: Duration = Duration::from_secs(60);
/// The window: a common laptop screen.
const WINDOW_WIDTH: f64 = 1366.0;
const WINDOW_HEIGHT: f64 = 900.0;
/// The report has this many tables (Table 1, derived values, statistics,
/// claims, joint placement, coverage); fewer means one went missing.
const MIN_TABLES: usize = 15;
/// The kinds of plot, by the start of their figure id.
const PLOT_KINDS: [&str; 3] = ["plot-finger-", "plot-hand", "plot-forest"];
/// The WebXR hand's deformation figure (a PNG data URI), by the start of its id.
const DEFORM_FIGURE: &str = "plot-deform-";
/// The id of the `<pre>` the probe writes its JSON into.
const RESULT_ID: &str = "phalanx-test-result";
/// A plot narrower than this (CSS pixels) is unreadable.
const MIN_PLOT_WIDTH: f64 = 200.0;
/// Browser names looked up on `PATH`, in order.
const BROWSER_NAMES: [&str; 3] = ["chromium", "chromium-browser", "google-chrome"];
/// Rounding slack for layout comparisons, in CSS pixels.
const SLACK: f64 = 1.0;

/// Measures the page once it has loaded and appends the JSON summary in a
/// hidden `<pre id="phalanx-test-result">` (after measuring, so the `<pre>`
/// cannot change what is measured).
const PROBE: &str = r#"<script>
window.addEventListener('load', function () {
  var out = {};
  try {
    var de = document.documentElement;
    var all = function (sel, root) { return Array.prototype.slice.call((root || document).querySelectorAll(sel)); };
    out.details = all('details').length;
    all('details').forEach(function (d) { d.open = true; });
    var box = function (el) {
      var r = el.getBoundingClientRect();
      var s = getComputedStyle(el);
      return {
        left: r.left + window.scrollX, top: r.top + window.scrollY,
        width: r.width, height: r.height,
        display: s.display, visibility: s.visibility,
        checkVisibility: typeof el.checkVisibility === 'function'
          ? el.checkVisibility({ opacityProperty: true, visibilityProperty: true }) : null
      };
    };
    out.innerWidth = window.innerWidth;
    out.innerHeight = window.innerHeight;
    out.docScrollWidth = de.scrollWidth;
    out.docScrollHeight = de.scrollHeight;
    out.bodyScrollWidth = document.body.scrollWidth;
    out.h1 = all('h1').map(function (h) { var b = box(h); b.text = h.textContent.trim(); return b; });
    out.tables = all('table').map(function (t) {
      var b = box(t);
      var cap = t.querySelector('caption');
      b.caption = cap ? cap.textContent.trim() : null;
      b.captionHeight = cap ? cap.getBoundingClientRect().height : 0;
      b.rows = t.querySelectorAll('tbody tr').length;
      var w = t.parentElement ? t.parentElement.closest('.table-wrap') : null;
      if (w) {
        var wb = box(w);
        wb.overflowX = getComputedStyle(w).overflowX;
        wb.scrollWidth = w.scrollWidth;
        wb.clientWidth = w.clientWidth;
        b.wrap = wb;
      } else {
        b.wrap = null;
      }
      return b;
    });
    out.svgs = all('figure svg').map(function (s) {
      var b = box(s);
      var f = s.closest('figure');
      b.figure = f ? f.id : '';
      var t = s.querySelector('title');
      b.title = t ? t.textContent.trim() : null;
      return b;
    });
    out.imgs = all('figure img').map(function (i) {
      var b = box(i);
      var f = i.closest('figure');
      b.figure = f ? f.id : '';
      b.alt = i.getAttribute('alt') || '';
      b.naturalWidth = i.naturalWidth;
      b.complete = i.complete;
      return b;
    });
  } catch (e) {
    out.error = String((e && e.stack) || e);
  }
  var pre = document.createElement('pre');
  pre.id = 'phalanx-test-result';
  pre.hidden = true;
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"#;

/// Whether `path` is a file we may execute.
fn is_executable(path: &Path) -> bool {
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    if !meta.is_file() {
        return false;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        meta.permissions().mode() & 0o111 != 0
    }
    #[cfg(not(unix))]
    {
        true
    }
}

/// `name` looked up in the directories of `path` (a `PATH`-style list).
fn on_path(name: &str, path: Option<&OsStr>) -> Option<PathBuf> {
    std::env::split_paths(path?)
        .map(|dir| dir.join(name))
        .find(|p| is_executable(p))
}

/// The browser to use, or why there is none: `explicit` (the value of
/// `PHALANX_CHROMIUM`) when set, as a path or a command on `path`, and nothing
/// when it names no executable; else the first of [`BROWSER_NAMES`] on `path`.
fn find_browser(explicit: Option<&OsStr>, path: Option<&OsStr>) -> Result<PathBuf, String> {
    if let Some(var) = explicit.filter(|v| !v.is_empty()) {
        let given = PathBuf::from(var);
        let found = if given.components().count() > 1 {
            Some(given.clone()).filter(|p| is_executable(p))
        } else {
            on_path(&given.to_string_lossy(), path)
        };
        return found.ok_or_else(|| {
            format!(
                "PHALANX_CHROMIUM={} is not an executable file or a command on PATH",
                given.display()
            )
        });
    }
    BROWSER_NAMES
        .iter()
        .find_map(|name| on_path(name, path))
        .ok_or_else(|| format!("none of {} on PATH", BROWSER_NAMES.join(", ")))
}

/// A `file://` URL for an absolute path, percent-encoding what needs it.
fn file_url(path: &Path) -> String {
    let mut url = String::from("file://");
    for &b in path.to_string_lossy().as_bytes() {
        if b.is_ascii_alphanumeric() || b"/-_.~".contains(&b) {
            url.push(b as char);
        } else {
            url.push_str(&format!("%{b:02X}"));
        }
    }
    url
}

/// The last lines of Chromium's stderr, for failure messages.
fn tail(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(20)..].join("\n")
}

/// Runs `browser --dump-dom` on `page` and returns the dumped DOM.
fn dump_dom(browser: &Path, page: &Path, work: &Path) -> String {
    let profile = work.join("profile");
    std::fs::create_dir(&profile).expect("create the browser profile directory");
    let out_path = work.join("dom.html");
    let err_path = work.join("stderr.txt");
    let mut cmd = Command::new(browser);
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        "--virtual-time-budget=5000",
    ])
    .arg(format!("--user-data-dir={}", profile.display()))
    .arg(format!("--window-size={WINDOW_WIDTH},{WINDOW_HEIGHT}"))
    .arg("--dump-dom")
    .arg(file_url(page))
    .stdin(Stdio::null())
    .stdout(File::create(&out_path).expect("create the DOM file"))
    .stderr(File::create(&err_path).expect("create the stderr file"));
    // Own process group, so a timeout can kill the renderer and helpers too.
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    let mut child = cmd
        .spawn()
        .unwrap_or_else(|e| panic!("could not start {}: {e}", browser.display()));
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if started.elapsed() < TIMEOUT => {
                std::thread::sleep(Duration::from_millis(50))
            }
            Ok(None) => {
                #[cfg(unix)]
                let _ = Command::new("kill")
                    .args(["-KILL", "--", &format!("-{}", child.id())])
                    .stderr(Stdio::null())
                    .status();
                let _ = child.kill();
                let _ = child.wait();
                panic!(
                    "{} did not finish within {TIMEOUT:?} and was killed; its stderr ends:\n{}",
                    browser.display(),
                    tail(&err_path)
                );
            }
            Err(e) => panic!("waiting for {}: {e}", browser.display()),
        }
    };
    assert!(
        status.success(),
        "{} exited with {status}; its stderr ends:\n{}",
        browser.display(),
        tail(&err_path)
    );
    let dom = std::fs::read_to_string(&out_path).expect("read the dumped DOM");
    assert!(
        !dom.trim().is_empty(),
        "{} dumped no DOM; its stderr ends:\n{}",
        browser.display(),
        tail(&err_path)
    );
    dom
}

/// The probe's JSON from the dumped DOM.
fn probe_result(dom: &str) -> Value {
    let doc = Html::parse_document(dom);
    let sel = Selector::parse(&format!("pre#{RESULT_ID}")).expect("selector");
    let pre = doc.select(&sel).next().unwrap_or_else(|| {
        panic!("no <pre id=\"{RESULT_ID}\"> in the dumped DOM: the probe script did not run")
    });
    let text: String = pre.text().collect();
    let v: Value = serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("the probe's output is not JSON ({e}): {text}"));
    if let Some(err) = v.get("error") {
        panic!("the probe script failed: {err}");
    }
    v
}

fn num(v: &Value, key: &str) -> f64 {
    v.get(key)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("probe output has no number {key:?}: {v}"))
}

fn text<'a>(v: &'a Value, key: &str) -> &'a str {
    v.get(key).and_then(Value::as_str).unwrap_or("")
}

fn list<'a>(v: &'a Value, key: &str) -> &'a [Value] {
    v.get(key)
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or_else(|| panic!("probe output has no list {key:?}"))
}

/// Why a measured element is not visible, if it is not.
fn invisibility(b: &Value) -> Option<String> {
    let (w, h) = (num(b, "width"), num(b, "height"));
    if w <= 0.0 || h <= 0.0 {
        return Some(format!("has size {w} x {h} px"));
    }
    if text(b, "display") == "none" {
        return Some("has display: none".into());
    }
    let visibility = text(b, "visibility");
    if visibility == "hidden" || visibility == "collapse" {
        return Some(format!("has visibility: {visibility}"));
    }
    if b.get("checkVisibility") == Some(&Value::Bool(false)) {
        return Some("is not rendered (checkVisibility() is false)".into());
    }
    None
}

/// Why the box `b` lies outside the document's scroll area, if it does.
/// `horizontal` says whether to check the left and right edges too.
fn outside(b: &Value, page: &Value, horizontal: bool) -> Option<String> {
    let (left, top) = (num(b, "left"), num(b, "top"));
    let (right, bottom) = (left + num(b, "width"), top + num(b, "height"));
    let (sw, sh) = (num(page, "docScrollWidth"), num(page, "docScrollHeight"));
    if top < -SLACK || bottom > sh + SLACK {
        return Some(format!(
            "spans y {top:.0}..{bottom:.0} px outside the document's height {sh} px"
        ));
    }
    if horizontal && (left < -SLACK || right > sw + SLACK) {
        return Some(format!(
            "spans x {left:.0}..{right:.0} px outside the document's width {sw} px"
        ));
    }
    None
}

/// Every way the measured page falls short, as readable lines.
fn problems(page: &Value) -> Vec<String> {
    let mut bad = Vec::new();

    let inner = num(page, "innerWidth");
    if (inner - WINDOW_WIDTH).abs() > SLACK {
        bad.push(format!(
            "the window is {inner} px wide, not {WINDOW_WIDTH}: the width checks mean nothing"
        ));
    }
    for key in ["bodyScrollWidth", "docScrollWidth"] {
        let w = num(page, key);
        if w > inner {
            bad.push(format!(
                "the page scrolls sideways at {inner} px: {key} is {w} px"
            ));
        }
    }

    let h1s = list(page, "h1");
    if !h1s
        .iter()
        .any(|h| invisibility(h).is_none() && !text(h, "text").is_empty())
    {
        bad.push(format!("no visible, non-empty <h1> (found {})", h1s.len()));
    }

    let tables = list(page, "tables");
    if tables.len() < MIN_TABLES {
        bad.push(format!(
            "{} tables rendered, expected at least {MIN_TABLES}",
            tables.len()
        ));
    }
    for (i, t) in tables.iter().enumerate() {
        let caption = text(t, "caption");
        let name = format!("table {} ({caption:?})", i + 1);
        if caption.is_empty() {
            bad.push(format!("{name} has no caption text"));
        } else if num(t, "captionHeight") <= 0.0 {
            bad.push(format!("{name}: its caption has zero height"));
        }
        if num(t, "rows") < 1.0 {
            bad.push(format!("{name} has no body rows"));
        }
        if let Some(why) = invisibility(t) {
            bad.push(format!("{name} {why}"));
        }
        // A table may be wider than the page only if its wrapper scrolls.
        let wrap = t.get("wrap").filter(|w| !w.is_null());
        let scrolls = wrap.is_some_and(|w| matches!(text(w, "overflowX"), "auto" | "scroll"));
        if let Some(why) = outside(t, page, !scrolls) {
            bad.push(format!("{name} {why}"));
        }
        if let Some(w) = wrap.filter(|_| scrolls) {
            if let Some(why) = invisibility(w) {
                bad.push(format!("{name}: its .table-wrap {why}"));
            }
            if let Some(why) = outside(w, page, true) {
                bad.push(format!("{name}: its .table-wrap {why}"));
            }
        }
    }

    let svgs = list(page, "svgs");
    for s in svgs {
        let name = format!("the SVG in figure #{}", text(s, "figure"));
        if text(s, "title").is_empty() {
            bad.push(format!("{name} has no <title>"));
        }
        if let Some(why) = invisibility(s) {
            bad.push(format!("{name} {why}"));
        } else if num(s, "width") < MIN_PLOT_WIDTH {
            bad.push(format!(
                "{name} is only {} px wide, less than {MIN_PLOT_WIDTH}",
                num(s, "width")
            ));
        }
        if let Some(why) = outside(s, page, true) {
            bad.push(format!("{name} {why}"));
        }
    }
    let imgs = list(page, "imgs");
    for i in imgs {
        let name = format!("the image in figure #{}", text(i, "figure"));
        if text(i, "alt").is_empty() {
            bad.push(format!("{name} has no alt text"));
        }
        // A data URI that does not decode leaves naturalWidth at 0.
        if num(i, "naturalWidth") <= 0.0 {
            bad.push(format!("{name} did not decode (naturalWidth 0)"));
        }
        if let Some(why) = invisibility(i) {
            bad.push(format!("{name} {why}"));
        } else if num(i, "width") < MIN_PLOT_WIDTH {
            bad.push(format!(
                "{name} is only {} px wide, less than {MIN_PLOT_WIDTH}",
                num(i, "width")
            ));
        }
        if let Some(why) = outside(i, page, true) {
            bad.push(format!("{name} {why}"));
        }
    }
    if !imgs
        .iter()
        .any(|i| text(i, "figure").starts_with(DEFORM_FIGURE) && invisibility(i).is_none())
    {
        bad.push(format!("no visible image in a figure #{DEFORM_FIGURE}*"));
    }
    for kind in PLOT_KINDS {
        let visible = svgs
            .iter()
            .filter(|s| text(s, "figure").starts_with(kind))
            .filter(|s| invisibility(s).is_none())
            .count();
        if visible == 0 {
            bad.push(format!("no visible plot in a figure #{kind}*"));
        }
    }
    bad
}

#[test]
#[ignore = "slow: starts headless Chromium (run by .ci/run, which installs it)"]
fn report_renders_in_chromium() {
    let explicit = std::env::var_os("PHALANX_CHROMIUM");
    let path = std::env::var_os("PATH");
    let browser = match find_browser(explicit.as_deref(), path.as_deref()) {
        Ok(b) => b,
        Err(why) => {
            crate::common::skip(format!(
                "no Chromium found ({why}); .ci/run installs the Debian package chromium"
            ));
            return;
        }
    };
    let started = Instant::now();
    let report = Path::new(env!("CARGO_MANIFEST_DIR")).join("reports/index.html");
    let html = std::fs::read_to_string(&report)
        .unwrap_or_else(|e| panic!("read {}: {e}", report.display()));
    assert!(
        !html.to_ascii_lowercase().contains("<script"),
        "reports/index.html must work without scripts, but it has a <script>"
    );
    let at = html
        .rfind("</body>")
        .expect("reports/index.html has no </body>");
    let probed = format!("{}{PROBE}{}", &html[..at], &html[at..]);

    let work = tempfile::tempdir().expect("create a temporary directory");
    let page = work.path().join("index.html");
    std::fs::write(&page, probed).expect("write the probed copy of the report");

    let dom = dump_dom(&browser, &page, work.path());
    let result = probe_result(&dom);
    let bad = problems(&result);
    assert!(
        bad.is_empty(),
        "reports/index.html in {} at {WINDOW_WIDTH} px:\n  {}\nmeasurements: {result}",
        browser.display(),
        bad.join("\n  ")
    );
    eprintln!(
        "browser: {} tables and {} plots visible; body {} px and page {} px wide in a {} px window; {:.1?} with {}",
        list(&result, "tables").len(),
        list(&result, "svgs").len(),
        num(&result, "bodyScrollWidth"),
        num(&result, "docScrollWidth"),
        num(&result, "innerWidth"),
        started.elapsed(),
        browser.display()
    );
}

#[test]
fn a_browser_that_is_not_there_means_skip() {
    let dir = tempfile::tempdir().expect("create a temporary directory");
    let bin = dir.path().join("chromium");
    std::fs::write(&bin, "#!/bin/sh\n").expect("write a fake browser");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&bin, std::fs::Permissions::from_mode(0o755))
            .expect("make the fake browser executable");
    }
    let path = Some(dir.path().as_os_str());
    // Without the variable, PATH is searched.
    assert_eq!(find_browser(None, path), Ok(bin.clone()));
    assert!(find_browser(None, Some(OsStr::new("/nonexistent"))).is_err());
    assert!(find_browser(None, None).is_err());
    // An empty variable counts as unset.
    assert_eq!(find_browser(Some(OsStr::new("")), path), Ok(bin.clone()));
    // A path to nothing is "no browser", even when PATH has one.
    let missing = find_browser(Some(OsStr::new("/nonexistent/chromium")), path);
    assert!(
        missing
            .as_ref()
            .is_err_and(|why| why.contains("/nonexistent/chromium")),
        "{missing:?}"
    );
    // So is a directory; a bare name is looked up on PATH.
    assert!(find_browser(Some(dir.path().as_os_str()), path).is_err());
    assert_eq!(find_browser(Some(OsStr::new("chromium")), path), Ok(bin));
}
