//! The palm, the thumb, the names of the fingers and the hand's side
//! ([`super::find`], steps 6-8), and the checks of the hand's pose.

use super::finger::Traced;
use super::geometry::{arcs, nearest_on, point_at, surface_axes};
use super::hand::{FindError, FindOptions, FoundFinger, FoundHand, finger_words, mm};
use super::surface::{Object, Surface};
use super::wrist::Wrist;
use crate::dataset::Finger;
use crate::rig::read::naming::Side;
use glam::DVec3;

/// Names the fingers, finds the palm and the side, checks the pose, and
/// makes the hand (see [`super::find`], steps 7-8).
pub(super) fn frame(
    s: &Surface<'_>,
    obj: &Object,
    g: &[f64],
    wrist: &Wrist,
    traced: Vec<Traced>,
    opts: &FindOptions,
    notes: &mut Vec<String>,
) -> Result<FoundHand, FindError> {
    let bases: Vec<DVec3> = traced.iter().map(base).collect();
    let (palm_centre, normal) = palm_plane(s, obj, g, wrist, &traced, &bases)?;
    let in_plane = |v: DVec3| (v - normal * v.dot(normal)).try_normalize();
    let thumb = pick_thumb(
        &traced,
        &bases,
        in_plane(wrist.normal).ok_or(FindError::Flat)?.cross(normal),
        notes,
    );
    let others: Vec<usize> = (0..traced.len()).filter(|&i| i != thumb).collect();
    let mean_base = others.iter().map(|&i| bases[i]).sum::<DVec3>() / others.len() as f64;
    let distal = in_plane(mean_base - wrist.centre)
        .or_else(|| in_plane(wrist.normal))
        .ok_or(FindError::Flat)?;
    // The palm side: where the thumb's tip and the other tips lie.
    let off = |i: usize| (traced[i].trace.tip - palm_centre).dot(normal);
    let thumb_off = off(thumb);
    let tips_off = others.iter().map(|&i| off(i)).sum::<f64>() / others.len() as f64;
    let beyond = obj
        .vertices
        .iter()
        .map(|&v| (s.positions[v as usize] - wrist.centre).dot(wrist.normal))
        .fold(0.0, f64::max);
    let cue = thumb_off + tips_off;
    let clear = cue.abs() >= 0.03 * beyond;
    // A right hand has its thumb on the side of distal x palm normal.
    let side_of = |n: DVec3| {
        if (bases[thumb] - mean_base).dot(distal.cross(n)) > 0.0 {
            Side::Right
        } else {
            Side::Left
        }
    };
    let geometric = if cue >= 0.0 { normal } else { -normal };
    let (palm_normal, side) = match (clear, opts.side) {
        (true, None) => {
            notes.push(format!(
                "the palm faces where the thumb's tip ({} mm off the palm's plane) and the \
                 other fingertips ({} mm on average) lie; the thumb lies {} distal x palm \
                 normal: a {} hand",
                crate::format::num(mm(thumb_off.abs()), 0),
                crate::format::num(mm(tips_off.abs()), 0),
                if side_of(geometric) == Side::Right {
                    "on the side of"
                } else {
                    "opposite"
                },
                side_of(geometric).name()
            ));
            (geometric, side_of(geometric))
        }
        (_, Some(side)) => {
            if clear && side_of(geometric) != side {
                notes.push(format!(
                    "the skin reads as a {} hand (the thumb's tip and the fingertips lie on the \
                     other side of the palm), but --side {} was given and is kept",
                    side_of(geometric).name(),
                    side.name()
                ));
            }
            let n = if side_of(normal) == side {
                normal
            } else {
                -normal
            };
            (n, side)
        }
        (false, None) => return Err(FindError::NoSide),
    };
    // The others in order across the palm from the thumb.
    let across = distal.cross(palm_normal);
    let from_thumb = |i: usize| {
        let x = bases[i].dot(across);
        if (bases[thumb] - mean_base).dot(across) >= 0.0 {
            -x
        } else {
            x
        }
    };
    let mut row = others.clone();
    row.sort_by(|&a, &b| from_thumb(a).total_cmp(&from_thumb(b)));
    let mut named: Vec<(Finger, usize)> = vec![(Finger::Thumb, thumb)];
    named.extend(
        row.iter()
            .enumerate()
            .map(|(k, &i)| (Finger::ALL[k + 1], i)),
    );
    check_pose(&named, &traced, wrist)?;
    check_widths(&named, &traced)?;
    let fingers = named
        .iter()
        .map(|&(finger, i)| found_finger(finger, &traced[i], wrist.centre))
        .collect();
    Ok(FoundHand {
        side,
        wrist: wrist.centre,
        palm_normal,
        distal,
        fingers,
        notes: Vec::new(),
    })
}

/// A finger's base: its axis at the web (continued straight past the last
/// ring when the web lies beyond it).
fn base(t: &Traced) -> DVec3 {
    let pts: Vec<DVec3> = std::iter::once(t.trace.tip)
        .chain(t.trace.centres.iter().copied())
        .collect();
    let last = pts[pts.len() - 1];
    let beyond = (t.web - last).dot(-t.trace.base_dir);
    let (arc, _) = nearest_on(&pts, t.web);
    if arc >= arcs(&pts)[pts.len() - 1] && beyond > 0.0 {
        last - t.trace.base_dir * beyond
    } else {
        point_at(&pts, arc)
    }
}

/// The palm's centre and unit normal (either way): the least principal axis
/// of the palm's skin (beyond the wrist, in no finger, below the highest
/// web); with too little of it, of the wrist and the fingers' bases.
fn palm_plane(
    s: &Surface<'_>,
    obj: &Object,
    g: &[f64],
    wrist: &Wrist,
    traced: &[Traced],
    bases: &[DVec3],
) -> Result<(DVec3, DVec3), FindError> {
    let top_web = traced.iter().map(|t| t.web_level).fold(0.0, f64::max);
    let palm_tris: Vec<[u32; 3]> = obj
        .tris
        .iter()
        .filter(|t| {
            t.iter().all(|&v| {
                let v = v as usize;
                !traced.iter().any(|f| f.mask[v])
                    && g[v] <= top_web
                    && (s.positions[v] - wrist.centre).dot(wrist.normal) > 0.0
            })
        })
        .copied()
        .collect();
    let (centre, normal) = match surface_axes(s.positions, &palm_tris) {
        Some(a) if palm_tris.len() >= 8 => (a.centre, a.axes[2]),
        _ => {
            let mut pts = bases.to_vec();
            pts.push(wrist.centre);
            let c = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
            let mut cov = glam::DMat3::ZERO;
            for p in &pts {
                let d = *p - c;
                cov += glam::DMat3::from_cols(d * d.x, d * d.y, d * d.z);
            }
            (c, super::geometry::symmetric_eigen(cov).1[2])
        }
    };
    Ok((centre, normal.try_normalize().ok_or(FindError::Flat)?))
}

/// The thumb: of the two fingers at the ends of the row across the palm
/// (the bases in order along `across`), the one whose web is lower (nearer
/// the wrist along the skin). Noted when another finger's web is lower still.
fn pick_thumb(traced: &[Traced], bases: &[DVec3], across: DVec3, notes: &mut Vec<String>) -> usize {
    let mut order: Vec<usize> = (0..traced.len()).collect();
    order.sort_by(|&a, &b| bases[a].dot(across).total_cmp(&bases[b].dot(across)));
    let (first, last) = (order[0], order[order.len() - 1]);
    let thumb = if traced[first].web_level <= traced[last].web_level {
        first
    } else {
        last
    };
    let lowest = (0..traced.len())
        .min_by(|&a, &b| traced[a].web_level.total_cmp(&traced[b].web_level))
        .unwrap_or(thumb);
    if lowest != thumb {
        notes.push(
            "the finger with the lowest web is not at an end of the row across the palm; the \
             thumb was taken at the end whose web is lower"
                .into(),
        );
    }
    thumb
}

/// A fist: an axis that turns more than 120 degrees, or two fingers (not the
/// thumb) whose tips lie straight from the wrist at under 0.6 of their
/// distance along the skin.
pub(super) fn check_pose(
    named: &[(Finger, usize)],
    traced: &[Traced],
    wrist: &Wrist,
) -> Result<(), FindError> {
    let measure = |i: usize| {
        let t = &traced[i];
        let straight = t.trace.tip.distance(wrist.centre);
        let along = t.along + t.trace.tip.distance(t.trace.centres[0]).min(t.along);
        let turn = t
            .trace
            .end_dir
            .dot(t.trace.base_dir)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        (straight, along, turn)
    };
    if let Some(&(f, i)) = named.iter().find(|&&(_, i)| measure(i).2 > 120.0) {
        return Err(FindError::Fist(format!(
            "the {}'s axis turns {} degrees from its base to its tip",
            finger_words(f),
            crate::format::num(measure(i).2, 0)
        )));
    }
    let curled: Vec<(Finger, usize)> = named
        .iter()
        .filter(|(f, i)| {
            *f != Finger::Thumb && {
                let (straight, along, _) = measure(*i);
                straight < 0.6 * along
            }
        })
        .copied()
        .collect();
    if curled.len() >= 2 {
        let &(f, i) = curled
            .iter()
            .min_by(|a, b| {
                let r = |i: usize| {
                    let (s, a, _) = measure(i);
                    s / a
                };
                r(a.1).total_cmp(&r(b.1))
            })
            .unwrap_or(&curled[0]);
        let (straight, along, _) = measure(i);
        return Err(FindError::Fist(format!(
            "the {}'s tip lies {} mm from the wrist but {} mm from it along the skin \
             ({} fingers curled back so)",
            finger_words(f),
            crate::format::num(mm(straight), 0),
            crate::format::num(mm(along), 0),
            curled.len()
        )));
    }
    Ok(())
}

/// Two fingers fused in one: a finger (not the thumb) more than 1.8 times as
/// wide as the median of the others, with three or more besides the thumb.
pub(super) fn check_widths(named: &[(Finger, usize)], traced: &[Traced]) -> Result<(), FindError> {
    let width = |i: usize| {
        let mut r = traced[i].trace.radii.clone();
        r.sort_by(f64::total_cmp);
        2.0 * r[r.len() / 2]
    };
    let others: Vec<(Finger, f64)> = named
        .iter()
        .filter(|(f, _)| *f != Finger::Thumb)
        .map(|&(f, i)| (f, width(i)))
        .collect();
    if others.len() < 3 {
        return Ok(());
    }
    for &(f, w) in &others {
        let mut rest: Vec<f64> = others
            .iter()
            .filter(|(g, _)| *g != f)
            .map(|x| x.1)
            .collect();
        rest.sort_by(f64::total_cmp);
        let m = rest[rest.len() / 2];
        if w > 1.8 * m {
            return Err(FindError::Fused {
                finger: f,
                width: mm(w),
                ratio: w / m,
            });
        }
    }
    Ok(())
}

/// The finger as found: its axis from the tip through the rings, continued
/// straight to the point nearest the wrist and at least two radii past its web.
pub(super) fn found_finger(finger: Finger, t: &Traced, wrist: DVec3) -> FoundFinger {
    let mut axis = vec![t.trace.tip];
    axis.extend(t.trace.centres.iter().copied());
    let mut radius = vec![t.trace.radii[0]];
    radius.extend(t.trace.radii.iter().copied());
    let measured = axis.len();
    let (web_arc, _) = nearest_on(&axis, t.web);
    let total = arcs(&axis)[axis.len() - 1];
    let last = axis[axis.len() - 1];
    let back = -t.trace.base_dir;
    let r_last = radius[radius.len() - 1];
    let to_wrist = (wrist - last).dot(back);
    let more = to_wrist.max(web_arc + 2.0 * r_last - total).max(0.0);
    if more > 0.0 {
        axis.push(last + back * more);
        radius.push(r_last);
    }
    let (web_arc, _) = nearest_on(&axis, t.web);
    FoundFinger {
        finger,
        tip: t.trace.tip,
        tip_direction: t.trace.end_dir,
        axis,
        measured,
        radius,
        web: t.web,
        web_arc,
        vertices: t.region.clone(),
        persistence: t.persistence,
    }
}
