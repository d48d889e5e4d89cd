//! The wrist's ring, where the geodesics start ([`super::find`], step 2):
//! at the point given, else the mesh's open end, else a cut across the main
//! axis inside the end the fingers are not at.

use super::geometry::{Axes, section};
use super::graph::{Extremity, dijkstra, persistence};
use super::hand::{FindError, FindOptions, mm, too_few};
use super::surface::{Object, Surface, extent, two_clusters};
use glam::DVec3;

/// Where the geodesics start: the wrist's ring.
pub(super) struct Wrist {
    pub(super) centre: DVec3,
    /// Unit normal of the wrist's plane, towards the fingers.
    pub(super) normal: DVec3,
    pub(super) sources: Vec<(u32, f64)>,
    pub(super) how: String,
}

/// The wrist's ring (see the module doc, step 2).
pub(super) fn wrist_ring(
    s: &Surface<'_>,
    obj: &Object,
    axes: &Axes,
    opts: &FindOptions,
    notes: &mut Vec<String>,
) -> Result<Wrist, FindError> {
    let main = axes.axes[0];
    let (lo, hi) = extent(s, obj, main);
    let length = hi - lo;
    if let Some(w) = opts.wrist {
        let d = obj.distance(s, w);
        if d > 0.25 * length {
            return Err(FindError::WristOff { distance: mm(d) });
        }
        let normal = if (axes.centre - w).dot(main) >= 0.0 {
            main
        } else {
            -main
        };
        let given = opts.wrist_is.as_deref().unwrap_or("the point given");
        return Ok(given_wrist(s, obj, (w, given), normal, length, notes));
    }
    if let Some(ring) = open_end(s, obj, axes, lo, hi) {
        return Ok(ring);
    }
    // A cut 4% inside the end the fingers are not at.
    let mut counts = [0usize; 2];
    let mut seen: Vec<Extremity> = Vec::new();
    for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
        let normal = main * sign;
        let end = if sign > 0.0 { lo } else { -hi };
        let at = point_on_axis(axes, main, (end + 0.04 * length) * sign);
        let w = cut_at(s, obj, at, normal, String::new(), &mut Vec::new());
        let g = dijkstra(&s.graph, &w.sources, Some(&obj.mask));
        let floor = w.sources.iter().map(|x| x.1).fold(0.0, f64::min);
        let all: Vec<Extremity> = persistence(&s.graph, &g)
            .into_iter()
            .filter(|e| obj.mask[e.top as usize])
            .collect();
        counts[k] = all
            .iter()
            .filter(|e| {
                (s.positions[e.top as usize] - at).dot(normal) > 0.4 * length
                    && e.persistence(floor) >= 0.1 * length
            })
            .count();
        if k == 0 {
            // Two hands joined across the main axis: a hand's worth of
            // extremities on either side (finger-long, a twentieth of the
            // length of both).
            seen = all
                .into_iter()
                .filter(|e| e.persistence(floor) >= 0.05 * length)
                .collect();
        }
    }
    let best = counts[0].max(counts[1]);
    if best < 2 {
        return Err(too_few(best, opts.fingers));
    }
    if counts[0] == counts[1] {
        if seen.len() >= 2 * opts.fingers - 2 && two_clusters(s, &seen, opts.fingers) {
            return Err(FindError::TwoHandsJoined { found: seen.len() });
        }
        return Err(FindError::NoWrist(format!(
            "the mesh has no open end and looks alike from both ends of its length ({} \
             extremities beyond the middle from either)",
            counts[0]
        )));
    }
    let sign = if counts[0] > counts[1] { 1.0 } else { -1.0 };
    let normal = main * sign;
    let end = if sign > 0.0 { lo } else { -hi };
    let at = point_on_axis(axes, main, (end + 0.04 * length) * sign);
    Ok(cut_at(
        s,
        obj,
        at,
        normal,
        format!(
            "the wrist is a cut across the hand's main axis {} mm inside its end (no wrist \
             given, no open end; {} extremities lie beyond the middle from that end, {} from the \
             other); give --wrist X,Y,Z to place it",
            crate::format::num(mm(0.04 * length), 0),
            best,
            counts[0].min(counts[1])
        ),
        notes,
    ))
}

/// The ring for a wrist given at `w`: the plane across the main axis
/// through it, or moved towards the fingers in steps of 2% of the length
/// (at most 10%) until its curve nearest `w` is closed and centred within
/// half its radius of the line through `w` along the axis: a wrist given at
/// the mesh's very end (the Godot hands' wrist bone sits on their flat end)
/// cuts only a sliver of the cap. The hand's wrist stays the point given.
pub(super) fn given_wrist(
    s: &Surface<'_>,
    obj: &Object,
    (w, given): (DVec3, &str),
    normal: DVec3,
    length: f64,
    notes: &mut Vec<String>,
) -> Wrist {
    let off_line = |c: DVec3| {
        let d = c - w;
        (d - normal * d.dot(normal)).length()
    };
    for k in 0..=5 {
        let shift = 0.02 * length * k as f64;
        let at = w + normal * shift;
        let rings = section(s.positions, &obj.tris, at, normal);
        let Some(ring) = rings
            .iter()
            .min_by(|a, b| off_line(a.centre).total_cmp(&off_line(b.centre)))
        else {
            continue;
        };
        if !ring.open && off_line(ring.centre) <= 0.5 * ring.radius {
            let how = if k == 0 {
                format!("the wrist is {given}")
            } else {
                format!(
                    "the wrist is {given}; the geodesics start from the ring {} mm \
                     towards the fingers, where the plane across the hand first closes around it",
                    crate::format::num(mm(shift), 0)
                )
            };
            let mut wrist = ring_sources(s, ring, at, normal, how);
            wrist.centre = w;
            return wrist;
        }
    }
    let mut wrist = cut_at(s, obj, w, normal, format!("the wrist is {given}"), notes);
    wrist.centre = w;
    wrist
}

/// The point of the main axis through the object's centre at projection `x`.
pub(super) fn point_on_axis(axes: &Axes, main: DVec3, x: f64) -> DVec3 {
    axes.centre + main * (x - axes.centre.dot(main))
}

/// The ring where the plane through `at` (normal `normal`) cuts the object,
/// the curve nearest `at`: its centre and its crossed edges' ends, each
/// starting at its distance from the cut. Without a curve, the vertex nearest
/// `at` alone (noted).
pub(super) fn cut_at(
    s: &Surface<'_>,
    obj: &Object,
    at: DVec3,
    normal: DVec3,
    how: String,
    notes: &mut Vec<String>,
) -> Wrist {
    let rings = section(s.positions, &obj.tris, at, normal);
    if let Some(ring) = rings
        .iter()
        .min_by(|a, b| a.centre.distance(at).total_cmp(&b.centre.distance(at)))
    {
        return ring_sources(s, ring, at, normal, how);
    }
    let v = obj
        .vertices
        .iter()
        .copied()
        .min_by(|&a, &b| {
            s.positions[a as usize]
                .distance(at)
                .total_cmp(&s.positions[b as usize].distance(at))
        })
        .unwrap_or(0);
    notes.push(
        "the plane across the hand at the wrist does not cut the mesh; the geodesics start \
         from the vertex nearest the wrist"
            .into(),
    );
    Wrist {
        centre: s.positions[v as usize],
        normal,
        sources: vec![(v, 0.0)],
        how,
    }
}

/// The wrist of a ring cut by the plane through `at`: its centre, and its
/// crossed edges' ends, each starting at its distance from the cut.
pub(super) fn ring_sources(
    s: &Surface<'_>,
    ring: &super::geometry::Ring,
    at: DVec3,
    normal: DVec3,
    how: String,
) -> Wrist {
    let mut sources = Vec::with_capacity(2 * ring.edges.len());
    for &(a, b) in &ring.edges {
        let (pa, pb) = (s.positions[a as usize], s.positions[b as usize]);
        let (sa, sb) = ((pa - at).dot(normal), (pb - at).dot(normal));
        let t = if sa != sb { sa / (sa - sb) } else { 0.5 };
        let x = pa + t * (pb - pa);
        sources.push((a, pa.distance(x)));
        sources.push((b, pb.distance(x)));
    }
    Wrist {
        centre: ring.centre,
        normal,
        sources,
        how: format!(
            "{how} (its ring {} mm around)",
            crate::format::num(mm(ring.perimeter), 0)
        ),
    }
}

/// The mesh's open end as the wrist: its longest border loop, when it is at
/// least half the hand's width around and lies in the outer quarter of the
/// main axis.
pub(super) fn open_end(
    s: &Surface<'_>,
    obj: &Object,
    axes: &Axes,
    lo: f64,
    hi: f64,
) -> Option<Wrist> {
    let mut count: rustc_hash::FxHashMap<(u32, u32), u32> = rustc_hash::FxHashMap::default();
    for t in &obj.tris {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let border: Vec<(u32, u32)> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|(k, _)| k)
        .collect();
    if border.is_empty() {
        return None;
    }
    let n = s.positions.len();
    let mut uf = super::graph::UnionFind::new(n);
    for &(a, b) in &border {
        uf.union(a as usize, b as usize);
    }
    let mut loops: rustc_hash::FxHashMap<usize, (f64, DVec3, Vec<u32>)> =
        rustc_hash::FxHashMap::default();
    for &(a, b) in &border {
        let (pa, pb) = (s.positions[a as usize], s.positions[b as usize]);
        let l = pa.distance(pb);
        let e = loops
            .entry(uf.find(a as usize))
            .or_insert((0.0, DVec3::ZERO, Vec::new()));
        e.0 += l;
        e.1 += l * (pa + pb) / 2.0;
        e.2.push(a);
        e.2.push(b);
    }
    let (perimeter, sum, mut vertices) = loops.into_values().max_by(|a, b| a.0.total_cmp(&b.0))?;
    let width = 3.46 * axes.values[1].max(0.0).sqrt();
    let main = axes.axes[0];
    let length = hi - lo;
    let centre = sum / perimeter;
    let x = centre.dot(main);
    if perimeter.is_nan() || perimeter < 0.5 * width || (x - lo).min(hi - x) > 0.25 * length {
        return None;
    }
    vertices.sort_unstable();
    vertices.dedup();
    let normal = if hi - x > x - lo { main } else { -main };
    Some(Wrist {
        centre,
        normal,
        sources: vertices.into_iter().map(|v| (v, 0.0)).collect(),
        how: format!(
            "the wrist is the mesh's open end, a border {} mm around",
            crate::format::num(mm(perimeter), 0)
        ),
    })
}
