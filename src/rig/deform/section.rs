//! Plane sections of a triangle mesh: closed polylines and their areas.
//!
//! A vertex is on the positive side when its signed distance d >= 0 (so a
//! vertex exactly on the plane counts as positive, consistently for every
//! triangle that shares it); an edge crosses the plane when its ends are on
//! different sides, at the point where d = 0 along it. Each crossing triangle
//! gives one segment between its two crossing edges; segments sharing an
//! edge (vertices welded by position) are chained into polylines, closed when
//! the mesh is closed around them.

use glam::{DVec2, DVec3};
use rustc_hash::FxHashMap as HashMap;

/// A point where the plane cuts a mesh edge: welded vertices `a`, `b` and
/// the fraction `t` from a to b; `at` in the plane's 2-D frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cut {
    pub at: DVec2,
    pub a: u32,
    pub b: u32,
    pub t: f64,
}

impl Cut {
    /// The same surface point on the mesh at other `positions` (same vertex order).
    pub(super) fn carried(&self, positions: &[DVec3]) -> DVec3 {
        let (a, b) = (positions[self.a as usize], positions[self.b as usize]);
        a + (b - a) * self.t
    }
}

/// A plane with an orthonormal frame: `e1`, `e2` span it, `normal` is e1 x e2.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plane {
    pub origin: DVec3,
    pub normal: DVec3,
    pub e1: DVec3,
    pub e2: DVec3,
}

impl Plane {
    /// The plane through `origin` with unit `normal`, `e1` along `across` with
    /// its normal part removed; `None` when `across` is along the normal.
    pub(super) fn new(origin: DVec3, normal: DVec3, across: DVec3) -> Option<Plane> {
        let e1 = (across - normal * across.dot(normal)).try_normalize()?;
        Some(Plane {
            origin,
            normal,
            e1,
            e2: normal.cross(e1),
        })
    }

    /// `p` in the plane's frame (its part along the normal dropped).
    pub(super) fn to_2d(self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.e1), d.dot(self.e2))
    }
}

/// The closed polylines where `plane` cuts the triangles `tris` of a mesh,
/// in the plane's 2-D frame. Each triangle's segment is directed along
/// n x N (n the plane's normal, N the triangle's by its vertex order), so on
/// a closed mesh whose triangles face outwards every loop runs
/// counter-clockwise around the inside, and the loops' signed areas add up to
/// the winding-number integral of the section. (On a mesh of inconsistent
/// orientation a segment may be followed backwards to close a loop.) Open
/// polylines (a mesh with holes) are dropped. Cost O(triangles).
pub(crate) fn loops(
    positions: &[DVec3],
    welded: &[u32],
    tris: &[[u32; 3]],
    plane: &Plane,
) -> Vec<Vec<Cut>> {
    let key = |a: u32, b: u32| {
        let (a, b) = (welded[a as usize], welded[b as usize]);
        if a < b { (a, b) } else { (b, a) }
    };
    let pos = |v: u32| positions[welded[v as usize] as usize];
    let dist = |v: u32| (pos(v) - plane.origin).dot(plane.normal);
    // Directed segments between edge keys; each edge key's crossing point.
    let mut points: HashMap<(u32, u32), Cut> = HashMap::default();
    let mut segments: Vec<[(u32, u32); 2]> = Vec::new();
    // A segment of zero length (the plane through a vertex) has no direction of its own.
    let mut degenerate: Vec<bool> = Vec::new();
    for t in tris {
        let d = t.map(dist);
        let side = d.map(|x| x >= 0.0);
        if side[0] == side[1] && side[1] == side[2] {
            continue;
        }
        let mut ends = Vec::with_capacity(2);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if side[i] != side[j] {
                let k = key(t[i], t[j]);
                let p = *points.entry(k).or_insert_with(|| {
                    let (a, b) = (positions[k.0 as usize], positions[k.1 as usize]);
                    let (da, db) = (
                        (a - plane.origin).dot(plane.normal),
                        (b - plane.origin).dot(plane.normal),
                    );
                    let t = da / (da - db);
                    Cut {
                        at: plane.to_2d(a + (b - a) * t),
                        a: k.0,
                        b: k.1,
                        t,
                    }
                });
                ends.push((k, p.at));
            }
        }
        if let [(ka, pa), (kb, pb)] = ends[..] {
            let normal = (pos(t[1]) - pos(t[0])).cross(pos(t[2]) - pos(t[0]));
            let along = plane.normal.cross(normal);
            let dir = DVec2::new(along.dot(plane.e1), along.dot(plane.e2));
            degenerate.push(pa == pb);
            if (pb - pa).dot(dir) >= 0.0 {
                segments.push([ka, kb]);
            } else {
                segments.push([kb, ka]);
            }
        }
    }
    let mut starting: HashMap<(u32, u32), Vec<usize>> = HashMap::default();
    let mut ending: HashMap<(u32, u32), Vec<usize>> = HashMap::default();
    for (i, s) in segments.iter().enumerate() {
        starting.entry(s[0]).or_default().push(i);
        ending.entry(s[1]).or_default().push(i);
    }
    let free = |m: &HashMap<(u32, u32), Vec<usize>>, k: &(u32, u32), used: &[bool]| {
        m.get(k).and_then(|c| c.iter().copied().find(|&s| !used[s]))
    };
    let mut used = vec![false; segments.len()];
    let mut out = Vec::new();
    // Loops start from segments with a direction, so each runs the right way round.
    let mut starts: Vec<usize> = (0..segments.len()).collect();
    starts.sort_by_key(|&i| degenerate[i]);
    for start in starts {
        if used[start] {
            continue;
        }
        used[start] = true;
        let first = segments[start][0];
        let mut at = segments[start][1];
        let mut poly = vec![points[&first], points[&at]];
        let mut closed = false;
        loop {
            if at == first {
                closed = true;
                poly.pop();
                break;
            }
            // Forwards when the orientation allows, else backwards.
            let next = match free(&starting, &at, &used) {
                Some(s) => Some((s, segments[s][1])),
                None => free(&ending, &at, &used).map(|s| (s, segments[s][0])),
            };
            let Some((s, to)) = next else { break };
            used[s] = true;
            at = to;
            poly.push(points[&at]);
        }
        if closed && poly.len() >= 3 {
            out.push(poly);
        }
    }
    out
}

/// Signed area by the shoelace formula (positive counter-clockwise). For a
/// self-crossing polygon it is the integral of the winding number.
pub(crate) fn shoelace(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| poly[i].perp_dot(poly[(i + 1) % n]))
        .sum::<f64>()
        / 2.0
}

/// The vector area of a closed 3-D polygon, (1/2) sum p_i x p_(i+1): its
/// length is the area of the polygon's projection on the plane where that
/// projection is largest (the polygon's own plane when it is flat), its
/// direction that plane's normal, counter-clockwise.
pub(crate) fn vector_area(poly: &[DVec3]) -> DVec3 {
    let n = poly.len();
    (0..n)
        .map(|i| poly[i].cross(poly[(i + 1) % n]))
        .sum::<DVec3>()
        / 2.0
}

/// The winding number of `poly` around `p`.
pub(crate) fn winding(poly: &[DVec2], p: DVec2) -> i32 {
    let n = poly.len();
    let mut w = 0;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let side = (b - a).perp_dot(p - a);
        if a.y <= p.y {
            if b.y > p.y && side > 0.0 {
                w += 1;
            }
        } else if b.y <= p.y && side < 0.0 {
            w -= 1;
        }
    }
    w
}

/// `poly` clipped to the strip |x| <= `half` (Sutherland-Hodgman against its
/// two half-planes; the signed area of the result is the winding-number
/// integral of `poly` over the strip, also for a self-crossing polygon). Each
/// vertex carries a 3-D point, interpolated along with it.
pub(crate) fn clip_strip(poly: &[(DVec2, DVec3)], half: f64) -> Vec<(DVec2, DVec3)> {
    if !half.is_finite() {
        return poly.to_vec();
    }
    let clip = |poly: &[(DVec2, DVec3)], sign: f64| -> Vec<(DVec2, DVec3)> {
        let inside = |p: DVec2| sign * p.x <= half;
        let n = poly.len();
        let mut out = Vec::with_capacity(n + 4);
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            match (inside(a.0), inside(b.0)) {
                (true, true) => out.push(b),
                (true, false) | (false, true) => {
                    let t = (sign * half - a.0.x) / (b.0.x - a.0.x);
                    out.push((a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
                    if inside(b.0) {
                        out.push(b);
                    }
                }
                (false, false) => {}
            }
        }
        out
    };
    let once = clip(poly, 1.0);
    clip(&once, -1.0)
}

/// Do the polygons' edges cross (properly)?
fn edges_cross(a: &[DVec2], b: &[DVec2]) -> bool {
    let (na, nb) = (a.len(), b.len());
    let lo_hi = |p: &[DVec2]| {
        p.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), q| (lo.min(*q), hi.max(*q)),
        )
    };
    let ((la, ha), (lb, hb)) = (lo_hi(a), lo_hi(b));
    if la.cmpgt(hb).any() || lb.cmpgt(ha).any() {
        return false;
    }
    for i in 0..na {
        let (p, q) = (a[i], a[(i + 1) % na]);
        for k in 0..nb {
            let (r, s) = (b[k], b[(k + 1) % nb]);
            let d1 = (q - p).perp_dot(r - p);
            let d2 = (q - p).perp_dot(s - p);
            let d3 = (s - r).perp_dot(p - r);
            let d4 = (s - r).perp_dot(q - r);
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                return true;
            }
        }
    }
    false
}

/// The section of the skin around the plane's origin, as indices into
/// `loops`: the loop that winds around it (the one of least area when several
/// do), together with every loop that crosses it or lies inside it, and so on.
/// `None` when no loop winds around the origin.
pub(crate) fn around_origin(loops: &[Vec<DVec2>]) -> Option<Vec<usize>> {
    let main = loops
        .iter()
        .enumerate()
        .filter(|(_, l)| winding(l, DVec2::ZERO) != 0)
        .min_by(|a, b| shoelace(a.1).abs().total_cmp(&shoelace(b.1).abs()))
        .map(|(i, _)| i)?;
    let mut group = vec![main];
    let mut k = 0;
    while k < group.len() {
        let g = group[k];
        for (i, l) in loops.iter().enumerate() {
            if !group.contains(&i) && (edges_cross(&loops[g], l) || winding(&loops[g], l[0]) != 0) {
                group.push(i);
            }
        }
        k += 1;
    }
    group.sort_unstable();
    Some(group)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_unit_cube_cut_in_half_is_a_unit_square() {
        // The 12 triangles of the unit cube, cut by z = 0.5: area 1 by hand.
        let p: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        // Each face counter-clockwise seen from outside.
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let tris: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let welded: Vec<u32> = (0..8).collect();
        let plane = Plane::new(DVec3::new(0.5, 0.5, 0.5), DVec3::Z, DVec3::X).unwrap();
        let l: Vec<Vec<DVec2>> = loops(&p, &welded, &tris, &plane)
            .iter()
            .map(|l| l.iter().map(|c| c.at).collect())
            .collect();
        assert_eq!(l.len(), 1);
        assert_eq!(around_origin(&l), Some(vec![0]));
        // The cube's triangles face outwards: the loop runs counter-clockwise.
        assert!((shoelace(&l[0]) - 1.0).abs() < 1e-12);
        assert_eq!(winding(&l[0], DVec2::ZERO), 1);
        // Clipped to |x| <= 0.25: half the square.
        let carried: Vec<(DVec2, DVec3)> = l[0]
            .iter()
            .map(|p| (*p, DVec3::new(p.x, p.y, 0.0)))
            .collect();
        let clipped = clip_strip(&carried, 0.25);
        let flat: Vec<DVec2> = clipped.iter().map(|c| c.0).collect();
        assert!((shoelace(&flat) - 0.5).abs() < 1e-12);
        // The carried points are clipped alike.
        assert!(
            clipped
                .iter()
                .all(|(a, b)| (a.x - b.x).abs() < 1e-15 && (a.y - b.y).abs() < 1e-15)
        );
        // Through a vertex-level plane (z = 0 exactly): still one closed loop.
        let plane = Plane::new(DVec3::new(0.5, 0.5, 1.0), DVec3::Z, DVec3::X).unwrap();
        let l = loops(&p, &welded, &tris, &plane);
        assert_eq!(l.len(), 1);
        let flat: Vec<DVec2> = l[0].iter().map(|c| c.at).collect();
        assert!((shoelace(&flat) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_figure_eight_counts_its_lobes_against_each_other() {
        // Two unit-square lobes traversed in opposite senses: net area 0.
        let fig8 = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
        ];
        assert!(shoelace(&fig8).abs() < 1e-15);
        let square = [
            DVec2::new(-1.0, -1.0),
            DVec2::new(1.0, -1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(-1.0, 1.0),
        ];
        assert_eq!(winding(&square, DVec2::ZERO), 1);
        assert_eq!(winding(&square, DVec2::new(2.0, 0.0)), 0);
        // A loop through the square's edges joins it; one far away does not.
        let crossing = square.map(|p| p + DVec2::new(1.5, 0.0));
        let far = square.map(|p| p + DVec2::new(9.0, 0.0));
        let got = around_origin(&[far.to_vec(), square.to_vec(), crossing.to_vec()]);
        assert_eq!(got, Some(vec![1, 2]));
    }
}
