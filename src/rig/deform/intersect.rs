//! Which triangles of a mesh cross each other: an exact triangle-triangle
//! test and a uniform grid to find the candidates.
//!
//! The test uses only the sign of orient3d, evaluated exactly by the `robust`
//! crate (Shewchuk's adaptive predicates), so it never errs by rounding. Two
//! triangles in general position intersect exactly when an edge of one
//! pierces the other: their intersection is a segment whose ends lie on
//! edges. So the test asks, for each edge whose ends lie strictly on opposite
//! sides of the other triangle's plane, whether the edge passes strictly
//! inside the other triangle's three edges (the signs of orient3d(p, q, a, b)
//! over the triangle's edges ab agree). Contact without crossing (touching at
//! a point or along an edge) and coplanar overlap do not count: neither is a
//! crossing of the skin through itself, and both have measure zero.
//!
//! Candidates: each triangle's bounding box is entered in the cells of a grid
//! whose cell is the mean box size (at most 16 cells a side); a pair is tested
//! once, in the cell that holds the low corner of the two boxes' overlap. Pairs sharing a vertex
//! (welded by position) are skipped: neighbours meet along edges by design.
//! Cost about O(triangles x neighbours per cell).

use glam::DVec3;
use robust::{Coord3D, orient3d};
use std::collections::HashMap;

fn c(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

fn o3(a: DVec3, b: DVec3, cc: DVec3, d: DVec3) -> f64 {
    orient3d(c(a), c(b), c(cc), c(d))
}

/// Does an edge of `b` pierce the inside of `a` (see the module doc)?
fn pierces(a: &[DVec3; 3], b: &[DVec3; 3], side: [f64; 3]) -> bool {
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        if side[i] * side[j] < 0.0 {
            let (p, q) = (b[i], b[j]);
            let s = [
                o3(p, q, a[0], a[1]),
                o3(p, q, a[1], a[2]),
                o3(p, q, a[2], a[0]),
            ];
            if s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0) {
                return true;
            }
        }
    }
    false
}

/// Do triangles `a` and `b` cross (see the module doc)?
pub(crate) fn triangles_cross(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let sb = b.map(|p| o3(a[0], a[1], a[2], p));
    if sb.iter().all(|&x| x > 0.0) || sb.iter().all(|&x| x < 0.0) || sb.iter().all(|&x| x == 0.0) {
        return false;
    }
    let sa = a.map(|p| o3(b[0], b[1], b[2], p));
    if sa.iter().all(|&x| x > 0.0) || sa.iter().all(|&x| x < 0.0) {
        return false;
    }
    pierces(a, b, sb) || pierces(b, a, sa)
}

/// The pairs (i, j), i < j, of the triangles `subset` (indices into `tris`)
/// that cross at `positions`, sorted.
pub(crate) fn crossing_pairs(
    positions: &[DVec3],
    welded: &[u32],
    tris: &[[u32; 3]],
    subset: &[usize],
) -> Vec<(usize, usize)> {
    if subset.len() < 2 {
        return Vec::new();
    }
    let corners = |t: usize| tris[t].map(|v| positions[v as usize]);
    let boxes: Vec<(DVec3, DVec3)> = subset
        .iter()
        .map(|&t| {
            let p = corners(t);
            (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
        })
        .collect();
    let mean = boxes
        .iter()
        .map(|(lo, hi)| (*hi - *lo).max_element())
        .sum::<f64>()
        / boxes.len() as f64;
    let cell = if mean.is_finite() && mean > 0.0 {
        mean
    } else {
        1.0
    };
    let at = |p: DVec3| (p / cell).floor().as_i64vec3().to_array();
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (k, (lo, hi)) in boxes.iter().enumerate() {
        let (a, b) = (at(*lo), at(*hi));
        // A sliver spanning more than 16 cells a side is entered in its first 16
        // (bounded work on a torn mesh; a pair whose overlap starts beyond them is missed).
        let span = |i: usize| (b[i] - a[i]).clamp(0, 15);
        for x in 0..=span(0) {
            for y in 0..=span(1) {
                for z in 0..=span(2) {
                    grid.entry([a[0] + x, a[1] + y, a[2] + z])
                        .or_default()
                        .push(k);
                }
            }
        }
    }
    let mut out = Vec::new();
    let mut keys: Vec<&[i64; 3]> = grid.keys().collect();
    keys.sort_unstable();
    for key in keys {
        let members = &grid[key];
        for (x, &i) in members.iter().enumerate() {
            for &j in &members[x + 1..] {
                let (li, hi) = boxes[i];
                let (lj, hj) = boxes[j];
                if li.cmpgt(hj).any() || lj.cmpgt(hi).any() {
                    continue;
                }
                if at(li.max(lj)) != *key {
                    continue;
                }
                let (ti, tj) = (subset[i], subset[j]);
                let wi = tris[ti].map(|v| welded[v as usize]);
                let wj = tris[tj].map(|v| welded[v as usize]);
                let mut shared = false;
                for a in wi {
                    shared |= a == wj[0] || a == wj[1] || a == wj[2];
                }
                if shared {
                    continue;
                }
                if triangles_cross(&corners(ti), &corners(tj)) {
                    out.push((ti.min(tj), ti.max(tj)));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_touching_and_apart() {
        let a = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        ];
        // Pierces a's inside.
        let b = [
            DVec3::new(0.5, 0.5, -1.0),
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(3.0, 3.0, 1.0),
        ];
        assert!(triangles_cross(&a, &b) && triangles_cross(&b, &a));
        // The same, moved beyond a's hypotenuse: no crossing.
        let off = b.map(|p| p + DVec3::new(1.6, 1.6, 0.0));
        assert!(!triangles_cross(&a, &off));
        // Touching a's plane at one vertex only.
        let touch = [
            DVec3::new(0.5, 0.5, 0.0),
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(1.0, 0.2, 1.0),
        ];
        assert!(!triangles_cross(&a, &touch));
        // Coplanar overlap does not count.
        let flat = a.map(|p| p + DVec3::new(0.3, 0.3, 0.0));
        assert!(!triangles_cross(&a, &flat));
        // A crossing where neither triangle's vertex is inside the other: two slabs in an X.
        let x1 = [
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let x2 = [
            DVec3::new(-1.0, 0.2, 1.0),
            DVec3::new(1.0, 0.2, -1.0),
            DVec3::new(0.0, 1.2, 0.0),
        ];
        assert!(triangles_cross(&x1, &x2));
    }

    #[test]
    fn the_grid_finds_what_all_pairs_find() {
        // A fan of thin triangles, some crossing, checked against testing every pair.
        let mut positions = Vec::new();
        let mut tris = Vec::new();
        for k in 0..40 {
            let a = k as f64 * 0.37;
            let (s, co) = a.sin_cos();
            let base = positions.len() as u32;
            positions.push(DVec3::new(co, s, -0.2 + 0.01 * k as f64));
            positions.push(DVec3::new(-co, -s, 0.1));
            positions.push(DVec3::new(0.1 * s, 0.1 * co, 0.5 - 0.02 * k as f64));
            tris.push([base, base + 1, base + 2]);
        }
        let welded: Vec<u32> = (0..positions.len() as u32).collect();
        let all: Vec<usize> = (0..tris.len()).collect();
        let got = crossing_pairs(&positions, &welded, &tris, &all);
        let mut want = Vec::new();
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                let p = |t: usize| tris[t].map(|v| positions[v as usize]);
                if triangles_cross(&p(i), &p(j)) {
                    want.push((i, j));
                }
            }
        }
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }
}
