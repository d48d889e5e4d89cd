//! `phalanx rig`: place a hand's finger joints from its skin and the statistics, and weight the skin.

use super::args::{
    BootArgs, DataArgs, ForceArgs, TextFormat, check_output_file, metacarpals_or_default,
};
use super::out;
use crate::error::Error;
use crate::report;
use crate::report::layout::{Width, fit_text};
use crate::rig::make::MakeOptions;
use crate::rig::make::names::Names;
use crate::rig::make::write::WriteOptions;
use crate::rig::naming::Side;
use crate::rig::session::{self, RigRequest};
use glam::DVec3;
use std::path::PathBuf;

/// Rig a hand's fingers: find them on its skin, place their joints from the statistics, weight the skin
#[derive(clap::Args, Debug)]
#[command(
    after_help = "The hand is a glTF, GLB, VRM or FBX mesh: unskinned, or skinned to a hand (wrist) bone without \
                  finger bones. On its skin phalanx finds the wrist (the hand bone's origin, --wrist, or where the \
                  mesh opens), the five fingertips, each finger's axis (the centres of rings traced from its tip) \
                  and the webs, then tells the thumb from the fingers and the side. It places each finger's joints \
                  on its axis as the paper does: PIP and DIP (the thumb's IP) at the data's mean proportions from \
                  the MCP to the skin's tip; the MCP where the atlas's wrist-to-MCP ratio puts it; the thumb's CMC \
                  where the atlas puts it beside the wrist and its MCP at the atlas's metacarpal ratio; each \
                  finger joint at 0.4 of the finger's thickness from its back. It weights the skin with smooth \
                  blends across each joint, 1.5 finger radii long, the palm blending into the first bones, and \
                  writes a glTF 2.0 copy (nodes named by --names, inverse bind matrices, JOINTS_0/WEIGHTS_0); \
                  anything rigged before (a body, the hand bone) and its animations stay. The copy is read back \
                  and judged as `audit` judges it before it is written.\n\n\
                  --replace-fingers re-rigs a rigged hand: its finger nodes are moved to the new places and its \
                  skin weighted to them anew; its finger bones and their weights are not read (only their nodes \
                  are reused).\n\n\
                  Examples:\n  phalanx rig scan.glb --out rigged.glb\n  phalanx rig avatar.vrm --side left --names vrm --out left.glb\n  \
                  phalanx rig hand.glb --replace-fingers --out rerigged.glb\n  phalanx rig hand.fbx --wrist 0,0.02,0.01 --names mixamo --out hand.glb"
)]
pub(crate) struct Args {
    /// The hand: a .glb, .gltf, .vrm or .fbx file
    #[arg(value_name = "HAND")]
    hand: PathBuf,
    /// Where to write the rigged copy (.glb or .vrm; .gltf for an embedded buffer)
    #[arg(long, value_name = "RIGGED.glb")]
    out: PathBuf,
    /// How the new nodes are named
    #[arg(long, value_enum, default_value_t = Names::Openxr)]
    names: Names,
    /// Re-rig the fingers of a rigged hand (its finger nodes moved, its skin weighted anew)
    #[arg(long)]
    replace_fingers: bool,
    /// Which hand, for a file with two
    #[arg(long, value_enum)]
    side: Option<SideArg>,
    /// The wrist's centre, in the file's units (metres for glTF), for a mesh without a hand bone or a clear opening
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_point, allow_hyphen_values = true)]
    wrist: Option<DVec3>,
    /// How many fingers the hand has, the thumb included (2 to 5)
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(2..=5))]
    fingers: Option<u8>,
    #[command(flatten)]
    data: DataArgs,
    /// Place from this cohort's dataset instead of --data (e.g. data/atlas/measurements.csv)
    #[arg(long, value_name = "DATA")]
    reference: Option<PathBuf>,
    /// The dataset with metacarpals and, beside it, the atlas's landmarks (default: data/atlas/measurements.csv)
    #[arg(long, value_name = "DATASET")]
    metacarpals: Option<PathBuf>,
    /// Soft tissue past the bone tip in mm, to carry bone tips to the skin (default: the measured table's)
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    tip_soft_tissue: Option<f64>,
    #[command(flatten)]
    boot: BootArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
    #[command(flatten)]
    force: ForceArgs,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum SideArg {
    Left,
    Right,
}

/// A point X,Y,Z: three finite numbers.
fn parse_point(text: &str) -> Result<DVec3, String> {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}' is not a point X,Y,Z; give e.g. 0,0.02,-0.01"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite() && c.abs() < 1e9) => Ok(DVec3::new(x, y, z)),
        _ => Err(format!(
            "'{text}' is not a point X,Y,Z of three finite numbers; give e.g. 0,0.02,-0.01"
        )),
    }
}

pub(crate) fn run(args: &Args, quiet: bool, width: Width) -> Result<i32, Error> {
    check_output_file("--out", &args.out, args.force.force)?;
    let soft_tissue = match args.tip_soft_tissue {
        Some(mm) if mm.is_finite() && (0.0..1000.0).contains(&mm) => {
            crate::rig::judge::SoftTissue::Length {
                length: mm / 1000.0,
            }
        }
        Some(mm) => {
            return Err(Error::Usage(format!(
                "--tip-soft-tissue {mm}: give millimetres, 0 or more and below 1000"
            )));
        }
        None => super::soft_tissue_table()?,
    };
    let metacarpals = metacarpals_or_default(args.metacarpals.as_deref());
    let data = args.reference.as_deref().unwrap_or(&args.data.data);
    let rigged = session::rig(&RigRequest {
        input: &args.hand,
        output: &args.out,
        data,
        settings: args.boot.settings()?,
        metacarpals: metacarpals.as_deref(),
        soft_tissue,
        make: MakeOptions {
            side: args.side.map(|s| match s {
                SideArg::Left => Side::Left,
                SideArg::Right => Side::Right,
            }),
            wrist: args.wrist,
            fingers: args.fingers.map(usize::from),
            write: WriteOptions {
                names: args.names,
                replace_fingers: args.replace_fingers,
                glb: true,
            },
        },
        prior_hands: crate::analysis::region::PRIOR_HANDS,
    })?;
    let bytes = match args.format {
        TextFormat::Table => report::rig::table(&rigged, width).into_bytes(),
        TextFormat::Json => report::rig::json(&rigged)?,
    };
    out::print(&bytes)?;
    if !quiet {
        eprintln!("{}", fit_text(&report::rig::summary(&rigged), width));
        for w in &rigged.made.written.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(0)
}
