//! The geometry [`super::find`] measures with: principal axes of a surface,
//! plane sections of a mesh (the rings whose centres trace a finger's axis),
//! where a line crosses a mesh, and points on a polyline.

use glam::{DMat3, DVec3};
use rustc_hash::FxHashMap;

/// Principal axes of a surface: its area-weighted centre and the axes of its
/// spread, largest first.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Axes {
    pub centre: DVec3,
    /// Variances along `axes`, largest first.
    pub values: [f64; 3],
    pub axes: [DVec3; 3],
}

/// The principal axes of the triangles `tris` of `positions`, each
/// triangle's centroid weighted by its area; `None` without area. O(T).
pub(crate) fn surface_axes(positions: &[DVec3], tris: &[[u32; 3]]) -> Option<Axes> {
    let mut area = 0.0;
    let mut sum = DVec3::ZERO;
    let parts: Vec<(DVec3, f64)> = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let w = 0.5 * (b - a).cross(c - a).length();
            ((a + b + c) / 3.0, w)
        })
        .filter(|(_, w)| w.is_finite() && *w > 0.0)
        .collect();
    for &(c, w) in &parts {
        area += w;
        sum += w * c;
    }
    if !(area > 0.0 && area.is_finite()) {
        return None;
    }
    let centre = sum / area;
    let mut cov = DMat3::ZERO;
    for &(c, w) in &parts {
        let d = c - centre;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z) * (w / area);
    }
    let (values, axes) = symmetric_eigen(cov);
    Some(Axes {
        centre,
        values,
        axes,
    })
}

/// Eigenvalues (largest first) and unit eigenvectors of a symmetric 3x3
/// matrix, by cyclic Jacobi rotations (Numerical Recipes, section 11.1);
/// 50 sweeps is far more than a 3x3 needs.
pub(crate) fn symmetric_eigen(m: DMat3) -> ([f64; 3], [DVec3; 3]) {
    let mut a = m.to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-32 * diag || off == 0.0 || !off.is_finite() {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in &mut v {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
        }
    }
    let col = |j: usize| DVec3::new(v[0][j], v[1][j], v[2][j]).normalize_or_zero();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    (order.map(|i| a[i][i]), order.map(col))
}

/// One closed curve (or an open piece of one) where a plane cuts a mesh.
#[derive(Debug, Clone)]
pub(crate) struct Ring {
    /// The centre of the curve, each piece weighted by its length.
    pub centre: DVec3,
    /// The length-weighted mean distance of the curve from its centre.
    pub radius: f64,
    pub perimeter: f64,
    /// True when the curve is no closed loop: it runs between edges with one
    /// triangle of those cut (the mesh's border or the border of the
    /// triangles given). Dangling pieces of a closed loop (a fin's flap) are
    /// left out of it.
    pub open: bool,
    /// The mesh edges the curve crosses (lower vertex first).
    pub edges: Vec<(u32, u32)>,
}

/// A piece of a section: its two ends and the two mesh edges they lie on.
type Segment = (DVec3, DVec3, [(u32, u32); 2]);

/// The curves where the plane through `point` with normal `normal` cuts the
/// triangles `tris` of `positions`: each triangle with vertices on both sides
/// gives a segment between its two crossed edges; segments sharing an edge
/// are one curve. A vertex on the plane counts as on its positive side, so
/// every crossed edge is crossed the same way in both its triangles. O(T).
pub(crate) fn section(
    positions: &[DVec3],
    tris: &[[u32; 3]],
    point: DVec3,
    normal: DVec3,
) -> Vec<Ring> {
    let segments = cut(positions, tris, point, normal);
    // Segments sharing a crossed edge belong to one curve.
    let mut uf = super::graph::UnionFind::new(segments.len());
    let mut owner: FxHashMap<(u32, u32), (usize, u32)> = FxHashMap::default();
    for (i, s) in segments.iter().enumerate() {
        for key in s.2 {
            let e = owner.entry(key).or_insert((i, 0));
            e.1 += 1;
            uf.union(i, e.0);
        }
    }
    let count: FxHashMap<(u32, u32), u32> = owner.iter().map(|(k, v)| (*k, v.1)).collect();
    let pruned = dangling(&segments, count);
    let mut by_root: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
    for i in 0..segments.len() {
        by_root.entry(uf.find(i)).or_default().push(i);
    }
    let mut roots: Vec<usize> = by_root.keys().copied().collect();
    roots.sort_unstable();
    roots
        .into_iter()
        .filter_map(|r| {
            let all = &by_root[&r];
            let kept: Vec<usize> = all.iter().copied().filter(|&i| !pruned[i]).collect();
            let open = kept.is_empty();
            ring_of(&segments, if open { all } else { &kept }, open)
        })
        .collect()
}

/// The segments where the plane through `point` with normal `normal` cuts
/// the triangles `tris`, one per triangle with vertices on both sides.
fn cut(positions: &[DVec3], tris: &[[u32; 3]], point: DVec3, normal: DVec3) -> Vec<Segment> {
    let side = |i: u32| (positions[i as usize] - point).dot(normal);
    let mut segments: Vec<Segment> = Vec::new();
    for t in tris {
        let s = t.map(side);
        let neg = s.map(|x| x < 0.0);
        if neg[0] == neg[1] && neg[1] == neg[2] {
            continue;
        }
        let mut ends = [DVec3::ZERO; 2];
        let mut keys = [(0u32, 0u32); 2];
        let mut k = 0;
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            if neg[a] != neg[b] && k < 2 {
                let u = s[a] / (s[a] - s[b]);
                let (pa, pb) = (positions[t[a] as usize], positions[t[b] as usize]);
                ends[k] = pa + u * (pb - pa);
                keys[k] = (t[a].min(t[b]), t[a].max(t[b]));
                k += 1;
            }
        }
        if k == 2 {
            segments.push((ends[0], ends[1], keys));
        }
    }
    segments
}

/// The dangling segments (a fin's flap: a segment with a crossed edge no
/// other segment shares), pruned leaf by leaf given each crossed edge's
/// `count` of segments; what stays is the closed curve. A curve pruned away
/// entirely is open: it ran from border to border.
fn dangling(segments: &[Segment], mut count: FxHashMap<(u32, u32), u32>) -> Vec<bool> {
    let mut by_edge: FxHashMap<(u32, u32), Vec<usize>> = FxHashMap::default();
    for (i, s) in segments.iter().enumerate() {
        for key in s.2 {
            by_edge.entry(key).or_default().push(i);
        }
    }
    let mut pruned = vec![false; segments.len()];
    let mut queue: Vec<usize> = (0..segments.len())
        .filter(|&i| segments[i].2.iter().any(|k| count[k] == 1))
        .collect();
    while let Some(i) = queue.pop() {
        if pruned[i] || !segments[i].2.iter().any(|k| count[k] == 1) {
            continue;
        }
        pruned[i] = true;
        for key in segments[i].2 {
            let c = count.entry(key).or_insert(1);
            *c = c.saturating_sub(1);
            if *c == 1 {
                queue.extend(by_edge[&key].iter().copied().filter(|&j| !pruned[j]));
            }
        }
    }
    pruned
}

/// The ring of the segments `members`: its length-weighted centre, mean
/// radius, perimeter and crossed edges; `None` for a curve of no length.
fn ring_of(segments: &[Segment], members: &[usize], open: bool) -> Option<Ring> {
    let mut length = 0.0;
    let mut sum = DVec3::ZERO;
    let mut edges = Vec::with_capacity(members.len());
    for &i in members {
        let (a, b, keys) = segments[i];
        let l = a.distance(b);
        length += l;
        sum += l * (a + b) / 2.0;
        edges.extend(keys);
    }
    edges.sort_unstable();
    edges.dedup();
    if !(length > 0.0 && length.is_finite()) {
        return None;
    }
    let centre = sum / length;
    let radius = members
        .iter()
        .map(|&i| {
            let (a, b, _) = segments[i];
            a.distance(b) * ((a + b) / 2.0).distance(centre)
        })
        .sum::<f64>()
        / length;
    Some(Ring {
        centre,
        radius,
        perimeter: length,
        open,
        edges,
    })
}

/// Where the line `origin + t dir` crosses the triangles `tris`: every `t`
/// (either side of the origin), by Moller and Trumbore's test with a small
/// tolerance so that a line through an edge or a vertex is not lost. O(T).
pub(crate) fn line_crossings(
    positions: &[DVec3],
    tris: &[[u32; 3]],
    origin: DVec3,
    dir: DVec3,
) -> Vec<f64> {
    const EPS: f64 = 1e-9;
    let mut out = Vec::new();
    for t in tris {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let h = dir.cross(e2);
        let det = e1.dot(h);
        let scale = e1.length() * e2.length() * dir.length();
        if det.is_nan() || det.abs() <= 1e-12 * scale {
            continue;
        }
        let f = 1.0 / det;
        let s = origin - a;
        let u = f * s.dot(h);
        let q = s.cross(e1);
        let v = f * dir.dot(q);
        if u < -EPS || v < -EPS || u + v > 1.0 + EPS {
            continue;
        }
        let t = f * e2.dot(q);
        if t.is_finite() {
            out.push(t);
        }
    }
    out
}

/// The cumulative arc length at each point of a polyline.
pub(crate) fn arcs(points: &[DVec3]) -> Vec<f64> {
    let mut out = Vec::with_capacity(points.len());
    let mut s = 0.0;
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            s += p.distance(points[i - 1]);
        }
        out.push(s);
    }
    out
}

/// The nearest point of a polyline to `q`: its arc position and distance.
/// A single point is its own polyline. O(n).
pub(crate) fn nearest_on(points: &[DVec3], q: DVec3) -> (f64, f64) {
    if points.len() == 1 {
        return (0.0, points[0].distance(q));
    }
    let mut best = (0.0, f64::INFINITY);
    let mut s = 0.0;
    for w in points.windows(2) {
        let ab = w[1] - w[0];
        let len2 = ab.length_squared();
        let t = if len2 > 0.0 {
            ((q - w[0]).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (w[0] + t * ab).distance(q);
        if d < best.1 {
            best = (s + t * len2.sqrt(), d);
        }
        s += len2.sqrt();
    }
    best
}

/// The point of a polyline at arc position `s` (clamped to its ends).
pub(crate) fn point_at(points: &[DVec3], s: f64) -> DVec3 {
    let mut at = 0.0;
    for w in points.windows(2) {
        let l = w[0].distance(w[1]);
        if s <= at + l && l > 0.0 {
            return w[0] + (w[1] - w[0]) * ((s - at) / l).clamp(0.0, 1.0);
        }
        at += l;
    }
    points.last().copied().unwrap_or(DVec3::ZERO)
}

/// The unit direction of the least-squares line through `points` (their
/// principal axis), turned to agree with `towards`; `None` for fewer than two
/// distinct points.
pub(crate) fn line_direction(points: &[DVec3], towards: DVec3) -> Option<DVec3> {
    if points.len() < 2 {
        return None;
    }
    let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let mut cov = DMat3::ZERO;
    for p in points {
        let d = *p - c;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let (values, axes) = symmetric_eigen(cov);
    if !(values[0] > 0.0 && values[0].is_finite()) {
        return None;
    }
    let d = axes[0].try_normalize()?;
    Some(if d.dot(towards) < 0.0 { -d } else { d })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed tube of `around` x `rings` quads about the z axis, radius r,
    /// from z = 0 to z = len, capped by fans at both ends.
    fn tube(around: usize, rings: usize, r: f64, len: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for k in 0..=rings {
            for i in 0..around {
                let a = i as f64 / around as f64 * std::f64::consts::TAU;
                p.push(DVec3::new(
                    r * a.cos(),
                    r * a.sin(),
                    len * k as f64 / rings as f64,
                ));
            }
        }
        let at = |k: usize, i: usize| (k * around + i % around) as u32;
        let mut t = Vec::new();
        for k in 0..rings {
            for i in 0..around {
                t.push([at(k, i), at(k, i + 1), at(k + 1, i + 1)]);
                t.push([at(k, i), at(k + 1, i + 1), at(k + 1, i)]);
            }
        }
        let (b, e) = (p.len() as u32, p.len() as u32 + 1);
        p.push(DVec3::ZERO);
        p.push(DVec3::new(0.0, 0.0, len));
        for i in 0..around {
            t.push([b, at(0, i + 1), at(0, i)]);
            t.push([e, at(rings, i), at(rings, i + 1)]);
        }
        (p, t)
    }

    #[test]
    fn a_section_of_a_tube_is_one_closed_ring_around_its_axis() {
        let (p, t) = tube(24, 10, 2.0, 10.0);
        // An oblique cut at z = 5.3: an ellipse centred on the axis.
        let n = DVec3::new(0.3, 0.0, 1.0).normalize();
        let rings = section(&p, &t, DVec3::new(0.0, 0.0, 5.3), n);
        assert_eq!(rings.len(), 1);
        let r = &rings[0];
        assert!(!r.open);
        assert!(r.centre.truncate().length() < 1e-9, "{:?}", r.centre);
        assert!((r.centre.z - 5.3).abs() < 1e-9);
        // Perimeter of a regular 24-gon of radius 2 stretched along x by
        // 1/cos: between 2 pi r and that times 1.05.
        assert!(r.perimeter > 12.5 && r.perimeter < 13.3, "{}", r.perimeter);
        // A fin on the tube (a third triangle on one of its edges, its corner
        // off the skin) is pruned from the ring: the same centre, closed.
        let mut finned = t.clone();
        let mut q = p.clone();
        q.push(DVec3::new(3.0, 0.0, 5.5));
        finned.push([t[240][0], t[240][1], q.len() as u32 - 1]);
        let with = section(&q, &finned, DVec3::new(0.0, 0.0, 5.3), n);
        assert_eq!(with.len(), 1);
        assert!(!with[0].open);
        assert!((with[0].centre - r.centre).length() < 1e-9, "{:?}", with[0]);
        // Cutting only the tube's first half of triangles leaves it open.
        let half: Vec<[u32; 3]> = t[..t.len() / 4].to_vec();
        let rings = section(&p, &half, DVec3::new(0.0, 0.0, 2.5), DVec3::Z);
        assert!(rings.iter().all(|r| r.open), "{rings:?}");
    }

    #[test]
    fn the_axis_of_a_tube_leaves_it_at_its_caps() {
        let (p, t) = tube(16, 4, 1.0, 8.0);
        let mut hits = line_crossings(&p, &t, DVec3::new(0.0, 0.0, 3.0), DVec3::Z);
        hits.sort_by(f64::total_cmp);
        // The line through the fans' centres meets every fan triangle at its
        // shared vertex: the ends at t = -3 and t = 5.
        assert!((hits[0] + 3.0).abs() < 1e-9 && (hits[hits.len() - 1] - 5.0).abs() < 1e-9);
    }

    #[test]
    fn principal_axes_of_a_long_tube() {
        let (p, t) = tube(16, 20, 1.0, 20.0);
        let a = surface_axes(&p, &t).unwrap();
        assert!(a.axes[0].dot(DVec3::Z).abs() > 0.999);
        assert!((a.centre - DVec3::new(0.0, 0.0, 10.0)).length() < 1e-6);
        assert!(a.values[0] > a.values[1] && a.values[1] >= a.values[2]);
    }

    #[test]
    fn the_nearest_point_of_a_polyline() {
        let pts = [DVec3::ZERO, DVec3::X * 2.0, DVec3::new(2.0, 2.0, 0.0)];
        assert_eq!(nearest_on(&pts, DVec3::new(1.0, 1.0, 0.0)), (1.0, 1.0));
        assert_eq!(nearest_on(&pts, DVec3::new(3.0, 1.5, 0.0)), (3.5, 1.0));
        assert_eq!(arcs(&pts), vec![0.0, 2.0, 4.0]);
    }
}
