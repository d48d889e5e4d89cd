//! `phalanx rig`'s output: the joints made on each finger, where they were
//! written, and how the written copy is judged (a table, JSON, and the line
//! on what was written); and the report's part on a hand rigged from its
//! skin ([`made_section`]).

use super::audit::MM;
use super::json::SCHEMA_VERSION;
use super::layout::{Align, Give, Grid, Hidden, Width};
use super::render3d::{FINGER_COLOURS, Marked, MarkedChain, MeshView, View};
use super::sections::deform::DeformFigureView;
use super::sections::made::{MadeRow, MadeSection, MadeView};
use super::writer::OutputFile;
use crate::analysis::placement::Joint;
use crate::dataset::Finger;
use crate::error::Error;
use crate::format::{count, num, trimmed};
use crate::rig::AuditedRig;
use crate::rig::deform::file::FileDeformation;
use crate::rig::deform::verdict::{Better, JointVerdict, Measure};
use crate::rig::deform::{Pose, Skinning};
use crate::rig::make::place::{DEPTH, MadeFinger};
use crate::rig::naming::Side;
use crate::rig::read::FingerChain;
use crate::rig::session::{Rigged, RiggedInMemory};
use glam::DVec3;
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
        let standing = standing(&r.audit, f.finger);
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
    let notes: String = r
        .made
        .notes
        .iter()
        .map(|n| format!("note: {n}\n"))
        .collect();
    out.push_str(&super::layout::fit_text(&notes, width));
    out
}

/// A finger's standing in the written copy's audit: inside or outside the
/// joint region with T^2 over its bound, or why it is not judged.
fn standing(audit: &AuditedRig, finger: Finger) -> String {
    let Some(f) = audit.fingers.iter().find(|f| f.chain.finger == finger) else {
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

/// What [`made_section`] needs: the rig as given (its own chains: the
/// artist's joints), the hand rigged again from its skin, and both posed.
pub(crate) struct MadeInputs<'a> {
    /// The rig file, as the report names it.
    pub rig: &'a str,
    /// The rig's own finger chains of the hand rigged.
    pub artist: &'a [FingerChain],
    pub rigged: &'a RiggedInMemory,
    /// The rig as given (A) and as `rig --replace-fingers` writes it (B),
    /// posed alike, with the verdicts per joint.
    pub a: &'a FileDeformation,
    pub b: &'a FileDeformation,
    pub verdicts: &'a [(Side, Vec<JointVerdict>)],
    pub pose: &'a Pose,
    pub method: Skinning,
    /// File name stem under `plots/`, e.g. `made-webxr-generic-hand-left`.
    pub stem: &'a str,
}

/// Pixels of one panel of the joints' figure.
const JOINTS_PANEL: (u32, u32) = (480, 520);

/// The report's part on a hand rigged from its skin: the made joints and
/// the artist's on the skin, both rigs in the fist, a row per finger (each
/// made joint's distance from the artist's, the written copy's audit) and
/// what it shows. `font` for the figures' words ([`Marked::render`]).
pub(crate) fn made_section(s: MadeInputs<'_>, font: Option<&[u8]>) -> Result<MadeSection, Error> {
    let made = &s.rigged.made;
    let side = made.hand.side;
    let (Some(ha), Some(hb)) = (
        s.a.hands.iter().find(|h| h.chains.side == side),
        s.b.hands.iter().find(|h| h.chains.side == side),
    ) else {
        return Err(Error::Usage(format!(
            "{}: the {} hand rigged from its skin could not be posed beside the rig as given",
            s.rig,
            side.name()
        )));
    };
    let (joints_png, joints_size) = joints_figure(&s, ha, font)?;
    let file_name = std::path::Path::new(s.rig)
        .file_name()
        .map_or_else(|| s.rig.to_string(), |n| n.to_string_lossy().into_owned());
    let (fist_png, fist) = super::deform::figure(
        ha,
        Some(hb),
        &[
            &format!("A: the artist's rig, {file_name}"),
            "B: rigged from its skin (rig --replace-fingers)",
        ],
        font,
    )?;
    let mut files = Vec::new();
    let joints = png_view(
        &mut files,
        &format!("{}-joints", s.stem),
        joints_png,
        joints_size,
        format!(
            "The {} hand's skin seen through, with the joints phalanx rig made (dots, labelled) and \
             the artist's (rings), from above and from the side",
            side.name()
        ),
        format!(
            "The joints rig --replace-fingers made on the {} hand's skin (filled dots, labelled, \
             joined by their bones) and the artist's joints in the file (rings), each finger in its \
             colour; the skin at rest, faded, is drawn under the marks, which show through it. \
             Left: from above, the back of the hand; right: from the little finger's side, the \
             back up.",
            side.name()
        ),
    );
    let fist_view = png_view(
        &mut files,
        &format!("{}-fist", s.stem),
        fist_png.bytes,
        (fist.width, fist.height),
        format!(
            "The {} hand in the fist as the artist rigged it (left) and as rigged from its skin \
             (right), from the side (top) and from above (bottom), coloured by strain",
            side.name()
        ),
        fist_caption(side),
    );
    let joints_verdicts = s
        .verdicts
        .iter()
        .find(|(v, _)| *v == side)
        .map_or(&[][..], |(_, j)| j.as_slice());
    Ok(MadeSection {
        view: MadeView {
            rig: s.rig.to_string(),
            command: format!("phalanx rig {} --replace-fingers", s.rig),
            made: made_words(s.rigged),
            rows: made_rows(s.rigged, s.artist),
            sentences: made_sentences(s.rigged, s.artist),
            joints,
            fist: fist_view,
            pose: super::deform::pose_line(s.pose, s.method)
                .trim_end()
                .to_string(),
            fist_summary: fist_summary(joints_verdicts),
        },
        figures: files,
    })
}

/// The figure of the joints made on the skin at rest beside the artist's, from above and
/// from the side: its PNG and size in pixels.
fn joints_figure(
    s: &MadeInputs<'_>,
    ha: &crate::rig::deform::file::HandDeformation,
    font: Option<&[u8]>,
) -> Result<(Vec<u8>, (u32, u32)), Error> {
    let made = &s.rigged.made;
    // The joints on the skin at rest, from above and from the side.
    let focus = ha.hand_vertices();
    let still = vec![0.0; ha.mesh.positions.len()];
    let skin = MeshView {
        positions: &ha.mesh.positions,
        triangles: &ha.mesh.triangles,
        strain: &still,
        focus: &focus,
    };
    let views = [View::above(&ha.posed.frame), View::side(&ha.posed.frame)];
    let layout = Marked::layout(&skin, &views, JOINTS_PANEL.0, JOINTS_PANEL.1);
    let chains = marked_chains(made, s.artist);
    let key: Vec<(String, [u8; 3])> = made
        .hand
        .fingers
        .iter()
        .map(|f| (f.finger.name().to_string(), colour(f.finger)))
        .collect();
    let joints_png = layout
        .render(
            &skin,
            &chains,
            &[
                "from above (the back of the hand)",
                "from the little finger's side",
            ],
            &key,
            [
                "made by phalanx rig (labelled)",
                "the artist's joint (in the file)",
            ],
            font,
        )
        .map_err(|e| Error::render("cannot draw the joints made on the skin", e))?;
    Ok((joints_png, (layout.width, layout.height)))
}

/// A finger's colour in the joints' figure.
fn colour(finger: Finger) -> [u8; 3] {
    FINGER_COLOURS[finger.index() % FINGER_COLOURS.len()]
}

/// A PNG figure under `plots/` and its view (a data URI for the HTML).
fn png_view(
    files: &mut Vec<OutputFile>,
    id: &str,
    png: Vec<u8>,
    (width, height): (u32, u32),
    alt: String,
    caption: String,
) -> DeformFigureView {
    use base64::Engine;
    let file = format!("plots/{id}.png");
    let data_uri = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&png)
    );
    files.push(OutputFile::new(&file, png));
    DeformFigureView {
        id: id.to_string(),
        file,
        data_uri,
        width: width.to_string(),
        height: height.to_string(),
        alt,
        caption,
    }
}

/// The fist figure's caption.
fn fist_caption(side: Side) -> String {
    format!(
        "The {} hand in the fist, as the artist rigged it (A, left) and as rig --replace-fingers \
         rigs it from its skin (B, right), from the side (top row) and from above (bottom row). \
         Colour: edge strain |ln(posed/rest edge length)|, grey 0, amber 0.1, red 0.25 and more.",
        side.name()
    )
}

/// The made points of a finger, root first, with the joint each is (`None`:
/// the thumb's CMC).
fn made_points(f: &MadeFinger) -> Vec<(Option<Joint>, DVec3)> {
    f.cmc
        .map(|c| (None, c))
        .into_iter()
        .chain(f.joints.iter().map(|&(j, at)| (Some(j), at)))
        .collect()
}

/// Where the artist put `joint` of `finger` (`None`: the thumb's CMC, its
/// metacarpal node's origin), when the rig has it.
fn artist_point(artist: &[FingerChain], finger: Finger, joint: Option<Joint>) -> Option<DVec3> {
    let c = artist.iter().find(|c| c.finger == finger)?;
    match joint {
        None => c.metacarpal.as_ref().map(|m| m.position),
        Some(j) => c.joints.iter().find(|x| x.joint == j).map(|x| x.position),
    }
}

/// The figure's chains: each finger's joints as the artist put them, then
/// as made (labelled: the joint's name, the finger's at its tip), and the
/// wrist the made MCPs are placed from.
fn marked_chains(made: &crate::rig::make::Made, artist: &[FingerChain]) -> Vec<MarkedChain> {
    let mut out = Vec::new();
    for f in &made.hand.fingers {
        let points = made_points(f);
        let theirs: Vec<DVec3> = points
            .iter()
            .filter_map(|(j, _)| artist_point(artist, f.finger, *j))
            .collect();
        out.push(MarkedChain {
            labels: vec![String::new(); theirs.len()],
            points: theirs,
            colour: colour(f.finger),
            made: false,
        });
        out.push(MarkedChain {
            labels: points
                .iter()
                .map(|(j, _)| match j {
                    None => "CMC".to_string(),
                    Some(Joint::Tip) => f.finger.name().to_string(),
                    Some(j) => j.name().to_string(),
                })
                .collect(),
            points: points.iter().map(|p| p.1).collect(),
            colour: colour(f.finger),
            made: true,
        });
    }
    out.push(MarkedChain {
        points: vec![made.hand.wrist],
        labels: vec!["wrist".to_string()],
        colour: [60, 60, 60],
        made: true,
    });
    out
}

/// What `rig` made, in one sentence that follows the command.
fn made_words(r: &RiggedInMemory) -> String {
    let w = &r.made.written;
    let moved = w.joints.iter().filter(|j| !j.2).count();
    let fresh = w.joints.len() - moved;
    format!(
        "finds the hand's {} on its skin ({}), moves {} of its own to the joints it places{} \
         and weights {} anew. Here the copy is made in memory, read back and judged as audit \
         judges a rig.",
        count(r.made.hand.fingers.len(), "finger", "fingers"),
        count(r.made.triangles, "triangle", "triangles"),
        count(moved, "node", "nodes"),
        if fresh > 0 {
            format!(", adds {}", count(fresh, "node", "nodes"))
        } else {
            String::new()
        },
        count(w.reweighted, "vertex", "vertices"),
    )
}

/// A distance in mm, 1 decimal.
fn mm1(x: f64) -> String {
    num(x * MM, 1)
}

/// Per finger, each made joint's distance from the artist's and the audit.
fn made_rows(r: &RiggedInMemory, artist: &[FingerChain]) -> Vec<MadeRow> {
    r.made
        .hand
        .fingers
        .iter()
        .map(|f| {
            let at = |joints: &[Joint]| -> String {
                f.joints
                    .iter()
                    .find(|(j, _)| joints.contains(j))
                    .and_then(|&(j, p)| Some(p.distance(artist_point(artist, f.finger, Some(j))?)))
                    .map_or_else(|| "n/a".to_string(), mm1)
            };
            MadeRow {
                finger: f.finger.name().to_string(),
                mcp: at(&[Joint::Mcp]),
                pip: at(&[Joint::Pip, Joint::Ip]),
                dip: at(&[Joint::Dip]),
                tip: at(&[Joint::Tip]),
                audit: standing(&r.audit, f.finger),
            }
        })
        .collect()
}

/// `d` (made less the artist's) along a finger (`along`, towards its tip)
/// and towards the back of the hand (against `palm`, the palm's normal).
fn in_words(d: DVec3, along: DVec3, palm: DVec3) -> String {
    let a = d.dot(along);
    let b = -d.dot(palm);
    format!(
        "{} mm {} along the finger and {} mm towards the {}",
        mm1(a.abs()),
        if a < 0.0 {
            "nearer the wrist"
        } else {
            "nearer the tip"
        },
        mm1(b.abs()),
        if b < 0.0 { "palm" } else { "back of the hand" }
    )
}

/// What the part shows: the audit's T^2 (0 by construction), where the
/// MCPs and the depth come from, and where the made joints differ from
/// the artist's.
fn made_sentences(r: &RiggedInMemory, artist: &[FingerChain]) -> Vec<String> {
    let audited = &r.audit.fingers;
    let inside = audited.iter().filter(|f| f.audit.is_consistent()).count();
    let largest = audited
        .iter()
        .filter_map(|f| f.audit.region.as_ref().map(|x| x.t2))
        .fold(0.0, f64::max);
    let mut out = vec![format!(
        "Each finger's joints are placed at the X-rays' mean proportions (PIP and DIP, the \
         thumb's IP, between the MCP and the skin's tip), so the rigged copy's audit finds {} of \
         {} inside the joint region at T^2 {} at most: 0 by construction, which shows that rig \
         writes what audit reads back, not that this hand is the X-rays' mean hand.",
        inside,
        count(audited.len(), "finger", "fingers"),
        num(largest, 2)
    )];
    out.push(format!(
        "Each MCP lies on its finger's axis where the atlas's mean wrist-to-MCP ratio (w/J) puts \
         it from the wrist (the thumb's CMC beside the wrist and its MCP at the atlas's mc/J), \
         and the depth rule puts the fingers' joints at {} of the finger's thickness from its \
         back, the thumb's on its axis.",
        trimmed(DEPTH, 2)
    ));
    let offsets = made_offsets(r, artist);
    out.extend(against_artist(&offsets));
    out.extend(differs_most(r, &offsets));
    out
}

/// A made point against the artist's: (finger, joint (`None`: the CMC), made less theirs,
/// the artist's finger direction).
type Offset = (Finger, Option<Joint>, DVec3, DVec3);

/// Each made point against the artist's, finger by finger.
fn made_offsets(r: &RiggedInMemory, artist: &[FingerChain]) -> Vec<Offset> {
    let fingers = &r.made.hand.fingers;
    // Each made point against the artist's: (finger, joint, made less theirs, along).
    let mut offsets: Vec<Offset> = Vec::new();
    for f in fingers {
        let Some(c) = artist.iter().find(|c| c.finger == f.finger) else {
            continue;
        };
        let along = match (c.joints.first(), c.joints.last()) {
            (Some(a), Some(b)) => (b.position - a.position).normalize_or_zero(),
            _ => DVec3::ZERO,
        };
        for (j, p) in made_points(f) {
            if let Some(q) = artist_point(artist, f.finger, j) {
                offsets.push((f.finger, j, p - q, along));
            }
        }
    }
    offsets
}

/// How far the made joints and tips lie from the artist's, in one sentence.
fn against_artist(offsets: &[Offset]) -> Option<String> {
    let span = |pick: &dyn Fn(Finger, Option<Joint>) -> bool| -> Option<(f64, f64)> {
        let d: Vec<f64> = offsets
            .iter()
            .filter(|o| pick(o.0, o.1))
            .map(|o| o.2.length())
            .collect();
        let lo = d.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (!d.is_empty()).then_some((lo, hi))
    };
    let inner = span(&|f, j| f != Finger::Thumb && j.is_some_and(|j| j != Joint::Tip));
    let tips = span(&|_, j| j == Some(Joint::Tip));
    let beyond = offsets
        .iter()
        .filter(|o| o.1 == Some(Joint::Tip))
        .all(|o| o.2.dot(o.3) > 0.0);
    let mut differs = Vec::new();
    if let Some((lo, hi)) = inner {
        differs.push(format!(
            "the fingers' MCPs, PIPs and DIPs lie {} to {} mm from the artist's",
            mm1(lo),
            mm1(hi)
        ));
    }
    if let Some((lo, hi)) = tips {
        differs.push(if beyond {
            format!(
                "the tips {} to {} mm farther out, at the skin's end along the last bone (where \
                 audit reads a rig's tip), the artist's tip nodes lying inside the fingertips",
                mm1(lo),
                mm1(hi)
            )
        } else {
            format!(
                "the tips {} to {} mm from the artist's, at the skin's end along the last bone",
                mm1(lo),
                mm1(hi)
            )
        });
    }
    (!differs.is_empty()).then(|| format!("Against the artist: {}.", differs.join("; ")))
}

/// The point that differs most from the artist's, the tips aside, with the rest of its finger.
fn differs_most(r: &RiggedInMemory, offsets: &[Offset]) -> Option<String> {
    // The point that differs most, the tips aside, and the rest of its finger.
    let worst = offsets
        .iter()
        .filter(|o| o.1 != Some(Joint::Tip))
        .max_by(|a, b| a.2.length().total_cmp(&b.2.length()));
    let &(finger, joint, d, along) = worst?;
    let name = |j: Option<Joint>| j.map_or("CMC", Joint::name);
    let rest: Vec<String> = offsets
        .iter()
        .filter(|o| o.0 == finger && o.1 != joint && o.1 != Some(Joint::Tip))
        .map(|o| format!("its {} {} mm", name(o.1), mm1(o.2.length())))
        .collect();
    Some(format!(
        "The tips aside, it differs most at the {finger}'s {}: {} mm from the artist's, {}{}{}.",
        name(joint),
        mm1(d.length()),
        in_words(d, along, r.made.hand.palm_normal),
        if rest.is_empty() {
            String::new()
        } else {
            format!("; {}", and_words(&rest))
        },
        if finger == Finger::Thumb {
            " (the thumb's ray is placed from the atlas, not from the artist's thumb)"
        } else {
            ""
        }
    ))
}

/// "a", "a and b", "a, b and c".
fn and_words(items: &[String]) -> String {
    match items.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

/// Which rig deforms better in the fist (B the made rig), overall and
/// measure by measure.
fn fist_summary(joints: &[JointVerdict]) -> String {
    let n = |b: Better| joints.iter().filter(|v| v.overall == b).count();
    let by = |b: Better| -> String {
        let parts: Vec<String> = Measure::ALL
            .iter()
            .map(|&m| {
                let k = joints
                    .iter()
                    .filter(|v| v.measures.iter().any(|x| x.measure == m && x.better == b))
                    .count();
                format!("{} {k}", m.name())
            })
            .collect();
        and_words(&parts)
    };
    format!(
        "In the fist the rig made from the skin deforms better at {}, the artist's at {}, mixed \
         at {}, the same at {} (of {}), by the measures of the part above. Measure by measure, \
         the joints where the artist's is better: {}; where the made one is: {}.",
        count(n(Better::B), "joint", "joints"),
        n(Better::A),
        n(Better::Mixed),
        n(Better::Same),
        joints.len(),
        by(Better::A),
        by(Better::B)
    )
}
