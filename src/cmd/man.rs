//! `phalanx man`: the manual page, in roff.

use super::out;
use crate::error::Error;
use clap_mangen::Man;
use std::path::{Path, PathBuf};

/// Print the manual page (roff); --out writes one page per command
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  phalanx man | man -l -\n  phalanx man --out /usr/local/share/man/man1"
)]
pub(crate) struct Args {
    /// Write phalanx.1 and a phalanx-COMMAND.1 for each command into this directory
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    #[command(flatten)]
    force: super::args::ForceArgs,
}

/// Renders the page of `cmd` (the whole command line) to standard output, or
/// every page into a directory.
pub(crate) fn run(args: &Args, cmd: clap::Command) -> Result<i32, Error> {
    match &args.out {
        None => out::print(&page(cmd)?)?,
        Some(dir) => write_pages(dir, cmd, args.force.force)?,
    }
    Ok(0)
}

/// The page of `cmd` alone (its commands listed, not described).
fn page(cmd: clap::Command) -> Result<Vec<u8>, Error> {
    let mut page = Vec::new();
    Man::new(cmd).render(&mut page).map_err(not_rendered)?;
    Ok(page)
}

/// Renders every page in memory, stages them all, then renames them into place:
/// a failure leaves the directory as it was.
fn write_pages(dir: &Path, cmd: clap::Command, force: bool) -> Result<(), Error> {
    let mut pages = Vec::new();
    let mut cmd = cmd.disable_help_subcommand(true);
    cmd.build();
    render_all(cmd, &mut pages).map_err(not_rendered)?;
    let names: Vec<String> = pages.iter().map(|(n, _)| n.clone()).collect();
    super::args::check_output_dir("--out", dir, &names, force)?;
    let mut staged = Vec::with_capacity(pages.len());
    for (name, page) in &pages {
        let path = dir.join(name);
        let tmp = crate::atomic::stage(&path, page).map_err(Error::write(&path))?;
        staged.push((tmp, path));
    }
    for (tmp, path) in staged {
        crate::atomic::commit(tmp, &path).map_err(Error::write(&path))?;
    }
    Ok(())
}

fn not_rendered(e: std::io::Error) -> Error {
    Error::render("cannot render the manual page", e)
}

/// The pages of a built command and its visible subcommands: (file name, roff).
fn render_all(cmd: clap::Command, pages: &mut Vec<(String, Vec<u8>)>) -> std::io::Result<()> {
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        render_all(sub.clone(), pages)?;
    }
    let man = Man::new(cmd);
    let mut page = Vec::new();
    man.render(&mut page)?;
    pages.push((man.get_filename(), page));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::Cli;
    use clap::CommandFactory;

    /// Checks the roff of a man(7) page: the title line `.TH` first (after
    /// clap_mangen's definition of the apostrophe string `Aq`), and every
    /// control line a request or macro of the man package or basic roff.
    fn assert_man_roff(page: &[u8], title: &str) {
        const KNOWN: [&str; 22] = [
            "TH", "SH", "SS", "TP", "PP", "LP", "P", "IP", "HP", "RS", "RE", "B", "I", "BR", "BI",
            "IR", "RB", "RI", "br", "sp", "ie", "el",
        ];
        let text = std::str::from_utf8(page).expect("UTF-8");
        let mut lines = text
            .lines()
            .skip_while(|l| l.starts_with(".ie \\n(.g .ds Aq ") || l.starts_with(".el .ds Aq "));
        let first = lines.next().unwrap_or_default();
        assert!(
            first.starts_with(&format!(".TH {title} 1 ")),
            "title line: {first}"
        );
        for line in lines.filter(|l| l.starts_with('.') || l.starts_with('\'')) {
            let name = line[1..].split_whitespace().next().unwrap_or_default();
            assert!(KNOWN.contains(&name), "unknown request in '{line}'");
        }
        assert!(text.contains(".SH NAME"), "no NAME section");
    }

    #[test]
    fn the_page_is_roff_and_lists_every_command() {
        let page = page(Cli::command()).unwrap();
        assert_man_roff(&page, "phalanx");
        let text = String::from_utf8(page).unwrap();
        for c in ["stats", "check", "report", "audit", "completions", "man"] {
            assert!(text.contains(&format!("phalanx\\-{c}")), "no {c}");
        }
    }

    #[test]
    fn out_writes_one_page_per_command() {
        let dir = tempfile::tempdir().unwrap();
        let mut args = Args {
            out: Some(dir.path().to_path_buf()),
            force: crate::cmd::args::ForceArgs { force: false },
        };
        assert_eq!(run(&args, Cli::command()).unwrap(), 0);
        // A second run replaces the pages only with --force.
        let e = run(&args, Cli::command()).unwrap_err().to_string();
        assert!(e.contains("phalanx.1") && e.contains("give --force"), "{e}");
        args.force.force = true;
        assert_eq!(run(&args, Cli::command()).unwrap(), 0);
        for name in ["phalanx", "phalanx-stats", "phalanx-audit", "phalanx-man"] {
            let page = std::fs::read(dir.path().join(format!("{name}.1"))).unwrap();
            assert_man_roff(&page, name);
        }
        assert!(!dir.path().join("phalanx-help.1").exists());
    }
}
