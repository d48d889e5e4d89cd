//! A finger's axis and tip, traced on its part of the skin (its region: the
//! vertices above its web, [`super::find`]).
//!
//! **Start.** Geodesic distance h from the finger's top (the maximum of the
//! geodesic from the wrist, on the fingertip's pad) over the region. The
//! region's triangles, by their mean h, fall in bands; the band at 25-35% of
//! the region's greatest h gives a first radius r0 (the area-weighted mean
//! distance of its triangles from their centre), and the centres of the bands
//! at h = r0-2r0 and 3r0-4r0 the first direction, towards the tip.
//!
//! **March.** From the tip end towards the palm, planes across the current
//! direction, `step` apart (a quarter of r0, or of the median edge on a coarse
//! mesh), cut the region's triangles ([`super::geometry::section`]). The cut
//! nearest the plane's point, with any cut nested with it (pieces that
//! overlap, as the mannequin's phalanges do), is the ring; its length-weighted
//! centre is a point of the axis and its mean distance from the centre the
//! finger's radius there. The direction follows the rings: the line through
//! the centres within 2.5 radii of the last (least squares), turning at most
//! 10 degrees a step. A ring whose centre lies more than half a radius off
//! the plane's point is skipped (a cut through a cap or a gap); the march
//! stops at the fourth skip in a row, and at the first open ring: there the
//! plane reaches the region's border, the web.
//!
//! **Tip.** The skin's end is where the axis leaves the mesh, not the top (the
//! top lies on the pad, 1-7 mm short of the end and off the axis): the line
//! fitted through the ring centres between half a radius and three radii
//! from the first ring (the fingertip's own direction, clear of the cap,
//! whose rings drift with the pad and the nail) is followed distally, and
//! the tip is its farthest crossing with the region's triangles. A line that
//! crosses none (a hole at the tip) ends at the farthest projection of the
//! region's vertices near the top instead. The centres of the cap's rings
//! (within half a radius of the first) are moved onto that line: they drift
//! with the pad and the nail.

use super::geometry::{Ring, line_crossings, line_direction, section};
use glam::DVec3;

/// A traced finger: ring centres from the tip end, their radii, the tip.
#[derive(Debug, Clone)]
pub(crate) struct Trace {
    /// Ring centres, the most distal first.
    pub centres: Vec<DVec3>,
    pub radii: Vec<f64>,
    pub tip: DVec3,
    /// The fingertip's direction (distal).
    pub end_dir: DVec3,
    /// The direction at the last ring (distal).
    pub base_dir: DVec3,
    /// False when the line missed the mesh and the tip is the farthest vertex.
    pub exits: bool,
}

/// What [`trace`] needs of the mesh and the finger.
pub(crate) struct Region<'a> {
    pub positions: &'a [DVec3],
    /// The region's triangles (all three vertices in the region).
    pub tris: &'a [[u32; 3]],
    /// Geodesic distance from `top` over the region (infinite outside).
    pub h: &'a [f64],
    pub top: u32,
    /// The median edge length of the whole mesh.
    pub median_edge: f64,
}

/// Most rings a march takes (a bound on the work whatever the input).
const MAX_RINGS: usize = 4000;

/// Traces the finger of `region` (see the module doc); `None` when fewer than
/// three rings are found (no tube to follow).
pub(crate) fn trace(region: &Region<'_>) -> Option<Trace> {
    let start = start(region)?;
    let (centres, radii) = march(region, &start);
    finish(region, centres, radii, &start.near)
}

/// Where a march starts: its first direction and point, its step, the
/// radius first guessed, the vertices near the top, and its most rings.
struct Start {
    u: DVec3,
    at: DVec3,
    step: f64,
    r0: f64,
    near: Vec<DVec3>,
    limit: usize,
}

/// The march's start from the bands of the region's triangles by height:
/// the first radius from the band at a quarter to a third of the height, the
/// direction from two bands near the top; `None` for a flat or empty region.
fn start(region: &Region<'_>) -> Option<Start> {
    let p = region.positions;
    // Each triangle's area, centroid and mean h.
    let tri: Vec<(f64, DVec3, f64)> = region
        .tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            let h = t.iter().map(|&i| region.h[i as usize]).sum::<f64>() / 3.0;
            (0.5 * (b - a).cross(c - a).length(), (a + b + c) / 3.0, h)
        })
        .filter(|x| x.0.is_finite() && x.2.is_finite())
        .collect();
    let hmax = tri.iter().map(|x| x.2).fold(0.0, f64::max);
    if !(hmax > 0.0 && hmax.is_finite()) {
        return None;
    }
    let band = |lo: f64, hi: f64| -> Option<(DVec3, f64)> {
        let mut area = 0.0;
        let mut sum = DVec3::ZERO;
        for &(w, c, h) in &tri {
            if h >= lo && h < hi {
                area += w;
                sum += w * c;
            }
        }
        if !(area > 0.0 && area.is_finite()) {
            return None;
        }
        let centre = sum / area;
        let spread = tri
            .iter()
            .filter(|x| x.2 >= lo && x.2 < hi)
            .map(|&(w, c, _)| w * c.distance(centre))
            .sum::<f64>()
            / area;
        Some((centre, spread))
    };
    let r0 = band(0.25 * hmax, 0.35 * hmax)
        .map(|b| b.1)
        .filter(|r| *r > 0.0)
        .unwrap_or(0.1 * hmax);
    let top = p[region.top as usize];
    let all = band(0.0, f64::INFINITY)?.0;
    let first = match (band(r0, 2.0 * r0), band(3.0 * r0, 4.0 * r0)) {
        (Some(a), Some(b)) => a.0 - b.0,
        _ => top - all,
    };
    let u = first.try_normalize()?;
    let step = (r0 / 4.0).max(region.median_edge / 4.0);
    if !(step > 0.0 && step.is_finite()) {
        return None;
    }
    let near: Vec<DVec3> = region
        .tris
        .iter()
        .flatten()
        .filter(|&&i| region.h[i as usize] < 3.0 * r0)
        .map(|&i| p[i as usize])
        .collect();
    let end = near.iter().map(|v| v.dot(u)).fold(top.dot(u), f64::max);
    let at = top + u * ((end - step) - top.dot(u));
    let limit = ((4.0 * hmax / step).ceil() as usize).clamp(8, MAX_RINGS);
    Some(Start {
        u,
        at,
        step,
        r0,
        near,
        limit,
    })
}

/// Marches down the finger from `start`, one cross-section a step: each
/// ring's centre and radius, the direction turned (at most 10 degrees a
/// step) to the line through the recent centres; stops after 3 misses in a
/// row, at an open ring (the region's border), or when the rings run out.
fn march(region: &Region<'_>, start: &Start) -> (Vec<DVec3>, Vec<f64>) {
    let p = region.positions;
    let Start {
        mut u,
        mut at,
        step,
        r0,
        limit,
        ..
    } = *start;
    let mut centres: Vec<DVec3> = Vec::new();
    let mut radii: Vec<f64> = Vec::new();
    let mut r_est = r0;
    let mut misses = 0;
    for _ in 0..limit {
        let rings = section(p, region.tris, at, u);
        let ring = nearest_ring(&rings, at);
        let ok = match ring {
            Some(Ok((c, r))) => {
                let off = (c - at) - u * (c - at).dot(u);
                if centres.len() < 2 || off.length() <= 0.5 * r_est {
                    Some((c, r))
                } else {
                    None
                }
            }
            Some(Err(())) => break,
            None if !centres.is_empty() => break,
            None => None,
        };
        match ok {
            Some((c, r)) => {
                centres.push(c);
                radii.push(r);
                misses = 0;
                let mut recent: Vec<f64> = radii.iter().rev().take(7).copied().collect();
                recent.sort_by(f64::total_cmp);
                r_est = recent[recent.len() / 2];
                let window = (2.5 * r_est).max(3.0 * step);
                let last = c;
                let pts: Vec<DVec3> = centres
                    .iter()
                    .copied()
                    .filter(|q| q.distance(last) <= window)
                    .collect();
                if pts.len() >= 3
                    && let Some(nu) = line_direction(&pts, u)
                {
                    u = turn_at_most(u, nu, 10f64.to_radians());
                }
                at = c - step * u;
            }
            None => {
                misses += 1;
                if misses > 3 {
                    break;
                }
                at -= step * u;
            }
        }
    }
    (centres, radii)
}

/// The trace from the march's rings: the fingertip's line fitted to the
/// rings clear of the cap, the tip where that line leaves the mesh (else the
/// farthest `near` vertex along it), the cap's centres put on the line.
fn finish(
    region: &Region<'_>,
    mut centres: Vec<DVec3>,
    radii: Vec<f64>,
    near: &[DVec3],
) -> Option<Trace> {
    let p = region.positions;
    if centres.len() < 3 {
        return None;
    }
    let mut sorted = radii.clone();
    sorted.sort_by(f64::total_cmp);
    let r = sorted[sorted.len() / 2];
    // The fingertip's own direction, from the rings clear of the cap.
    let arc = super::geometry::arcs(&centres);
    let mut fit: Vec<DVec3> = centres
        .iter()
        .zip(&arc)
        .filter(|(_, s)| **s >= 0.5 * r && **s <= 3.0 * r)
        .map(|(c, _)| *c)
        .collect();
    if fit.len() < 2 {
        fit = centres.iter().take(4).copied().collect();
    }
    let towards = centres[0] - centres[centres.len() - 1];
    let d = line_direction(&fit, towards)?;
    let mean = fit.iter().copied().sum::<DVec3>() / fit.len() as f64;
    let origin = mean + d * (centres[0] - mean).dot(d);
    let crossings = line_crossings(p, region.tris, origin, d);
    let (tip, exits) = match crossings.iter().copied().max_by(f64::total_cmp) {
        Some(t) => (origin + d * t, true),
        None => {
            let t = near
                .iter()
                .map(|v| (*v - origin).dot(d))
                .fold(0.0, f64::max);
            (origin + d * t, false)
        }
    };
    // The rings of the cap, nearer the tip end than half a radius, drift with
    // the pad and the nail: their centres are taken onto the fingertip's line.
    for (c, s) in centres.iter_mut().zip(&arc) {
        if *s < 0.5 * r {
            *c = mean + d * (*c - mean).dot(d);
        }
    }
    let last = centres[centres.len() - 1];
    let base: Vec<DVec3> = centres
        .iter()
        .copied()
        .filter(|q| q.distance(last) <= 2.5 * r)
        .collect();
    let base_dir = line_direction(&base, towards).unwrap_or(d);
    Some(Trace {
        centres,
        radii,
        tip,
        end_dir: d,
        base_dir,
        exits,
    })
}

/// The ring of `rings` nearest `at`, merged with the rings nested with it
/// (centres within half a radius): its centre and radius, weighted by
/// perimeter; `Err` when any of them is open (the region's border), `None`
/// without a ring.
fn nearest_ring(rings: &[Ring], at: DVec3) -> Option<Result<(DVec3, f64), ()>> {
    let nearest = rings
        .iter()
        .min_by(|a, b| a.centre.distance(at).total_cmp(&b.centre.distance(at)))?;
    let group: Vec<&Ring> = rings
        .iter()
        .filter(|r| r.centre.distance(nearest.centre) < 0.5 * r.radius.max(nearest.radius))
        .collect();
    if group.iter().any(|r| r.open) {
        return Some(Err(()));
    }
    let per: f64 = group.iter().map(|r| r.perimeter).sum();
    if !(per > 0.0 && per.is_finite()) {
        return None;
    }
    let c = group.iter().map(|r| r.centre * r.perimeter).sum::<DVec3>() / per;
    let rad = group.iter().map(|r| r.radius * r.perimeter).sum::<f64>() / per;
    Some(Ok((c, rad)))
}

/// `to`, or the direction `max` radians from `from` towards it.
fn turn_at_most(from: DVec3, to: DVec3, max: f64) -> DVec3 {
    let angle = from.dot(to).clamp(-1.0, 1.0).acos();
    if angle <= max {
        return to;
    }
    let w = max / angle;
    (from * (1.0 - w) + to * w).try_normalize().unwrap_or(from)
}
