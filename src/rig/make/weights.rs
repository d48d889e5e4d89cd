//! The skin's weights of a made hand: smooth blends across each joint, their
//! widths from the finger's radius there, and the palm blending into the
//! first bone of each finger.
//!
//! Each made finger is a chain of points, root first (a finger: MCP, PIP,
//! DIP, tip; the thumb: CMC, MCP, IP, tip), and a bone between each two.
//! A vertex is projected onto the chain (its first segment continued into
//! the palm, its last past the tip): s its arc position, d its distance. At
//! each joint k but the tip, at arc a_k with the finger's radius r_k there,
//! the share that has passed into the bones beyond it is
//!
//! R_k(s) = S((s - a_k + h_k) / (2 h_k)), h_k = [`BLEND`] r_k,
//!
//! S the smoothstep 3x^2 - 2x^3 on [0, 1]; h_k is cut to 0.45 of each
//! neighbouring bone so that the blends never overlap. The bone from joint k
//! takes R_k - R_(k+1) (the last bone R_k), and the palm before it 1 - R_0 (the
//! finger's metacarpal bone where the rig has one, else the hand bone). So the
//! weights sum to 1, at most two bones share a vertex, and a joint's next
//! bone passes half the weight exactly at the joint: the skin bends there
//! (as the audit reads a bend: [`crate::rig::judge::bend`]).
//!
//! Which finger a vertex follows: a vertex of a finger's region on the skin
//! (the finding's, tip to web) follows that finger; any other vertex (the
//! palm, the back of the hand, the webs' edges) the finger whose chain is
//! nearest in units of its radius, the share scaled by lambda(d / r), 1 within
//! [`REACH`] radii, falling smoothly to 0 one radius further (the thumb's
//! metacarpal reaches half as far, 1 radius fully: it moves the thenar, not
//! the middle of the palm). Cost: O(V J) for V vertices and J joints.

use super::place::{MadeFinger, MadeHand};
use crate::dataset::Finger;
use crate::rig::find::{FoundHand, HandMesh};
use glam::DVec3;

/// The half-width of a joint's blend, as a share of the finger's radius at
/// the joint: 1.5, a blend 3 radii long (24 mm on an 8 mm finger; cut to
/// 0.45 of each neighbouring bone). Chosen by deforming (`deform RIGGED
/// --against ORIGINAL`, fist and grip, LBS and DQS) against the artists'
/// weights of the shared rigs: at 0.75 the WebXR left hand's made rig was
/// better at 0 joints and worse at 12 (its narrow blends fold the skin into
/// itself); at 1.25, 12 and 7; at 1.5, better on every smooth-skinned rig
/// (XR Tools left 25 and 9, SteamVR right 34 and 0); 2.0 gains little more.
pub const BLEND: f64 = 1.5;

/// How far from a finger's chain, in its radii, a vertex outside its region
/// moves with it fully (the palm under the knuckles is 1.5-2 finger radii
/// from the chain).
pub const REACH: f64 = 2.5;

/// A bone of the made hand: the hand (wrist) bone, the palm before a finger,
/// or the bone of `finger`
/// from its `k`-th chain point (a finger: 0 proximal, 1 intermediate, 2
/// distal; the thumb: 0 metacarpal, 1 proximal, 2 distal).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Bone {
    Hand,
    /// The palm before `finger`'s first bone: its metacarpal where the rig
    /// has one for it, else the hand bone.
    Palm {
        finger: Finger,
    },
    Finger {
        finger: Finger,
        k: usize,
    },
}

/// A made finger's chain: its points root first (the thumb from its CMC)
/// and the radius at each.
struct Chain {
    finger: Finger,
    points: Vec<DVec3>,
    arcs: Vec<f64>,
    /// Half-widths of the blends at each point but the tip.
    half: Vec<f64>,
    /// The chain's mean radius.
    radius: f64,
}

impl Chain {
    fn of(f: &MadeFinger) -> Option<Chain> {
        let mut points: Vec<DVec3> = f.cmc.into_iter().collect();
        points.extend(f.joints.iter().map(|j| j.1));
        let mut radius: Vec<f64> = f.cmc.map(|_| f.radius[0]).into_iter().collect();
        radius.extend(f.radius.iter().copied());
        if points.len() < 2 || radius.len() != points.len() {
            return None;
        }
        let arcs = crate::rig::judge::chain::arc_positions(&points);
        let seg: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
        let half = (0..points.len() - 1)
            .map(|k| {
                let before = if k == 0 { f64::INFINITY } else { seg[k - 1] };
                (BLEND * radius[k]).min(0.45 * before).min(0.45 * seg[k])
            })
            .collect();
        let mean = radius.iter().sum::<f64>() / radius.len() as f64;
        Some(Chain {
            finger: f.finger,
            points,
            arcs,
            half,
            radius: mean,
        })
    }

    /// The arc position and distance of `v` projected on the chain, its first
    /// segment continued before the root and its last past the tip. O(J).
    fn project(&self, v: DVec3) -> (f64, f64) {
        let n = self.points.len() - 1;
        let mut best = (0.0, f64::INFINITY);
        for k in 0..n {
            let (a, b) = (self.points[k], self.points[k + 1]);
            let ab = b - a;
            let len2 = ab.length_squared();
            if len2 <= 0.0 {
                continue;
            }
            let mut t = (v - a).dot(ab) / len2;
            if k > 0 {
                t = t.max(0.0);
            }
            if k + 1 < n {
                t = t.min(1.0);
            }
            let d = (a + t * ab).distance(v);
            if d < best.1 {
                best = (self.arcs[k] + t * (self.arcs[k + 1] - self.arcs[k]), d);
            }
        }
        best
    }

    /// The share past joint k at arc position s (R_k in the module notes).
    fn past(&self, k: usize, s: f64) -> f64 {
        let h = self.half[k];
        if h.is_nan() || h <= 0.0 {
            return if s >= self.arcs[k] { 1.0 } else { 0.0 };
        }
        smoothstep((s - self.arcs[k] + h) / (2.0 * h))
    }

    /// The weights of the chain's bones at arc position s, scaled by
    /// `lambda`, and the hand's share, 1 minus their sum.
    fn weights(&self, s: f64, lambda: f64, out: &mut Vec<(Bone, f64)>) {
        let n = self.points.len() - 1;
        let past: Vec<f64> = (0..n).map(|k| self.past(k, s)).collect();
        let mut given = 0.0;
        for k in 0..n {
            let w = lambda * (past[k] - past.get(k + 1).copied().unwrap_or(0.0)).max(0.0);
            if w > 0.0 {
                out.push((
                    Bone::Finger {
                        finger: self.finger,
                        k,
                    },
                    w,
                ));
                given += w;
            }
        }
        if given < 1.0 {
            out.push((
                Bone::Palm {
                    finger: self.finger,
                },
                1.0 - given,
            ));
        }
    }
}

/// S(x) = 3x^2 - 2x^3 on [0, 1], 0 before and 1 after.
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Each welded vertex of `mesh`'s bones and weights (summing to 1, largest
/// first), for the hand `made` on the fingers `found` (see the module notes).
pub fn weigh(mesh: &HandMesh, found: &FoundHand, made: &MadeHand) -> Vec<Vec<(Bone, f64)>> {
    let chains: Vec<Chain> = made.fingers.iter().filter_map(Chain::of).collect();
    // The finger whose region each vertex lies in, by its chain's index.
    let mut region: Vec<Option<usize>> = vec![None; mesh.positions.len()];
    for f in &found.fingers {
        if let Some(c) = chains.iter().position(|c| c.finger == f.finger) {
            for &v in &f.vertices {
                if let Some(slot) = region.get_mut(v as usize) {
                    *slot = Some(c);
                }
            }
        }
    }
    mesh.positions
        .iter()
        .zip(&region)
        .map(|(&v, &own)| {
            let mut out = Vec::with_capacity(3);
            let pick = match own {
                Some(c) => {
                    let (s, _) = chains[c].project(v);
                    Some((c, s, 1.0))
                }
                None => chains
                    .iter()
                    .enumerate()
                    .map(|(c, chain)| {
                        let (s, d) = chain.project(v);
                        (c, s, d / chain.radius)
                    })
                    .min_by(|a, b| a.2.total_cmp(&b.2))
                    .map(|(c, s, x)| {
                        let reach = if chains[c].finger == Finger::Thumb {
                            REACH / 2.0
                        } else {
                            REACH
                        };
                        (c, s, 1.0 - smoothstep(x - reach))
                    }),
            };
            match pick {
                Some((c, s, lambda)) => chains[c].weights(s, lambda, &mut out),
                None => out.push((Bone::Hand, 1.0)),
            }
            out.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            out
        })
        .collect()
}
