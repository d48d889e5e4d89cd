//! A finger's region of the skin, traced ([`super::axis`]) before it is
//! named ([`super::palm`]).

use super::axis::{Region, Trace, trace};
use super::graph::{Extremity, dijkstra};
use super::hand::{FindError, mm};
use super::surface::{Object, Surface};
use glam::DVec3;

/// A finger traced, before it is named.
pub(super) struct Traced {
    pub(super) trace: Trace,
    pub(super) region: Vec<u32>,
    pub(super) mask: Vec<bool>,
    pub(super) web: DVec3,
    pub(super) web_level: f64,
    pub(super) persistence: f64,
    /// Geodesic distance of its top from the wrist.
    pub(super) along: f64,
}

pub(super) fn trace_finger(
    s: &Surface<'_>,
    obj: &Object,
    g: &[f64],
    e: &Extremity,
    level: f64,
    saddle: u32,
) -> Result<Traced, FindError> {
    let n = s.positions.len();
    let mut mask = vec![false; n];
    let mut stack = vec![e.top];
    mask[e.top as usize] = true;
    let mut region = Vec::new();
    while let Some(v) = stack.pop() {
        region.push(v);
        for (u, _) in s.graph.neighbours(v as usize) {
            if !mask[u] && obj.mask[u] && g[u] > level {
                mask[u] = true;
                stack.push(u as u32);
            }
        }
    }
    let h = dijkstra(&s.graph, &[(e.top, 0.0)], Some(&mask));
    let tris: Vec<[u32; 3]> = obj
        .tris
        .iter()
        .filter(|t| t.iter().all(|&v| mask[v as usize]))
        .copied()
        .collect();
    let top = s.positions[e.top as usize];
    let t = trace(&Region {
        positions: s.positions,
        tris: &tris,
        h: &h,
        top: e.top,
        median_edge: s.median_edge,
    })
    .ok_or(FindError::NoAxis {
        x: mm(top.x),
        y: mm(top.y),
        z: mm(top.z),
    })?;
    region.sort_by(|&a, &b| h[a as usize].total_cmp(&h[b as usize]).then(a.cmp(&b)));
    Ok(Traced {
        trace: t,
        region,
        mask,
        web: s.positions[saddle as usize],
        web_level: level,
        persistence: e.birth - e.death.unwrap_or(level),
        along: g[e.top as usize],
    })
}
