//! Command-line options through the binary: exit codes of good and bad option
//! values for every command, and the help texts.

use crate::common;

use common::*;

const COMMANDS: [&str; 3] = ["stats", "check", "coverage"];

#[test]
fn every_command_succeeds_on_the_shipped_data() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    for args in [
        &["stats"][..],
        &["stats", "--format", "json"],
        &["stats", "--format", "csv"],
        &["check"],
        &["check", "--format", "json"],
        &["coverage", "--sims", "50"],
        &["coverage", "--sims", "50", "--format", "json"],
    ] {
        let run = wd.run(args);
        run.ok();
        assert!(!run.stdout.is_empty(), "{args:?}: no output");
        assert!(run.stderr.is_empty(), "{args:?}: {}", run.stderr);
    }
}

#[test]
fn bad_option_values_exit_2_for_every_command_that_takes_them() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    let bad: &[(&str, &str)] = &[
        ("--confidence", "1.5"),
        ("--confidence", "1"),
        ("--confidence", "0"),
        ("--confidence", "-0.5"),
        ("--confidence", "NaN"),
        ("--confidence", "inf"),
        ("--confidence", "ninety"),
        ("--resamples", "0"),
        ("--resamples", "-1"),
        ("--resamples", "1.5"),
        ("--resamples", "many"),
        ("--resamples", "1000001"),
        ("--seed", "-1"),
        ("--seed", "abc"),
        ("--seed", "18446744073709551616"),
        ("--format", "xml"),
    ];
    for cmd in ["stats", "coverage"] {
        for (opt, value) in bad {
            // `--opt=value`, so that clap hands `-1` to the option, not as a flag.
            let arg = format!("{opt}={value}");
            let run = wd.run(&[cmd, &arg]);
            run.data_error().stderr_has(opt).stderr_has(value);
            // Given apart, the value may be taken for a flag: still exit 2.
            wd.run(&[cmd, opt, value]).data_error();
        }
    }
    for (opt, value) in [("--sims", "0"), ("--sims", "-3"), ("--sims", "x")] {
        wd.run(&["coverage", opt, value]).data_error();
    }
    for (opt, value) in [
        ("--format", "csv"),
        ("--format", "yaml"),
        ("--resamples", "10"),
    ] {
        // check has no CSV format and no bootstrap.
        wd.run(&["check", opt, value]).data_error();
    }
    for cmd in COMMANDS {
        wd.run(&[cmd, "--no-such-option"]).data_error();
        wd.run(&[cmd, "--data"]).data_error(); // value missing
    }
    wd.run(&["frobnicate"]).data_error();
    wd.run(&[]).expect_code(2);
}

#[test]
fn option_boundaries_are_accepted() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    for (opt, value) in [
        ("--confidence", "0.5"),
        ("--confidence", "0.999"),
        ("--confidence", "1e-3"),
        ("--resamples", "1"),
        ("--resamples", "1000000"), // n = 5: exact enumeration, still fast
        ("--seed", "0"),
        ("--seed", "18446744073709551615"),
    ] {
        let doc = wd
            .run(&["stats", "--format", "json", opt, value])
            .ok()
            .json();
        let key = opt.trim_start_matches("--");
        let got = &doc["settings"][key];
        if key == "confidence" {
            assert_rel(num(got), value.parse().unwrap(), 1e-15, key);
        } else {
            assert_eq!(got.to_string(), value, "{opt}");
        }
    }
}

#[test]
fn help_of_every_command_has_examples() {
    let wd = Workdir::new();
    for cmd in COMMANDS {
        for args in [&[cmd, "--help"][..], &[cmd, "-h"], &["help", cmd]] {
            let run = wd.run(args);
            run.ok()
                .stdout_has("Example")
                .stdout_has(&format!("phalanx {cmd}"))
                .stdout_has("Usage: phalanx");
        }
    }
    let run = wd.run(&["--help"]);
    run.ok().stdout_has("Exit status").stdout_has("Example");
    for cmd in COMMANDS {
        run.stdout_has(cmd);
    }
    wd.run(&["--version"])
        .ok()
        .stdout_has(env!("CARGO_PKG_VERSION"));
}

#[test]
fn out_of_range_confidence_and_resamples_explain_the_range() {
    let wd = Workdir::new();
    wd.copy_paper_data();
    wd.run(&["stats", "--confidence", "1.5"])
        .data_error()
        .stderr_has("'1.5'")
        .stderr_has("strictly between 0 and 1");
    wd.run(&["coverage", "--resamples", "0"])
        .data_error()
        .stderr_has("'0'")
        .stderr_has("from 1 to 1000000");
}
