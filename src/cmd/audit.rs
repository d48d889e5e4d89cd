//! `phalanx audit`: judge a rigged hand against the X-ray statistics; `--fix` writes a corrected copy.

use super::args::{BootArgs, DataArgs, TextFormat};
use super::out;
use crate::error::{EXIT_FAILURE, Error};
use crate::report;
use crate::rig::session::{self, Audit, AuditRequest, FixOutcome};
use std::path::PathBuf;

/// Judge a rigged hand (glTF 2.0) against the X-ray statistics; --fix writes a corrected copy
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Finds the finger chains of either hand by their names (Mixamo mixamorig:RightHandIndex1..4, \
                  Rigify f_index.01.R / DEF-f_index.01.R / thumb.01.R, VRM rightIndexProximal or its humanoid table, \
                  Unreal index_01_r, WebXR index-finger-phalanx-proximal; case and separators ignored; --map for others) \
                  and measures joint-to-joint distances in the node (bind) pose. Each inner joint is reported inside the \
                  X-ray range, inside the prediction interval, or outside by how many mm and in which direction. \
                  Rigs without tip nodes are judged on J2/J1 only.\n\n\
                  --fix OUT.glb writes a copy with the middle joints at the mean positions along each finger (root and \
                  tip fixed) and the inverse bind matrices updated so the mesh's rest shape is unchanged; the input is \
                  never modified.\n\n\
                  --map FILE: CSV with the header node,side,finger,joint (joint MCP, PIP, DIP, IP or tip).\n\n\
                  Examples:\n  phalanx audit hand.glb\n  phalanx audit hand.glb --fix hand-fixed.glb\n  phalanx audit avatar.vrm --format json\n  phalanx audit rig.gltf --map my-names.csv"
)]
pub(crate) struct Args {
    /// The rig: a .glb, .gltf or .vrm (glTF 2.0) file
    #[arg(value_name = "RIG")]
    rig: PathBuf,
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// Custom joint names: CSV with node,side,finger,joint
    #[arg(long, value_name = "FILE")]
    map: Option<PathBuf>,
    /// Write a corrected copy of the rig here (.glb, or .gltf with the buffer embedded)
    #[arg(long, value_name = "OUT")]
    fix: Option<PathBuf>,
    /// Exit with status 1 when a finger is outside the prediction interval
    #[arg(long)]
    strict: bool,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
}

pub(crate) fn run(args: &Args, quiet: bool) -> Result<i32, Error> {
    let audit = session::audit(&AuditRequest {
        rig: &args.rig,
        map: args.map.as_deref(),
        fix: args.fix.as_deref(),
        data: &args.data.data,
        settings: args.boot.settings()?,
    })?;
    let bytes = match args.format {
        TextFormat::Table => table(&audit).into_bytes(),
        TextFormat::Json => json(&audit)?,
    };
    out::print(&bytes)?;
    if !quiet && let Some(fix) = &audit.fix {
        eprintln!("{}", fix_summary(fix));
        for w in &fix.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(if args.strict && audit.rig.outside() > 0 {
        EXIT_FAILURE
    } else {
        0
    })
}

/// The audit table.
fn table(audit: &Audit) -> String {
    let a = &audit.analysis;
    let n_note = format!("{} X-rays", a.dataset.xrays);
    report::audit::text(&audit.rig, &a.dataset.path, &n_note, a.settings.confidence)
}

/// The audit document, with what the fix did.
fn json(audit: &Audit) -> Result<Vec<u8>, Error> {
    let fix = audit.fix.as_ref().map(|fix| report::json::FixView {
        output: fix.output.to_str().unwrap_or("(non-UTF-8 path)"),
        moved: fix
            .moved
            .iter()
            .map(|(node, shift)| report::json::MovedView {
                node,
                shift: *shift,
            })
            .collect(),
        warnings: &fix.warnings,
    });
    report::json::audit(&audit.analysis, &audit.rig, fix)
}

/// The line on standard error saying what the fix wrote.
fn fix_summary(fix: &FixOutcome) -> String {
    format!(
        "wrote {}: {} joints moved; re-audited, {} of {} fingers outside the prediction interval",
        fix.output.display(),
        fix.moved.iter().filter(|(_, d)| *d > 0.0).count(),
        fix.reaudit.outside(),
        fix.reaudit.fingers.len()
    )
}
