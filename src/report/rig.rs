//! `phalanx rig`'s output: the joints made on each finger, where they were
//! written, and how the written copy is judged (a table, JSON, and the line
//! on what was written).

use super::audit::MM;
use super::json::SCHEMA_VERSION;
use super::layout::{Align, Give, Grid, Hidden, Width};
use crate::error::Error;
use crate::format::{count, num};
use crate::rig::session::Rigged;
use schemars::JsonSchema;
use serde::Serialize;

/// The joints made, finger by finger: each point's node (new or the file's
/// own, moved), its place in mm, and each finger's standing in the written
/// copy's audit (T^2 against the joint region's bound).
pub(crate) fn table(r: &Rigged, width: Width) -> String {
    let mut t = Grid::new()
        .col("finger", Align::Left, Give::Keep)
        .col("joint", Align::Left, Give::Keep)
        .col("node", Align::Left, Give::Keep)
        .col("x, y, z (mm)", Align::Right, Give::Drop(1))
        .col("audit", Align::Left, Give::Wrap);
    let mut joints = r.made.written.joints.iter();
    for f in &r.made.hand.fingers {
        let names: Vec<&str> = f
            .cmc
            .map(|_| "CMC")
            .into_iter()
            .chain(f.joints.iter().map(|j| j.0.name()))
            .collect();
        let standing = standing(r, f.finger);
        for (k, name) in names.iter().enumerate() {
            let Some((node, at, fresh)) = joints.next() else {
                break;
            };
            t.row(vec![
                if k == 0 {
                    f.finger.name().to_string()
                } else {
                    String::new()
                },
                (*name).to_string(),
                format!("{node}{}", if *fresh { " (new)" } else { "" }),
                format!(
                    "{}, {}, {}",
                    num(at.x * MM, 1),
                    num(at.y * MM, 1),
                    num(at.z * MM, 1)
                ),
                if k == 0 {
                    standing.clone()
                } else {
                    String::new()
                },
            ]);
        }
    }
    let mut hidden = Hidden::new();
    let mut out = t.render(width, 0, &mut hidden);
    hidden.append_to(&mut out, width);
    for n in &r.made.notes {
        out.push_str(&format!("note: {n}\n"));
    }
    out
}

/// A finger's standing in the written copy's audit: inside or outside the
/// joint region with T^2 over its bound, or why it is not judged.
fn standing(r: &Rigged, finger: crate::dataset::Finger) -> String {
    let Some(f) = r.audit.fingers.iter().find(|f| f.chain.finger == finger) else {
        return "not read back".into();
    };
    match &f.audit.region {
        Some(region) => format!(
            "{} (T^2 {} of {})",
            if f.audit.is_consistent() {
                "inside"
            } else {
                "outside"
            },
            num(region.t2, 2),
            num(region.bound, 2)
        ),
        None if f.audit.is_consistent() => "inside".into(),
        None => "outside".into(),
    }
}

/// The line on what was written: the file, the joints (how many new), the
/// vertices weighted, and how many fingers the audit finds inside.
pub(crate) fn summary(r: &Rigged) -> String {
    let w = &r.made.written;
    let fresh = w.joints.iter().filter(|j| j.2).count();
    let fingers = r.made.hand.fingers.len();
    let inside = r
        .audit
        .fingers
        .iter()
        .filter(|f| f.audit.is_consistent())
        .count();
    format!(
        "wrote {}: {} on {} ({} new), {} weighted; read back, {} of {} inside the X-rays' joint region",
        r.output.display(),
        count(w.joints.len(), "joint", "joints"),
        count(fingers, "finger", "fingers"),
        fresh,
        count(w.reweighted, "vertex", "vertices"),
        inside,
        r.audit.fingers.len()
    )
}

/// `rig --format json`.
#[derive(Serialize, JsonSchema)]
pub(crate) struct RigDocument {
    #[schemars(extend("const" = SCHEMA_VERSION))]
    schema_version: u32,
    /// The file written.
    output: String,
    /// "left" or "right".
    side: String,
    /// The wrist, in the file's units.
    wrist: [f64; 3],
    fingers: Vec<RigFinger>,
    /// How many of the file's vertices were weighted anew.
    reweighted: usize,
    /// How the hand was found and what was left out.
    notes: Vec<String>,
    /// The writer's remarks.
    warnings: Vec<String>,
}

/// One made finger.
#[derive(Serialize, JsonSchema)]
pub(crate) struct RigFinger {
    finger: String,
    /// Root first: the thumb's CMC, then MCP, PIP, DIP (IP), tip.
    joints: Vec<RigJoint>,
    /// The finger's local radius at each joint, in the file's units.
    radius: Vec<f64>,
    /// The written copy's audit: inside the joint region.
    inside: Option<bool>,
    /// Its T^2 and the region's bound (`null`: judged without a region).
    t2: Option<f64>,
    bound: Option<f64>,
}

/// One made joint.
#[derive(Serialize, JsonSchema)]
pub(crate) struct RigJoint {
    /// "CMC", "MCP", "PIP", "DIP", "IP" or "tip".
    joint: String,
    /// The node written.
    node: String,
    /// True for a node added, false for the file's own node moved.
    new: bool,
    /// World position in the file's units.
    position: [f64; 3],
}

/// The JSON document of a rigged hand.
pub(crate) fn json(r: &Rigged) -> Result<Vec<u8>, Error> {
    let mut joints = r.made.written.joints.iter();
    let fingers = r
        .made
        .hand
        .fingers
        .iter()
        .map(|f| {
            let names: Vec<&str> = f
                .cmc
                .map(|_| "CMC")
                .into_iter()
                .chain(f.joints.iter().map(|j| j.0.name()))
                .collect();
            let audited = r.audit.fingers.iter().find(|a| a.chain.finger == f.finger);
            let region = audited.and_then(|a| a.audit.region.as_ref());
            RigFinger {
                finger: f.finger.name().to_string(),
                joints: names
                    .iter()
                    .filter_map(|name| {
                        let (node, at, fresh) = joints.next()?;
                        Some(RigJoint {
                            joint: (*name).to_string(),
                            node: node.clone(),
                            new: *fresh,
                            position: at.to_array(),
                        })
                    })
                    .collect(),
                radius: f.radius.clone(),
                inside: audited.map(|a| a.audit.is_consistent()),
                t2: region.map(|x| x.t2),
                bound: region.map(|x| x.bound),
            }
        })
        .collect();
    let doc = RigDocument {
        schema_version: SCHEMA_VERSION,
        output: r.output.display().to_string(),
        side: r.made.hand.side.name().to_string(),
        wrist: r.made.hand.wrist.to_array(),
        fingers,
        reweighted: r.made.written.reweighted,
        notes: r.made.notes.clone(),
        warnings: r.made.written.warnings.clone(),
    };
    let mut bytes = serde_json::to_vec_pretty(&doc)
        .map_err(|e| Error::render("cannot serialise the rig document", e))?;
    bytes.push(b'\n');
    Ok(bytes)
}
