//! The geometry of a rig finger's chain: the polyline through its joint
//! centres, positions along it by arc length, and the solver that moves the
//! inner joints along it so the chords have given proportions.
//!
//! Suggested positions stay on the rig's own chain, with root and tip (or DIP)
//! fixed, and are solved so the new chords have exactly the mean proportions.
//! Pure geometry: no statistics, no files, no glTF.

use glam::DVec3;

/// The point at arc length `u` along the polyline `points` (clamped to its ends). O(m).
pub(crate) fn point_at(points: &[DVec3], u: f64) -> DVec3 {
    let mut left = u.max(0.0);
    for w in points.windows(2) {
        let c = w[0].distance(w[1]);
        if left <= c {
            return if c > 0.0 {
                w[0].lerp_monotonic(w[1], left / c)
            } else {
                w[0]
            };
        }
        left -= c;
    }
    points.last().copied().unwrap_or(DVec3::ZERO)
}

/// Arc positions of the vertices of a polyline: 0, c_1, c_1 + c_2, ... O(m).
pub(crate) fn arc_positions(points: &[DVec3]) -> Vec<f64> {
    let mut out = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    out.push(0.0);
    for w in points.windows(2) {
        acc += w[0].distance(w[1]);
        out.push(acc);
    }
    out
}

/// The first arc position at or after `u0` whose point lies at distance `d`
/// from `q`; `None` past the end of the polyline. O(m).
///
/// On the segment a + t (b - a), |a + t (b - a) - q|^2 = d^2 is the quadratic
/// |b - a|^2 t^2 + 2 (a - q).(b - a) t + |a - q|^2 - d^2 = 0.
pub fn forward_at(points: &[DVec3], arcs: &[f64], u0: f64, q: DVec3, d: f64) -> Option<f64> {
    for (k, w) in points.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let len = arcs[k + 1] - arcs[k];
        if arcs[k + 1] < u0 || len <= 0.0 {
            continue;
        }
        let t0 = ((u0 - arcs[k]) / len).max(0.0);
        let ab = b - a;
        let aq = a - q;
        let qa = ab.length_squared();
        let qb = 2.0 * aq.dot(ab);
        let qc = aq.length_squared() - d * d;
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            continue;
        }
        let r = disc.sqrt();
        let mut roots = [(-qb - r) / (2.0 * qa), (-qb + r) / (2.0 * qa)];
        roots.sort_by(f64::total_cmp);
        if let Some(t) = roots
            .into_iter()
            .find(|t| *t >= t0 - 1e-12 && *t <= 1.0 + 1e-12)
        {
            return Some(arcs[k] + t.clamp(0.0, 1.0) * len);
        }
    }
    None
}

/// The last arc position at or before `u0` whose point lies at distance `d`
/// from `q`, walking towards the start; `None` past the start. O(m).
/// (The forward search on the reversed polyline.)
pub fn backward_at(points: &[DVec3], arcs: &[f64], u0: f64, q: DVec3, d: f64) -> Option<f64> {
    let total = *arcs.last()?;
    let rev: Vec<DVec3> = points.iter().rev().copied().collect();
    let rev_arcs: Vec<f64> = arcs.iter().rev().map(|a| total - a).collect();
    forward_at(&rev, &rev_arcs, total - u0, q, d).map(|u| total - u)
}

/// The arc position of the point of the polyline nearest to `p`, and that
/// point. Ties go to the earlier segment. O(m).
pub fn project(points: &[DVec3], arcs: &[f64], p: DVec3) -> (f64, DVec3) {
    let mut best = (
        f64::INFINITY,
        0.0,
        points.first().copied().unwrap_or(DVec3::ZERO),
    );
    for (k, w) in points.windows(2).enumerate() {
        let ab = w[1] - w[0];
        let len2 = ab.length_squared();
        let t = if len2 > 0.0 {
            ((p - w[0]).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = w[0] + t * ab;
        let d = q.distance_squared(p);
        if d < best.0 {
            best = (d, arcs[k] + t * (arcs[k + 1] - arcs[k]), q);
        }
    }
    (best.1, best.2)
}

/// New inner points on the polyline `points` (ends fixed) whose chords have the
/// proportions `shares` (summing to 1), with their arc positions: the first
/// point, `shares.len() - 1` inner points, the last point. A chain re-laid on
/// itself has one share per segment; a finger laid on a traced axis has
/// fewer shares than the axis has segments.
///
/// For a trial total chord C the points are laid one after the other, each the
/// first point along the chain at chord distance share_k x C from the one
/// before, and C is bisected until the last chord is share_m x C; so the points
/// keep their order on the chain. 200 bisection steps, O(m) each. `None` when
/// the chain is degenerate (non-finite, zero length) or no such C exists.
pub(crate) fn on_chain(points: &[DVec3], shares: &[f64]) -> Option<(Vec<DVec3>, Vec<f64>)> {
    let m = points.len().checked_sub(1)?;
    let k = shares.len();
    if m < 1 || k < 2 || shares.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return None;
    }
    let arcs = arc_positions(points);
    let arc = arcs[m];
    if !(arc.is_finite() && arc > 0.0) || points.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let lay = |c: f64| -> Option<(Vec<f64>, f64)> {
        let mut u = Vec::with_capacity(k - 1);
        let (mut at, mut q) = (0.0, points[0]);
        for s in &shares[..k - 1] {
            at = forward_at(points, &arcs, at, q, s * c)?;
            q = point_at(points, at);
            u.push(at);
        }
        Some((u, q.distance(points[m]) - shares[k - 1] * c))
    };
    let (mut lo, mut hi) = (0.0, arc);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        match lay(mid) {
            Some((_, f)) if f > 0.0 => lo = mid,
            _ => hi = mid,
        }
    }
    let (u, f) = lay(lo)?;
    if f.abs() > 1e-9 * arc {
        return None;
    }
    let mut q = Vec::with_capacity(k + 1);
    q.push(points[0]);
    q.extend(u.iter().map(|&x| point_at(points, x)));
    q.push(points[m]);
    Some((q, u))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chord proportions of a polyline.
    fn shares_of(q: &[DVec3]) -> Vec<f64> {
        let c: Vec<f64> = q.windows(2).map(|w| w[0].distance(w[1])).collect();
        let total: f64 = c.iter().sum();
        c.iter().map(|ck| ck / total).collect()
    }

    #[test]
    fn a_bent_chain_gets_exact_mean_proportions_and_keeps_its_ends() {
        let pts = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(40.0, 0.0, 0.0),
            DVec3::new(60.0, -10.0, 0.0),
            DVec3::new(70.0, -25.0, 3.0),
        ];
        let shares = [0.48, 0.29, 0.23];
        let (q, _) = on_chain(&pts, &shares).unwrap();
        assert_eq!(q[0], pts[0]);
        assert_eq!(q[3], pts[3]);
        for (got, s) in shares_of(&q).into_iter().zip(shares) {
            assert!((got - s).abs() < 1e-12, "{q:?}");
        }
    }

    #[test]
    fn backward_search_and_projection_by_hand() {
        // Along x from 0 to 10 then up y to (10, 10): from u = 15 ((10, 5)),
        // walking back, the first point 5 from (10, 5) is (10, 0) at u = 10;
        // 5.0 further than that from the end is none within the polyline at 13.
        let pts = [
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
        ];
        let arcs = arc_positions(&pts);
        let q = DVec3::new(10.0, 5.0, 0.0);
        let u = backward_at(&pts, &arcs, 15.0, q, 5.0).unwrap();
        assert!((u - 10.0).abs() < 1e-12, "{u}");
        // sqrt(5^2 + 5^2) from (10, 5) is (5, 0), at u = 5.
        let u = backward_at(&pts, &arcs, 15.0, q, 50f64.sqrt()).unwrap();
        assert!((u - 5.0).abs() < 1e-9, "{u}");
        assert!(backward_at(&pts, &arcs, 15.0, q, 20.0).is_none());
        // (4, 3) projects to (4, 0) at u = 4; (12, 7) to (10, 7) at u = 17.
        let (u, p) = project(&pts, &arcs, DVec3::new(4.0, 3.0, 0.0));
        assert_eq!((u, p), (4.0, DVec3::new(4.0, 0.0, 0.0)));
        let (u, _) = project(&pts, &arcs, DVec3::new(12.0, 7.0, 0.0));
        assert!((u - 17.0).abs() < 1e-12);
    }

    #[test]
    fn point_at_walks_the_chain_by_arc_length_and_clamps_at_its_ends() {
        // A 3-4-5 corner: 3 along x, then 4 along y (by hand: arc 5 is (3, 2, 0)).
        let pts = [
            DVec3::ZERO,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(3.0, 4.0, 0.0),
        ];
        assert_eq!(arc_positions(&pts), vec![0.0, 3.0, 7.0]);
        assert_eq!(point_at(&pts, 1.5), DVec3::new(1.5, 0.0, 0.0));
        assert_eq!(point_at(&pts, 5.0), DVec3::new(3.0, 2.0, 0.0));
        assert_eq!(point_at(&pts, -1.0), pts[0]);
        assert_eq!(point_at(&pts, 99.0), pts[2]);
        assert_eq!(point_at(&[], 1.0), DVec3::ZERO);
    }
}
