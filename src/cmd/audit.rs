//! `phalanx audit`: judge a rigged hand against the X-ray statistics; `--fix` writes a corrected copy.

use super::args::{
    BootArgs, DEFAULT_METACARPALS, DataArgs, ForceArgs, TextFormat, check_output_file,
    metacarpals_or_default,
};
use super::out;
use crate::analysis::placement::Joint;
use crate::error::{EXIT_FAILURE, Error};
use crate::format::count;
use crate::report;
use crate::report::layout::{Width, fit_text};
use crate::rig::AuditOptions;
use crate::rig::bend::BEND_TOLERANCE_MM;
use crate::rig::judge::{SoftTissue, TipKind};
use crate::rig::session::{self, Audit, AuditRequest, FixOutcome};
use std::path::{Path, PathBuf};

/// What a rig's tip nodes mark.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tip {
    /// The skin; where the mesh reaches past the tip node, the mesh's end
    Auto,
    /// The skin at the end of the finger, at the tip node
    Skin,
    /// The end of the distal phalanx, as on an X-ray
    Bone,
}

/// Where `--fix` puts an MCP.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FixMcp {
    /// Where the finger's proportions put it (when the explanation moves it)
    Finger,
    /// Where the metacarpals' dataset puts it from the CMC or the wrist (when outside)
    Atlas,
}

/// Judge a rigged hand (glTF 2.0 or FBX) against the X-ray statistics; --fix writes a corrected copy
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Finds the finger chains of either hand by their names (Mixamo mixamorig:RightHandIndex1..4, \
                  Rigify f_index.01.R / DEF-f_index.01.R / thumb.01.R, VRM rightIndexProximal or its humanoid table, \
                  Unreal index_01_r, WebXR index-finger-phalanx-proximal, SteamVR finger_index_0_r, Oculus b_r_index1, \
                  Unity EthanRightHandIndex1 / Right_Index_Finger_Joint_01a, Blender Index.R, Index.R.001; case and separators ignored; --map for others) \
                  and measures joint-to-joint distances in the node (bind) pose; the joints need not be parent and \
                  child when the names say which finger they belong to (WebXR). Every joint (MCP, PIP, DIP, tip) is \
                  reported inside the X-ray range, inside the prediction interval, or outside by how many mm and in \
                  which direction; the finger's verdict is its relative joint positions (J~1, J~1 + J~2) as one \
                  vector against the X-rays' 95% joint prediction region (Hotelling's T^2 with their covariance), \
                  and a misfit is explained by moving the fewest joints that bring it inside. Tips are read as skin tips \
                  (--tip) and the data's where its tip column says (the paper's at the skin): alike, the last \
                  segments are compared as they are; bone against skin, the last segment is corrected by that \
                  finger's soft tissue measured by Buryanov & Kotiuk 2010 (data/literature/), as a share of the \
                  rig's finger, so a rig in any unit is judged alike (--tip-soft-tissue MM sets one length). \
                  A finger without a tip node takes its tip from the mesh (where the skin weighted to its last \
                  bone ends: \"tip from the mesh\") and is judged on relative values; where the mesh has no clear \
                  end, on J2/J1 only. Where the skin weights make the mesh bend is found for each joint, and a \
                  joint further than --bend-tolerance from its bend is flagged. The finger and its ray's base are \
                  weighed together: an MCP that the CMC or the wrist puts inside the atlas's prediction interval, or \
                  outside the other way, is held (\"in range from its base\", \"its base puts it the other way\") \
                  and the explanation sought among the inner joints; each table row states its standing given the \
                  explanation, with the rig's own standing beside it (\"as the rig is\"). docs/internals.md, \
                  \"How a ray is judged\", gives the steps and their assumptions.\n\n\
                  The text opens with one line per finger, its verdict and its move (\"index   keep\", \
                  \"index   move the PIP 3.1 mm towards the tip\", or \"held: ...\" for a move the fix \
                  does not make), read off the same fields as the table and the JSON; then one table per \
                  finger (its joints, the rig against the X-rays, one verdict column), the explanation of a \
                  finger that does not fit as it is, and the summary. --explain (--verbose) prints every \
                  value, the method, the notes and the caveats; --brief prints only the opening lines and \
                  the summary (with --fix, the fix's line on standard error). A fix that moves no joint \
                  writes no file and says so. --hold \
                  pip,dip pins the artist's joints: the explanation moves only the others, and --fix, \
                  --moves and --fix-mcp atlas leave them (\"held: pinned by --hold\").\n\n\
                  --fix OUT.glb writes a copy with the explanation's joints moved along each finger, translation keys offset, and the inverse bind matrices updated so the mesh's rest \
                  shape is unchanged; the input is never modified. Each finger's skin weights move with its joints, \
                  so the skin bends at the new joint (the fix's line counts the vertices reweighted at each). A joint \
                  whose weights cannot follow is held (\"its skin cannot follow it\"): fewer than 8 vertices around \
                  it, more than a tenth of them weighted to another finger too, or carried weights that would not \
                  bend the skin within 0.5 mm of it. --keep-weights leaves the weights as painted and holds instead a \
                  joint whose move would take it more than 1 mm farther from where its skin bends. No move under \
                  1 mm is made. An MCP is held too: where the skin over a knuckle bends cannot be located \
                  well enough to guard its move, so only --fix-mcp atlas moves MCPs. --fix-mcp atlas places each MCP where the \
                  metacarpals' dataset puts it from its CMC (or the wrist, for a rig with a hand bone and no \
                  metacarpals) when it lies outside that interval. An FBX rig is read with ufbx (metres, +Y up, the \
                  bind pose from its skin clusters) and cannot be fixed in place: --moves FILE.csv lists each node the \
                  fix moves, with its new world position and its new local translation (FBX: Lcl Translation) to \
                  set in a DCC, and FILE.weights.csv beside it the vertices whose skin weights move with the joints \
                  (mesh, primitive, vertex: for FBX the mesh's control point; node, weight: a row per influence), for \
                  a script to set.\n\n\
                  --map FILE: CSV with the header node,side,finger,joint (joint MCP, PIP, DIP, IP or tip).\n\n\
                  Examples:\n  phalanx audit hand.glb\n  phalanx audit hand.glb --brief\n  phalanx audit hand.glb --fix hand-fixed.glb\n  phalanx audit hand.glb --hold pip --fix hand-fixed.glb\n  phalanx audit hand.glb --keep-weights --fix hand-fixed.glb\n  phalanx audit avatar.vrm --format json\n  phalanx audit rig.gltf --map my-names.csv\n  phalanx audit glove.fbx --moves moves.csv"
)]
pub(crate) struct Args {
    /// The rig: a .glb, .gltf or .vrm (glTF 2.0) or .fbx file
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
    /// Write the joints the fix moves to this CSV: node, old and new world position (m), new local
    /// translation in the file's units and axes (FBX: Lcl Translation), to apply in a DCC; and the
    /// vertices whose skin weights move with them to FILE.weights.csv beside it (mesh, primitive,
    /// vertex, node, weight)
    #[arg(long, value_name = "FILE.csv")]
    moves: Option<PathBuf>,
    /// With --fix or --moves: move only joints that are themselves outside the prediction interval
    #[arg(long)]
    only_outside: bool,
    /// What the rig's tip nodes mark
    #[arg(long, value_enum, default_value_t = Tip::Auto)]
    tip: Tip,
    /// Soft tissue between the bone tip and a skin tip, in mm, on every finger, where the rig's
    /// tips and the data's differ [default: each finger's measured share of its length, from
    /// data/literature/buryanov-kotiuk-2010.csv]
    #[arg(long, value_name = "MM")]
    tip_soft_tissue: Option<f64>,
    /// Flag a joint further than this from where its skin bends, in mm (default 3)
    #[arg(long, value_name = "MM")]
    bend_tolerance: Option<f64>,
    /// Also judge each MCP from its metacarpal (CMC) against this dataset's mc column
    /// [default: data/atlas/measurements.csv, when it exists]
    #[arg(long, value_name = "DATASET")]
    metacarpals: Option<PathBuf>,
    /// With --fix or --moves: leave the skin weights as painted. Without it the fix moves each
    /// finger's weights with its joints, so the skin bends at the new joint; a joint whose
    /// weights cannot follow (too few vertices around it, vertices shared with another finger, or
    /// carried weights that would not bend the skin at it) is held. A rig with no skin at all has
    /// nothing to carry: its joints move alone
    #[arg(long)]
    keep_weights: bool,
    /// How many hands the atlas's shape of each joint region counts as (--metacarpals' dataset):
    /// its correlation of the PIP's and DIP's positions is pooled with the X-rays' own, their
    /// variances kept; 0 judges on the X-rays' covariance alone (0 to 100000)
    #[arg(long, value_name = "N", default_value_t = crate::analysis::region::PRIOR_HANDS)]
    prior_hands: f64,
    /// Exit with status 1 when a finger is outside the joint region (without a tip, J2/J1's
    /// prediction interval), or an MCP judged from its CMC or wrist outside its prediction interval
    #[arg(long)]
    strict: bool,
    /// With --fix or --moves: where an MCP goes. `finger`: where the finger's own proportions put it,
    /// when it is part of the explanation. `atlas`: where the metacarpals' dataset puts it
    /// from its CMC (or the wrist), when it lies outside that prediction interval; the MCP is
    /// then held and only PIP and DIP move to fit the proportions
    #[arg(long, value_enum, default_value_t = FixMcp::Finger)]
    fix_mcp: FixMcp,
    /// Joints to pin where the rig has them, comma-separated (mcp, pip, dip, ip, tip): the
    /// explanation moves only the others, and --fix, --moves and --fix-mcp atlas never move them
    #[arg(long, value_name = "JOINTS", value_delimiter = ',', value_parser = parse_joint)]
    hold: Vec<Joint>,
    /// Print only the line per finger and the summary (with --fix: the line per finger, and the
    /// fix's line on standard error)
    #[arg(long, conflicts_with = "format")]
    brief: bool,
    /// Print the full text: every value of each finger against its interval, the method, each
    /// joint's new position, the skin's bends, the metacarpals, the notes and the caveats
    #[arg(long, visible_alias = "verbose", conflicts_with_all = ["format", "brief"])]
    explain: bool,
    /// Output format
    #[arg(long, value_enum, default_value_t = TextFormat::Table)]
    format: TextFormat,
    #[command(flatten)]
    force: ForceArgs,
}

/// A joint named on the command line (`--hold`), in any case.
fn parse_joint(s: &str) -> Result<Joint, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "mcp" => Ok(Joint::Mcp),
        "pip" => Ok(Joint::Pip),
        "dip" => Ok(Joint::Dip),
        "ip" => Ok(Joint::Ip),
        "tip" => Ok(Joint::Tip),
        _ => Err(format!(
            "no joint is called '{s}': give mcp, pip, dip, ip or tip, comma-separated"
        )),
    }
}

pub(crate) fn run(args: &Args, quiet: bool, width: Width) -> Result<i32, Error> {
    check_outputs(args)?;
    let metacarpals = metacarpals_or_default(args.metacarpals.as_deref());
    let options = options(args)?;
    let no_tissue = options.soft_tissue == SoftTissue::Unknown;
    let mut audit = session::audit(&AuditRequest {
        rig: &args.rig,
        map: args.map.as_deref(),
        fix: args.fix.as_deref(),
        data: &args.data.data,
        settings: args.boot.settings()?,
        options,
        only_outside: args.only_outside,
        metacarpals: metacarpals.as_deref(),
        mcp_from_atlas: args.fix_mcp == FixMcp::Atlas,
        moves: args.moves.is_some(),
        prior_hands: prior_hands(args.prior_hands)?,
    })?;
    add_metacarpal_notes(&mut audit, metacarpals.as_deref(), no_tissue);
    // --only-outside decides only what a fix moves.
    let only_outside = args.only_outside && (args.fix.is_some() || args.moves.is_some());
    let bytes = match args.format {
        TextFormat::Table if args.brief => report::audit::brief(
            &audit.rig,
            audit.analysis.settings.confidence,
            only_outside,
            audit.fix.is_none(),
            width,
        )
        .into_bytes(),
        TextFormat::Table if args.explain => table(&audit, only_outside, width).into_bytes(),
        TextFormat::Table => {
            let a = &audit.analysis;
            report::audit::compact(
                &audit.rig,
                &a.dataset.path,
                &crate::format::xrays(a.dataset.xrays),
                a.settings.confidence,
                only_outside,
                width,
            )
            .into_bytes()
        }
        TextFormat::Json => report::json::audit(&audit)?,
    };
    if let (Some(path), Some(outcome)) = (&args.moves, &audit.moves) {
        write_moves(path, outcome)?;
        if !quiet {
            let line = moves_summary(&audit, path, outcome.moves.len());
            say(&line, &outcome.warnings, args.brief, width);
        }
    }
    out::print(&bytes)?;
    if !quiet && let Some(fix) = &audit.fix {
        let line = fix_summary(fix, audit.analysis.settings.confidence);
        say(&line, &fix.warnings, args.brief, width);
    }
    Ok(
        if args.strict && audit.rig.outside() + audit.rig.metacarpals_outside() > 0 {
            EXIT_FAILURE
        } else {
            0
        },
    )
}

/// Refuses, before any work, a `--fix-mcp` without a fix, a `--moves` over the
/// input, and output files that exist (without `--force`).
fn check_outputs(args: &Args) -> Result<(), Error> {
    if args.fix_mcp != FixMcp::Finger && args.fix.is_none() && args.moves.is_none() {
        return Err(Error::Usage(
            "--fix-mcp says where the fix puts an MCP: give it with --fix OUT or --moves FILE.csv"
                .into(),
        ));
    }
    if let Some(m) = &args.moves
        && crate::atomic::same_file(&args.rig, m)
    {
        return Err(Error::Usage(format!(
            "--moves {} would overwrite the input rig; name a new .csv file",
            m.display()
        )));
    }
    // Writing over the input is refused by the session with its own message, --force or not.
    if let Some(path) = &args.fix
        && !crate::atomic::same_file(path, &args.rig)
    {
        check_output_file("--fix", path, args.force.force)?;
    }
    if let Some(path) = &args.moves {
        check_output_file("--moves", path, args.force.force)?;
        check_output_file("--moves", &weights_path(path), args.force.force)?;
    }
    Ok(())
}

/// The notes on MCPs left unjudged for a reason of the command's: the default
/// metacarpals' dataset not found here, or no soft tissue figure (from a file
/// here, or an option) for judging them from their CMC or the wrist.
fn add_metacarpal_notes(audit: &mut Audit, metacarpals: Option<&Path>, no_tissue: bool) {
    let fingers = &audit.rig.fingers;
    if metacarpals.is_none() && fingers.iter().any(|f| f.chain.metacarpal.is_some()) {
        audit.rig.notes.push(format!(
            "Metacarpals: the rig has them, but {DEFAULT_METACARPALS} (the Digital Hand Atlas) \
             was not found here, so its MCPs are not judged from their CMCs; give a dataset with \
             an mc column with --metacarpals DATASET"
        ));
    }
    // The judge says which MCPs went unjudged for want of a soft tissue figure; where that
    // figure comes from (a file here, or an option) is the command's to say.
    let fingers = &audit.rig.fingers;
    if let Some(dataset) = metacarpals
        && no_tissue
        && fingers.iter().all(|f| f.metacarpal_check.is_none())
        && fingers
            .iter()
            .any(|f| f.chain.metacarpal.is_some() || f.chain.wrist.is_some())
    {
        audit.rig.notes.push(format!(
            "Metacarpals: no MCP is judged from its CMC or the wrist against {}: the fingertip's \
             soft tissue table ({}) was not found here; run from the phalanx checkout, or give \
             --tip-soft-tissue MM",
            dataset.display(),
            crate::rig::judge::SOFT_TISSUE_TABLE
        ));
    }
}

/// Writes `--moves FILE.csv` and the weights beside it.
fn write_moves(path: &Path, outcome: &session::MovesOutcome) -> Result<(), Error> {
    let csv = report::csv_out::moves(&outcome.moves)?;
    let weights = report::csv_out::weight_changes(&outcome.weights)?;
    crate::atomic::replace(path, &csv).map_err(Error::write(path))?;
    let beside = weights_path(path);
    crate::atomic::replace(&beside, &weights).map_err(Error::write(&beside))
}

/// A result line on standard error, then its warnings (with `--brief`, only how many).
fn say(line: &str, warnings: &[String], brief: bool, width: Width) {
    let mut line = line.to_string();
    if brief {
        line.push_str(&brief_warnings(warnings.len()));
    }
    eprintln!("{}", fit_text(&line, width));
    for w in warnings.iter().filter(|_| !brief) {
        eprintln!("warning: {w}");
    }
}

/// The tip and bend options, in metres; lengths must be finite, not negative
/// (the bend tolerance above zero). Without `--tip-soft-tissue` the soft
/// tissue is the measured table's, when it is found.
fn options(args: &Args) -> Result<AuditOptions, Error> {
    let mm = |name: &str, v: Option<f64>, default: f64, zero_ok: bool| -> Result<f64, Error> {
        let x = v.unwrap_or(default);
        if x.is_finite() && (x > 0.0 || (zero_ok && x == 0.0)) && x < 1000.0 {
            Ok(x / 1000.0)
        } else {
            Err(Error::Usage(format!(
                "--{name} {x}: give millimetres, {} and below 1000",
                if zero_ok { "0 or more" } else { "above 0" }
            )))
        }
    };
    let soft_tissue = match args.tip_soft_tissue {
        Some(given) => SoftTissue::Length {
            length: mm("tip-soft-tissue", Some(given), 0.0, true)?,
        },
        None => super::soft_tissue_table()?,
    };
    Ok(AuditOptions {
        rig_tip: match args.tip {
            Tip::Auto | Tip::Skin => TipKind::Skin,
            Tip::Bone => TipKind::Bone,
        },
        soft_tissue,
        bend_tolerance: mm(
            "bend-tolerance",
            args.bend_tolerance,
            BEND_TOLERANCE_MM,
            false,
        )?,
        measure_tip: args.tip == Tip::Auto,
        hold: args.hold.clone(),
        shape: None,
        carry_weights: !args.keep_weights,
        found_tips: Default::default(),
    })
}

/// `--prior-hands`, checked: a finite number of hands from 0 to 100,000.
pub(crate) fn prior_hands(n: f64) -> Result<f64, Error> {
    if n.is_finite() && (0.0..=100_000.0).contains(&n) {
        Ok(n)
    } else {
        Err(Error::Usage(format!(
            "--prior-hands {n}: give a number of hands from 0 (the X-rays' own shape) to 100000 \
             (default {})",
            crate::analysis::region::PRIOR_HANDS
        )))
    }
}

/// What `--brief` says of the warnings it does not print, on the result line.
fn brief_warnings(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(
            "; {} (shown without --brief)",
            count(n, "warning", "warnings")
        )
    }
}

/// The audit table.
fn table(audit: &Audit, only_outside: bool, width: Width) -> String {
    let a = &audit.analysis;
    let n_note = crate::format::xrays(a.dataset.xrays);
    report::audit::text(
        &audit.rig,
        audit.fbx.as_ref(),
        &a.dataset.path,
        &n_note,
        a.settings.confidence,
        only_outside,
        width,
    )
}

/// Where `--moves FILE.csv` writes the vertices whose weights the fix
/// changes: `FILE.weights.csv` beside it.
fn weights_path(moves: &Path) -> PathBuf {
    let stem = moves
        .file_stem()
        .map_or_else(|| "moves".into(), |s| s.to_string_lossy().into_owned());
    moves.with_file_name(format!("{stem}.weights.csv"))
}

/// The line on standard error saying what `--moves` wrote.
fn moves_summary(audit: &Audit, path: &std::path::Path, n: usize) -> String {
    let units = match &audit.fbx {
        Some(src) => format!(
            "new Lcl Translations in the file's units ({}), each in its parent's frame; the \
             file's axes: {}",
            report::audit::unit_words(src.unit_meters),
            src.axes
        ),
        None => "new translations in metres, each in its parent's frame".into(),
    };
    let after = audit.moves.as_ref().map_or(String::new(), |m| {
        report::audit::moved_fingers_words(&m.fingers, "with the moves made")
    });
    let vertices = audit.moves.as_ref().map_or(0, |m| m.weights.len());
    format!(
        "wrote {}: {n} node{} to move (world positions in metres, +Y up; {units}){after}; and {}: \
         {} whose skin weights move with the joints (mesh, primitive, vertex: for FBX the mesh's \
         control point; one row per node and weight)",
        path.display(),
        if n == 1 { "" } else { "s" },
        weights_path(path).display(),
        count(vertices, "vertex", "vertices"),
    )
}

/// The line on standard error saying what the fix wrote.
fn fix_summary(fix: &FixOutcome, confidence: f64) -> String {
    if !fix.written {
        return format!(
            "nothing to fix: no joint moves, so {} was not written (the rig as given stands)",
            fix.output.display()
        );
    }
    let mut line = format!(
        "wrote {}: {} moved; re-audited, {} of {} outside {}",
        fix.output.display(),
        count(
            fix.moved.iter().filter(|(_, d)| *d > 0.0).count(),
            "joint",
            "joints"
        ),
        fix.reaudit.outside(),
        count(fix.reaudit.fingers.len(), "finger", "fingers"),
        crate::report::audit::outside_of(&fix.reaudit, confidence)
    );
    let rays = fix
        .reaudit
        .fingers
        .iter()
        .filter(|f| f.metacarpal_check.is_some())
        .count();
    if rays > 0 {
        line.push_str(&format!(
            ", {} of {} outside it from their CMC or wrist",
            fix.reaudit.metacarpals_outside(),
            count(rays, "MCP", "MCPs")
        ));
    }
    line.push_str(&report::audit::fix_after_words(fix));
    line
}
