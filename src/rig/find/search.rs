//! A hand's fingers, found on its skin alone: where each fingertip is, the
//! axis each finger's rings trace from its tip into the palm, its radius, its
//! web; the wrist, the palm's normal, the direction of the fingers, and which
//! hand it is. No bone is read here (a hand bone's origin may be given as the
//! wrist): the skin decides.
//!
//! # Method
//!
//! 1. **The surface.** The welded mesh ([`super::mesh`]) as a graph of its
//!    edges, separate pieces bridged across gaps of at most twice the median
//!    edge or 2% of the mesh's size ([`super::graph`]). Each bridged piece is
//!    an object; objects under a quarter of the largest's vertices are left
//!    out (noted), and each of the others is searched for a hand (two hands:
//!    see the rules).
//! 2. **The wrist**, a ring the geodesics start from, found in this order:
//!    the point given ([`FindOptions::wrist`]: `--wrist`, or the hand bone's
//!    origin), cut by the plane across the object's main axis (the principal
//!    axis of its surface) through it, the cut's curve nearest the point (the
//!    plane moved towards the fingers, up to 10% of the length, until that
//!    curve closes around the point: a wrist bone on the mesh's very end cuts
//!    only a sliver; the wrist stays the point given); else
//!    the mesh's open end, its longest border loop when it is at least half
//!    the hand's width around and lies in the outer quarter of the main axis;
//!    else a cut across the main axis 4% of the object's length inside the
//!    end the fingers are not at. That end is the one from which more
//!    extremities (see 4) lie beyond the middle of the object: from the wrist
//!    all the fingertips do, from the fingertips only the forearm's end and
//!    perhaps the thumb.
//! 3. **Geodesic distance** g from the wrist's ring over the graph (Dijkstra,
//!    each crossed edge's ends starting at their distance from the cut).
//! 4. **Extremities by persistence.** Sweeping g from high to low, each
//!    component of the super-level set is born at a maximum and dies at the
//!    saddle where it meets one born higher ([`super::graph::persistence`]).
//!    A finger's persistence is about its free length (the WebXR hand: 32-65
//!    mm, the middle finger, the oldest, never dies); a bump's a few mm; the
//!    forearm's end lies behind the wrist. An extremity is a maximum beyond
//!    the wrist (on the fingers' side, more than a tenth of the hand's length
//!    past the wrist's plane) whose persistence is at least a tenth of that
//!    length. The `fingers` most persistent are the fingers.
//! 5. **The web and the finger's region.** A finger's web is the highest of
//!    the saddles where it died and where other fingers died into it; its
//!    region, the vertices above the web's level connected to its top.
//! 6. **Axis, radius, tip** ([`super::axis`]): rings of plane sections traced
//!    from the tip towards the palm, their centres the axis; the tip where
//!    the fingertip's line (fitted through the rings half a radius to three
//!    radii from the tip end) leaves the mesh.
//!    The axis is continued straight along its last direction past the last
//!    ring to the point nearest the wrist, and at least a finger's width
//!    (two radii) past the web.
//! 7. **The palm and the thumb.** The palm is the rest of the hand beyond the
//!    wrist below the webs; its normal the least principal axis of its
//!    surface. The fingers' bases (their axes at their webs) are ordered
//!    across the palm; the thumb is the end of the row whose web is lowest
//!    (its web lies nearest the wrist along the skin), and the others take
//!    index, middle, ring, little from the thumb's side. The direction of the
//!    fingers is from the wrist to the mean of the other fingers' bases, in
//!    the palm's plane.
//! 8. **The palm's side and the hand's side.** The palm side is the side of
//!    the palm's plane where the thumb's tip and the other fingertips lie:
//!    at rest the thumb stands out in front of the palm and the fingers curl
//!    towards it (on the shared rigs the thumb's tip lies 20-51 mm palmar of
//!    the palm's plane, the other tips 2-56 mm on average). With the palm normal n
//!    towards the palm side and the direction of the fingers d, a right hand
//!    has its thumb on the side of d x n, a left hand on the other.
//!    [`FindOptions::side`] decides when the palm side is unclear (the sum of
//!    the two offsets under 3% of the hand's length), and is kept when it
//!    disagrees with the geometry (noted).
//!
//! # Rules that refuse a mesh ([`FindError`])
//!
//! - Fewer extremities than fingers: not a hand, or fused fingers (a mitten).
//! - Two objects that are both hands: two hands; give the side to take one.
//!   Twice as many extremities as fingers or more, in two clusters, in one
//!   piece of skin (or an end-to-end tie between two such clusters): two
//!   hands joined; rig each alone.
//! - A finger more than 1.8 times as wide as the median of the others (three
//!   or more besides the thumb): two fingers fused in one.
//! - A hand in a fist: a finger whose axis turns more than 120 degrees from
//!   its base to its tip, or two fingers (not the thumb) whose tips lie
//!   straight from the wrist at less than 0.6 of their distance along the
//!   skin (curled back towards the palm). The shared rigs' fingers measure
//!   0.80-1.14, their axes turn at most 23 degrees (the SteamVR gloves'
//!   relaxed middle fingers).
//! - No wrist: both ends of the mesh look alike; name it with `--wrist`.
//!
//! Lengths are in the mesh's units (metres for glTF); messages give them in
//! millimetres, reading the units as metres. Cost: O(V log V) for the
//! geodesics and persistence, and O(T) per ring of each finger's trace (a
//! few hundred rings at most).

use super::finger::{Traced, trace_finger};
use super::geometry::surface_axes;
use super::graph::{Extremity, dijkstra, persistence};
use super::hand::{mm, too_few};
use super::mesh::HandMesh;
use super::palm::frame;
use super::surface::{Object, Surface, extent, two_clusters};
use super::wrist::wrist_ring;
use crate::rig::read::naming::Side;
use glam::DVec3;

use super::hand::{FindError, FindOptions, FoundHand};

/// Finds the hand on `mesh` (see the module doc).
pub fn find_hand(mesh: &HandMesh, opts: &FindOptions) -> Result<FoundHand, FindError> {
    if !(2..=5).contains(&opts.fingers) {
        return Err(FindError::Options(format!(
            "a hand has 2 to 5 fingers counting the thumb; {} {} asked for",
            opts.fingers,
            if opts.fingers == 1 { "was" } else { "were" }
        )));
    }
    if opts.wrist.is_some_and(|w| !w.is_finite()) {
        return Err(FindError::Options(
            "the wrist given is not a finite point".into(),
        ));
    }
    let surface = Surface::new(mesh)?;
    let mut notes = Vec::new();
    let objects = pieces(&surface, opts.wrist, &mut notes)?;
    // Several hands are told apart by the side each one's skin shows, so
    // each is found without the side given.
    let each = if objects.len() > 1 {
        FindOptions {
            side: None,
            ..opts.clone()
        }
    } else {
        opts.clone()
    };
    let mut results: Vec<Result<FoundHand, FindError>> = objects
        .iter()
        .map(|o| find_in(&surface, o, &each))
        .collect();
    if results.len() == 1 {
        let mut hand = results.pop().unwrap_or(Err(FindError::Empty))?;
        notes.append(&mut hand.notes);
        hand.notes = notes;
        return Ok(hand);
    }
    one_hand(results, opts.side, notes)
}

/// The large pieces of `surface` a hand may be on: pieces under a quarter
/// of the largest's vertices left out, and with a `wrist` given only the
/// piece nearest it; each left out with a note.
fn pieces(
    surface: &Surface<'_>,
    wrist: Option<DVec3>,
    notes: &mut Vec<String>,
) -> Result<Vec<Object>, FindError> {
    let mut objects = surface.objects();
    let largest = objects.first().map_or(0, |o| o.vertices.len());
    let small: Vec<usize> = objects
        .iter()
        .filter(|o| o.vertices.len() * 4 < largest)
        .map(|o| o.vertices.len())
        .collect();
    if !small.is_empty() {
        notes.push(format!(
            "{} separate piece{} of {} vertices in all, too small to be a hand, {} left out",
            small.len(),
            if small.len() == 1 { "" } else { "s" },
            small.iter().sum::<usize>(),
            if small.len() == 1 { "was" } else { "were" }
        ));
    }
    objects.retain(|o| o.vertices.len() * 4 >= largest);
    if objects.is_empty() {
        return Err(FindError::Empty);
    }
    // With a wrist given, only the object nearest it.
    if let Some(w) = wrist
        && objects.len() > 1
    {
        let nearest = objects
            .iter()
            .enumerate()
            .map(|(i, o)| (o.distance(surface, w), i))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map_or(0, |x| x.1);
        let kept = objects.swap_remove(nearest);
        notes.push(format!(
            "{} other large piece{} of the mesh, away from the wrist given, {} left out",
            objects.len(),
            if objects.len() == 1 { "" } else { "s" },
            if objects.len() == 1 { "was" } else { "were" }
        ));
        objects = vec![kept];
    }
    Ok(objects)
}

/// The one hand of several pieces' `results`: the only piece that held a
/// hand, else the one of `side`; two hands without a side are refused.
fn one_hand(
    mut results: Vec<Result<FoundHand, FindError>>,
    side: Option<Side>,
    mut notes: Vec<String>,
) -> Result<FoundHand, FindError> {
    let hands: Vec<FoundHand> = results
        .iter()
        .filter_map(|r| r.as_ref().ok().cloned())
        .collect();
    match (hands.len(), side) {
        (0, _) => results.swap_remove(0),
        (1, _) => {
            let mut hand = hands.into_iter().next().ok_or(FindError::Empty)?;
            notes.push(format!(
                "{} other large piece{} of the mesh held no hand and {} left out",
                results.len() - 1,
                if results.len() == 2 { "" } else { "s" },
                if results.len() == 2 { "was" } else { "were" }
            ));
            notes.append(&mut hand.notes);
            hand.notes = notes;
            Ok(hand)
        }
        (_, None) => Err(FindError::TwoHands {
            found: hands.iter().map(|h| h.fingers.len()).sum(),
        }),
        (_, Some(side)) => {
            let mut of_side: Vec<FoundHand> =
                hands.iter().filter(|h| h.side == side).cloned().collect();
            match of_side.len() {
                1 => {
                    let mut hand = of_side.remove(0);
                    notes.push(format!(
                        "the mesh holds {} hands; the {} one was taken (--side)",
                        hands.len(),
                        side.name()
                    ));
                    notes.append(&mut hand.notes);
                    hand.notes = notes;
                    Ok(hand)
                }
                0 => Err(FindError::TwoHandsSide(format!(
                    "neither of them a {} hand",
                    side.name()
                ))),
                _ => Err(FindError::TwoHandsSide(format!(
                    "both {} hands",
                    side.name()
                ))),
            }
        }
    }
}

/// The hand of one object.
fn find_in(s: &Surface<'_>, obj: &Object, opts: &FindOptions) -> Result<FoundHand, FindError> {
    let axes = surface_axes(s.positions, &obj.tris).ok_or(FindError::Flat)?;
    if !(axes.values[1] > 0.0 && axes.values[1].is_finite()) {
        return Err(FindError::Flat);
    }
    let main = axes.axes[0];
    let (lo, hi) = extent(s, obj, main);
    let length = hi - lo;
    if !(length > 0.0 && length.is_finite()) {
        return Err(FindError::Flat);
    }
    let mut notes = Vec::new();
    let wrist = wrist_ring(s, obj, &axes, opts, &mut notes)?;
    notes.push(wrist.how.clone());
    let g = dijkstra(&s.graph, &wrist.sources, Some(&obj.mask));
    let reach = |v: u32| (s.positions[v as usize] - wrist.centre).dot(wrist.normal);
    let beyond = obj.vertices.iter().map(|&v| reach(v)).fold(0.0, f64::max);
    if !(beyond > 0.0 && beyond.is_finite()) {
        return Err(FindError::NoWrist(
            "the whole mesh lies behind the wrist's plane".into(),
        ));
    }
    let all = persistence(&s.graph, &g);
    let floor = obj
        .vertices
        .iter()
        .map(|&v| g[v as usize])
        .fold(f64::INFINITY, f64::min);
    let mut candidates: Vec<Extremity> = all
        .iter()
        .copied()
        .filter(|e| {
            obj.mask[e.top as usize]
                && reach(e.top) > 0.1 * beyond
                && e.persistence(floor) >= 0.1 * beyond
        })
        .collect();
    candidates.sort_by(|a, b| b.persistence(floor).total_cmp(&a.persistence(floor)));
    let wanted = opts.fingers;
    if candidates.len() < wanted {
        return Err(too_few(candidates.len(), wanted));
    }
    if candidates.len() >= 2 * wanted && two_clusters(s, &candidates, wanted) {
        return Err(FindError::TwoHandsJoined {
            found: candidates.len(),
        });
    }
    if candidates.len() > wanted {
        let left: Vec<String> = candidates[wanted..]
            .iter()
            .map(|e| format!("{} mm", crate::format::num(mm(e.persistence(floor)), 0)))
            .collect();
        notes.push(format!(
            "{} more extremit{} than the {wanted} fingers (persistence {}) {} left out",
            left.len(),
            if left.len() == 1 { "y" } else { "ies" },
            left.join(", "),
            if left.len() == 1 { "was" } else { "were" }
        ));
        candidates.truncate(wanted);
    }
    // Webs: the highest of the saddles where a finger died and where the
    // others died into it.
    let webs: Vec<(f64, u32)> = candidates
        .iter()
        .map(|e| {
            let mut web = e.death.zip(e.saddle);
            for o in &candidates {
                if o.into == Some(e.top)
                    && let (Some(d), Some(sv)) = (o.death, o.saddle)
                    && web.is_none_or(|w| d > w.0)
                {
                    web = Some((d, sv));
                }
            }
            web.unwrap_or_else(|| {
                // The oldest with none merged into it directly: the highest
                // web of the others.
                candidates
                    .iter()
                    .filter_map(|o| o.death.zip(o.saddle))
                    .max_by(|a, b| a.0.total_cmp(&b.0))
                    .unwrap_or((floor, e.top))
            })
        })
        .collect();
    let mut traced: Vec<Traced> = Vec::with_capacity(wanted);
    for (e, &(level, saddle)) in candidates.iter().zip(&webs) {
        let t = trace_finger(s, obj, &g, e, level, saddle)?;
        if !t.trace.exits {
            let p = t.trace.tip;
            notes.push(format!(
                "the axis of the finger ending near ({}, {}, {}) mm does not cross \
                 the skin (its tip is open, or holed); its tip is the farthest skin along the axis",
                crate::format::num(mm(p.x), 1),
                crate::format::num(mm(p.y), 1),
                crate::format::num(mm(p.z), 1)
            ));
        }
        traced.push(t);
    }
    let mut hand = frame(s, obj, &g, &wrist, traced, opts, &mut notes)?;
    hand.notes = notes;
    Ok(hand)
}
