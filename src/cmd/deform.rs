//! `phalanx deform`: curl a rigged hand, skin it, measure the skin, and
//! compare it with another version of the rig or with what `audit --fix` writes.

use super::args::{BootArgs, DataArgs, ForceArgs, TextFormat, check_output_dir};
use super::out;
use crate::error::Error;
use crate::report::deform::{self as view, DeformDocument, HandVerdicts, RigView};
use crate::report::json::{MovedView, SCHEMA_VERSION};
use crate::report::layout::Width;
use crate::report::writer;
use crate::rig::deform::file::{DeformRequest, FileDeformation};
use crate::rig::deform::{Pose, Skinning};
use crate::rig::map::NameMap;
use crate::rig::naming::Side;
use crate::rig::naming::hand_side;
use crate::rig::session::{self, Verdicts};
use clap::ValueEnum;
use std::path::PathBuf;

/// Curl a rigged hand (glTF 2.0 or FBX) and measure how its skin deforms; compare with --against or --fix
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Curls every finger of the rig's hand(s) to a pose, each joint about its flexion axis (in the palm's \
                  plane, across the finger; mirrored for a left hand), skins the rig's own mesh (JOINTS_n/WEIGHTS_n) \
                  and measures, per finger and joint: volume loss (cross-section area lost across the bent joint), \
                  new self-intersections, edge strain (95th percentile and maximum of |ln(posed/rest edge length)|) \
                  and crease offset (where the skin folds, from the joint). With --against or --fix it poses both rigs \
                  alike and says per joint which deforms better, by which measure and by how much.\n\n\
                  Default pose: fist, MCP 60, PIP 90, DIP 60 degrees (about two thirds of each joint's active range, \
                  AAOS averages MCP 90, PIP 100, DIP 80: the fingertips reach the palm without pressing into it); the \
                  thumb bends half as far (MCP 30, IP 45: its MCP's range is about half the fingers', and a thumb bent \
                  as far would pass through the index finger, which is not modelled) and turns at its CMC, its \
                  metacarpal with it, until its tip lies across the index's middle phalanx. grip: 45, 60, 30 (a 4 cm \
                  bar; the thumb only bends). point: the index straight, the rest in the fist, the thumb across the \
                  middle finger. --angles MCP,PIP,DIP: degrees from -30 to 180 \
                  (negative: hyperextension), the thumb at half the MCP and PIP angles.\n\n\
                  --fix compares the rig with the copy `phalanx audit RIG --fix OUT` would write (made in memory, \
                  judged against --data). Rigs whose joint names carry no side (WebXR) take --side, or the side \
                  the file name says.\n\n\
                  --out DIR writes deform-<side>.png per hand: the rig(s) posed, from the side and from above, one \
                  column per rig (A left, B right, each labelled), framed on the hand (the vertices its bones skin), \
                  coloured by strain (grey 0, amber 0.1, red 0.25 and more) with the scale and its numbers below.\n\n\
                  Examples:\n  phalanx deform hand.glb\n  phalanx deform hand.glb --fix --out renders\n  \
                  phalanx deform hand.glb --against hand-fixed.glb --skinning dqs\n  \
                  phalanx deform right.glb --angles 45,90,45 --format json"
)]
pub(crate) struct Args {
    /// The rig: a .glb, .gltf or .vrm (glTF 2.0) or .fbx file with a skinned mesh
    #[arg(value_name = "RIG")]
    rig: PathBuf,
    /// Compare with this version of the rig (B)
    #[arg(long, value_name = "FIXED.glb", conflicts_with = "fix")]
    against: Option<PathBuf>,
    /// Compare with what `audit --fix` would write (B), made in memory
    #[arg(long)]
    fix: bool,
    /// With --fix: the fix leaves the skin weights as painted, as `audit --fix --keep-weights`
    #[arg(long, requires = "fix")]
    keep_weights: bool,
    /// Named pose
    #[arg(long, value_enum, default_value_t = PoseName::Fist, conflicts_with = "angles")]
    pose: PoseName,
    /// Flexion of every finger's MCP, PIP and DIP in degrees, each from -30 to 180 (thumb: half the MCP and PIP)
    #[arg(long, value_name = "MCP,PIP,DIP", value_parser = parse_angles, allow_hyphen_values = true)]
    angles: Option<[f64; 3]>,
    /// Skinning: linear blend (lbs) or dual quaternion (dqs)
    #[arg(long, value_enum, default_value_t = Method::Lbs)]
    skinning: Method,
    /// The side of a hand whose joint names do not say (default: from the file name)
    #[arg(long, value_enum)]
    side: Option<SideArg>,
    /// Custom joint names: CSV with node,side,finger,joint
    #[arg(long, value_name = "FILE")]
    map: Option<PathBuf>,
    /// Write the figures (deform-<side>.png) into this directory
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    boot: BootArgs,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
    #[command(flatten)]
    force: ForceArgs,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum PoseName {
    Fist,
    Grip,
    Point,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum Method {
    Lbs,
    Dqs,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum SideArg {
    Left,
    Right,
}

/// Three angles in degrees, each finite and from -30 to 180.
fn parse_angles(text: &str) -> Result<[f64; 3], String> {
    let bad = || {
        format!(
            "'{text}' is not three angles MCP,PIP,DIP in degrees, each from -30 to 180; give e.g. 60,90,60"
        )
    };
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    match v[..] {
        [a, b, c]
            if v.iter()
                .all(|x| x.is_finite() && (-30.0..=180.0).contains(x)) =>
        {
            Ok([a, b, c])
        }
        _ => Err(bad()),
    }
}

impl Args {
    fn pose(&self) -> Result<Pose, Error> {
        match self.angles {
            Some([m, p, d]) => Pose::from_angles("angles", m, p, d).map_err(Error::Usage),
            None => {
                let name = match self.pose {
                    PoseName::Fist => "fist",
                    PoseName::Grip => "grip",
                    PoseName::Point => "point",
                };
                Pose::named(name).ok_or_else(|| Error::Usage(format!("unknown pose {name}")))
            }
        }
    }
}

/// The rig (A), what it is compared with (B), the verdicts and, with --fix,
/// the joints the fix moves.
type Deformed = (
    FileDeformation,
    Option<FileDeformation>,
    Verdicts,
    Option<Vec<(String, f64)>>,
);

fn deform_rigs(args: &Args, req: &DeformRequest<'_>) -> Result<Deformed, Error> {
    Ok(if args.fix {
        // The fix `audit --fix` writes: with the MCPs judged from their rays'
        // bases against the default metacarpals' dataset where it exists.
        let metacarpals = super::args::metacarpals_or_default(None);
        let fixed = session::fix_in_memory(
            &args.rig,
            args.map.as_deref(),
            &args.data.data,
            args.boot.settings()?,
            &super::soft_tissue_table()?,
            metacarpals.as_deref(),
            !args.keep_weights,
        )?;
        let (a, b, verdicts) = session::compare_fixed(&fixed, &args.rig, req)?;
        (a, Some(b), verdicts, Some(fixed.moved))
    } else {
        let a = session::deform_path(&args.rig, req)?;
        let b = args
            .against
            .as_deref()
            .map(|p| session::deform_path(p, req))
            .transpose()?;
        let verdicts = match &b {
            Some(b) => session::compare_deformed(&a, b)?,
            None => Vec::new(),
        };
        (a, b, verdicts, None)
    })
}

pub(crate) fn run(args: &Args, width: Width) -> Result<i32, Error> {
    let pose = args.pose()?;
    let map = args.map.as_deref().map(NameMap::load).transpose()?;
    let method = match args.skinning {
        Method::Lbs => Skinning::Lbs,
        Method::Dqs => Skinning::Dqs,
    };
    let given = args.side.map(|s| match s {
        SideArg::Left => Side::Left,
        SideArg::Right => Side::Right,
    });
    let side = hand_side(None, given, &args.rig.display().to_string());
    if let Some(dir) = &args.out {
        // Checked before the work: the figures' names are known from the side (both when
        // the side is not known yet).
        let names: Vec<String> = match side {
            Some(s) => vec![view::figure_file(s)],
            None => vec![
                view::figure_file(Side::Left),
                view::figure_file(Side::Right),
            ],
        };
        check_output_dir("--out", dir, &names, args.force.force)?;
    }
    let req = DeformRequest {
        map: map.as_ref(),
        side,
        ..session::deform_request(&args.rig, &pose, method)
    };
    let (a, b, verdicts, moved) = deform_rigs(args, &req)?;
    // The figures first: nothing is printed when they cannot be written.
    let mut renders = Vec::new();
    if let Some(dir) = &args.out {
        let (files, r) = view::figures(&a, b.as_ref(), args.fix)?;
        writer::write_all(dir, &files)?;
        renders = r;
    }
    let notes = pose.anatomy_notes();
    let bytes = match args.format {
        TextFormat::Table => match &b {
            Some(b) => view::text_two(&a, b, &verdicts, &pose, method, width),
            None => view::text_one(&a, &pose, method, width),
        }
        .into_bytes(),
        TextFormat::Json => view::json(&DeformDocument {
            schema_version: SCHEMA_VERSION,
            units: "m",
            pose: &pose,
            skinning: method,
            notes,
            rig: RigView::of(&a),
            against: b.as_ref().map(RigView::of),
            moved: moved.as_ref().map(|m| {
                m.iter()
                    .map(|(node, shift)| MovedView {
                        node,
                        shift: *shift,
                    })
                    .collect()
            }),
            verdicts: verdicts
                .iter()
                .map(|(side, joints)| HandVerdicts {
                    side: *side,
                    joints,
                })
                .collect(),
            renders,
            caveats: &view::CAVEATS,
        })?,
    };
    out::print(&bytes)?;
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_are_three_finite_degrees_in_range() {
        assert_eq!(parse_angles("60,90,60"), Ok([60.0, 90.0, 60.0]));
        assert_eq!(parse_angles(" -30, 0,180"), Ok([-30.0, 0.0, 180.0]));
        for bad in [
            "",
            "60,90",
            "60,90,60,1",
            "NaN,0,0",
            "inf,0,0",
            "0,181,0",
            "-31,0,0",
            "a,b,c",
        ] {
            let e = parse_angles(bad).unwrap_err();
            assert!(e.contains("from -30 to 180"), "{bad}: {e}");
        }
    }
}
