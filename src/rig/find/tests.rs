//! Hands built in the test, whose fingers are known exactly: a palm (a
//! rounded box) and a forearm joined smoothly to capsule fingers, a thumb
//! turned out of the palm's plane towards the palm side; the surface is the
//! zero set of their distance field (smooth union, k = 6 mm, which makes the
//! webs), meshed by surface nets on a 2.5 mm grid with every vertex moved
//! onto the surface (two Newton steps along the field's gradient). A
//! capsule's tip on the skin is its axis's end plus its radius along the
//! axis; its rings' centres lie on the axis.

use super::hand::{FindError, FindOptions, FoundHand};
use super::mesh::HandMesh;
use super::search::find_hand;
use crate::dataset::Finger;
use crate::rig::read::naming::Side;
use glam::{DQuat, DVec3};

/// A part of a hand's distance field.
#[derive(Debug, Clone, Copy)]
enum Part {
    /// A capsule: segment a-b, radius r.
    Capsule(DVec3, DVec3, f64),
    /// A box: centre, half extents, rounding radius.
    Box(DVec3, DVec3, f64),
    /// A sphere: centre, radius.
    Sphere(DVec3, f64),
}

impl Part {
    fn distance(&self, p: DVec3) -> f64 {
        match *self {
            Part::Capsule(a, b, r) => {
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                (a + t * ab).distance(p) - r
            }
            Part::Box(c, half, r) => {
                let q = (p - c).abs() - (half - DVec3::splat(r));
                q.max(DVec3::ZERO).length() + q.max_element().min(0.0) - r
            }
            Part::Sphere(c, r) => p.distance(c) - r,
        }
    }
}

/// A shape: parts joined by a smooth minimum of width `k` (0: a plain union),
/// turned by `turn` about the origin.
#[derive(Debug, Clone)]
struct Shape {
    parts: Vec<Part>,
    k: f64,
    turn: DQuat,
}

impl Shape {
    fn new(parts: Vec<Part>, k: f64) -> Shape {
        Shape {
            parts,
            k,
            turn: DQuat::IDENTITY,
        }
    }

    fn distance(&self, p: DVec3) -> f64 {
        let p = self.turn.inverse() * p;
        let mut d = f64::INFINITY;
        for part in &self.parts {
            let x = part.distance(p);
            d = if d.is_infinite() || self.k <= 0.0 {
                d.min(x)
            } else {
                // Polynomial smooth minimum (Quilez).
                let h = (0.5 + 0.5 * (x - d) / self.k).clamp(0.0, 1.0);
                x + (d - x) * h - self.k * h * (1.0 - h)
            };
        }
        d
    }

    fn gradient(&self, p: DVec3) -> DVec3 {
        let e = 1e-5;
        DVec3::new(
            self.distance(p + DVec3::X * e) - self.distance(p - DVec3::X * e),
            self.distance(p + DVec3::Y * e) - self.distance(p - DVec3::Y * e),
            self.distance(p + DVec3::Z * e) - self.distance(p - DVec3::Z * e),
        ) / (2.0 * e)
    }

    /// The shape mirrored through x = 0 (a left hand from a right).
    fn mirrored(&self) -> Shape {
        let m = |v: DVec3| DVec3::new(-v.x, v.y, v.z);
        Shape {
            parts: self
                .parts
                .iter()
                .map(|p| match *p {
                    Part::Capsule(a, b, r) => Part::Capsule(m(a), m(b), r),
                    Part::Box(c, h, r) => Part::Box(m(c), h, r),
                    Part::Sphere(c, r) => Part::Sphere(m(c), r),
                })
                .collect(),
            k: self.k,
            turn: self.turn,
        }
    }

    fn moved(&self, by: DVec3) -> Shape {
        Shape {
            parts: self
                .parts
                .iter()
                .map(|p| match *p {
                    Part::Capsule(a, b, r) => Part::Capsule(a + by, b + by, r),
                    Part::Box(c, h, r) => Part::Box(c + by, h, r),
                    Part::Sphere(c, r) => Part::Sphere(c + by, r),
                })
                .collect(),
            k: self.k,
            turn: self.turn,
        }
    }

    /// The surface meshed by surface nets on a grid of `cell` (see the
    /// module doc). Vertices are shared; triangles follow the grid edges.
    fn mesh(&self, cell: f64) -> HandMesh {
        // Bounds from the parts.
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &self.parts {
            let (a, b) = match *p {
                Part::Capsule(a, b, r) => (a.min(b) - DVec3::splat(r), a.max(b) + DVec3::splat(r)),
                Part::Box(c, h, _) => (c - h, c + h),
                Part::Sphere(c, r) => (c - DVec3::splat(r), c + DVec3::splat(r)),
            };
            lo = lo.min(a);
            hi = hi.max(b);
        }
        // The turned box's corners.
        let (l0, h0) = (lo, hi);
        (lo, hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for k in 0..8 {
            let c = DVec3::new(
                if k & 1 == 0 { l0.x } else { h0.x },
                if k & 2 == 0 { l0.y } else { h0.y },
                if k & 4 == 0 { l0.z } else { h0.z },
            );
            lo = lo.min(self.turn * c);
            hi = hi.max(self.turn * c);
        }
        lo -= DVec3::splat(3.0 * cell);
        hi += DVec3::splat(3.0 * cell);
        let n = ((hi - lo) / cell).ceil().as_uvec3() + glam::UVec3::ONE;
        let (nx, ny, nz) = (n.x as usize, n.y as usize, n.z as usize);
        let at =
            |i: usize, j: usize, k: usize| lo + DVec3::new(i as f64, j as f64, k as f64) * cell;
        let idx = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
        let f: Vec<f64> = (0..nx * ny * nz)
            .map(|x| {
                let (i, j, k) = (x % nx, (x / nx) % ny, x / (nx * ny));
                self.distance(at(i, j, k))
            })
            .collect();
        // One vertex per cell the surface crosses.
        let mut vertex = vec![u32::MAX; nx * ny * nz];
        let mut positions = Vec::new();
        for k in 0..nz - 1 {
            for j in 0..ny - 1 {
                for i in 0..nx - 1 {
                    let mut sum = DVec3::ZERO;
                    let mut count = 0.0;
                    for (a, b) in CUBE_EDGES {
                        let ca = (i + a.0, j + a.1, k + a.2);
                        let cb = (i + b.0, j + b.1, k + b.2);
                        let (fa, fb) = (f[idx(ca.0, ca.1, ca.2)], f[idx(cb.0, cb.1, cb.2)]);
                        if (fa < 0.0) != (fb < 0.0) {
                            let t = fa / (fa - fb);
                            sum += at(ca.0, ca.1, ca.2).lerp(at(cb.0, cb.1, cb.2), t);
                            count += 1.0;
                        }
                    }
                    if count > 0.0 {
                        let mut p = sum / count;
                        for _ in 0..2 {
                            let g = self.gradient(p);
                            if g.length_squared() > 1e-12 {
                                p -= self.distance(p) * g / g.length_squared();
                            }
                        }
                        vertex[idx(i, j, k)] = positions.len() as u32;
                        positions.push(p);
                    }
                }
            }
        }
        // A quad around every grid edge the surface crosses.
        let mut triangles = Vec::new();
        for k in 1..nz - 1 {
            for j in 1..ny - 1 {
                for i in 1..nx - 1 {
                    let f0 = f[idx(i, j, k)];
                    for axis in 0..3 {
                        let (di, dj, dk) = [(1, 0, 0), (0, 1, 0), (0, 0, 1)][axis];
                        if i + di >= nx || j + dj >= ny || k + dk >= nz {
                            continue;
                        }
                        let f1 = f[idx(i + di, j + dj, k + dk)];
                        if (f0 < 0.0) == (f1 < 0.0) {
                            continue;
                        }
                        // The four cells around the edge.
                        let cells: [(usize, usize, usize); 4] = match axis {
                            0 => [(i, j - 1, k - 1), (i, j, k - 1), (i, j, k), (i, j - 1, k)],
                            1 => [(i - 1, j, k - 1), (i, j, k - 1), (i, j, k), (i - 1, j, k)],
                            _ => [(i - 1, j - 1, k), (i, j - 1, k), (i, j, k), (i - 1, j, k)],
                        };
                        let q = cells.map(|(a, b, c)| vertex[idx(a, b, c)]);
                        if q.contains(&u32::MAX) {
                            continue;
                        }
                        let q = if f0 < 0.0 {
                            q
                        } else {
                            [q[3], q[2], q[1], q[0]]
                        };
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    }
                }
            }
        }
        let sources = (0..positions.len()).map(|v| vec![(0, 0, v)]).collect();
        HandMesh {
            positions,
            triangles,
            sources,
            notes: Vec::new(),
        }
    }
}

/// The 12 edges of a unit cube by their corners' offsets.
/// A corner of a grid cell, as offsets along x, y, z.
type Corner = (usize, usize, usize);

const CUBE_EDGES: [(Corner, Corner); 12] = [
    ((0, 0, 0), (1, 0, 0)),
    ((0, 1, 0), (1, 1, 0)),
    ((0, 0, 1), (1, 0, 1)),
    ((0, 1, 1), (1, 1, 1)),
    ((0, 0, 0), (0, 1, 0)),
    ((1, 0, 0), (1, 1, 0)),
    ((0, 0, 1), (0, 1, 1)),
    ((1, 0, 1), (1, 1, 1)),
    ((0, 0, 0), (0, 0, 1)),
    ((1, 0, 0), (1, 0, 1)),
    ((0, 1, 0), (0, 1, 1)),
    ((1, 1, 0), (1, 1, 1)),
];

/// A built right hand: its shape and each finger's known axis (base, end of
/// the capsule's segment, radius), thumb first. Distal is +y, the palm side
/// -z, so a right hand's thumb lies towards -x (distal x palm normal).
struct Built {
    shape: Shape,
    fingers: Vec<(Finger, DVec3, DVec3, f64)>,
    wrist: DVec3,
    /// The palm side's normal and the fingers' direction.
    palm: DVec3,
    distal: DVec3,
}

impl Built {
    /// The skin's end of finger `i`: its segment's end plus its radius along it.
    fn tip(&self, i: usize) -> DVec3 {
        let (_, a, b, r) = self.fingers[i];
        b + (b - a).normalize() * r
    }

    fn mirrored(&self) -> Built {
        let m = |v: DVec3| DVec3::new(-v.x, v.y, v.z);
        Built {
            shape: self.shape.mirrored(),
            fingers: self
                .fingers
                .iter()
                .map(|&(f, a, b, r)| (f, m(a), m(b), r))
                .collect(),
            wrist: m(self.wrist),
            palm: m(self.palm),
            distal: m(self.distal),
        }
    }

    /// The hand turned by `q` about the origin.
    fn turned(&self, q: DQuat) -> Built {
        let mut shape = self.shape.clone();
        shape.turn = q * shape.turn;
        Built {
            shape,
            fingers: self
                .fingers
                .iter()
                .map(|&(f, a, b, r)| (f, q * a, q * b, r))
                .collect(),
            wrist: q * self.wrist,
            palm: q * self.palm,
            distal: q * self.distal,
        }
    }
}

const MM: f64 = 0.001;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z) * MM
}

/// Palm, forearm stub, thumb and `long` fingers (index first) as capsules of
/// (x at the base in mm, splay in degrees towards +x, length, radius in mm).
fn right_hand(long: &[(f64, f64, f64, f64)]) -> Built {
    let mut parts = vec![
        Part::Box(v(0.0, 0.0, 0.0), v(44.0, 45.0, 13.0), 11.0 * MM),
        Part::Capsule(v(0.0, -75.0, 0.0), v(0.0, -40.0, 0.0), 24.0 * MM),
    ];
    let thumb_dir = DVec3::new(-0.55, 0.7, -0.45).normalize();
    let thumb_base = v(-33.0, -18.0, -6.0);
    let thumb_end = thumb_base + thumb_dir * 62.0 * MM;
    parts.push(Part::Capsule(thumb_base, thumb_end, 10.0 * MM));
    let mut fingers = vec![(Finger::Thumb, thumb_base, thumb_end, 10.0 * MM)];
    for (k, &(x, splay, len, r)) in long.iter().enumerate() {
        let a = v(x, 30.0, 0.0);
        let (s, c) = splay.to_radians().sin_cos();
        let b = a + DVec3::new(s, c, 0.0) * len * MM;
        parts.push(Part::Capsule(a, b, r * MM));
        fingers.push((Finger::ALL[k + 1], a, b, r * MM));
    }
    Built {
        shape: Shape::new(parts, 4.0 * MM),
        fingers,
        wrist: v(0.0, -55.0, 0.0),
        palm: -DVec3::Z,
        distal: DVec3::Y,
    }
}

fn five() -> Built {
    right_hand(&[
        (-32.0, -8.0, 78.0, 8.0),
        (-11.0, 0.0, 88.0, 8.5),
        (10.0, 7.0, 82.0, 8.0),
        (30.0, 15.0, 66.0, 7.0),
    ])
}

/// The distance from `q` to the line through a and b.
fn off_line(q: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = (b - a).normalize();
    let x = q - a;
    (x - d * x.dot(d)).length()
}

/// Checks a found hand against the built one: labels in order, side, tips
/// within 1 mm, every measured axis point within 1 mm of its line.
fn check(found: &FoundHand, built: &Built, side: Side) {
    assert_eq!(found.side, side, "{:?}", found.notes);
    let labels: Vec<Finger> = found.fingers.iter().map(|f| f.finger).collect();
    let want: Vec<Finger> = built.fingers.iter().map(|f| f.0).collect();
    assert_eq!(labels, want);
    for (i, f) in found.fingers.iter().enumerate() {
        let (_, a, b, r) = built.fingers[i];
        let e = f.tip.distance(built.tip(i));
        assert!(e < 1.0 * MM, "{:?} tip {:.2} mm off", f.finger, e / MM);
        let worst = f.axis[..f.measured]
            .iter()
            .map(|&q| off_line(q, a, b))
            .fold(0.0, f64::max);
        assert!(
            worst < 1.0 * MM,
            "{:?}: a measured axis point lies {:.2} mm off the capsule's axis",
            f.finger,
            worst / MM
        );
        // The radius along the free finger: the capsule's, within the grid's
        // faceting.
        let mid = f.radius[f.measured / 2];
        assert!(
            (mid - r).abs() < 0.5 * MM,
            "{:?} radius {}",
            f.finger,
            mid / MM
        );
        // The axis runs past the web, into the palm.
        let total = super::geometry::arcs(&f.axis)[f.axis.len() - 1];
        assert!(total >= f.web_arc + 2.0 * r - 1e-9, "{:?}", f.finger);
        assert_eq!(f.axis.len(), f.radius.len());
        assert!(f.tip_direction.dot((b - a).normalize()) > 0.999);
    }
    // The palm's normal towards the palm side, the fingers' direction.
    assert!(
        found.palm_normal.dot(built.palm) > 0.95,
        "{}",
        found.palm_normal
    );
    assert!(found.distal.dot(built.distal) > 0.95, "{}", found.distal);
    assert!(found.wrist.is_finite());
}

#[test]
fn a_built_right_hand_and_its_mirror_image() {
    let right = five();
    let mesh = right.shape.mesh(2.5 * MM);
    for wrist in [Some(right.wrist), None] {
        let opts = FindOptions {
            wrist,
            ..FindOptions::default()
        };
        let found = find_hand(&mesh, &opts).unwrap();
        check(&found, &right, Side::Right);
    }
    let left = right.mirrored();
    let found = find_hand(&left.shape.mesh(2.5 * MM), &FindOptions::default()).unwrap();
    check(&found, &left, Side::Left);
    // Turned any way in space, the same hands.
    let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.7, -1.9, 2.6);
    for (built, side) in [(right.turned(q), Side::Right), (left.turned(q), Side::Left)] {
        let found = find_hand(&built.shape.mesh(2.5 * MM), &FindOptions::default()).unwrap();
        check(&found, &built, side);
    }
}

/// The error `find_hand` gives for `mesh` with the default options.
fn error_of(mesh: &HandMesh, opts: &FindOptions) -> FindError {
    match find_hand(mesh, opts) {
        Ok(h) => panic!(
            "found a {} hand with {:?}",
            h.side.name(),
            h.fingers.iter().map(|f| f.finger).collect::<Vec<_>>()
        ),
        Err(e) => e,
    }
}

#[test]
fn a_thumb_and_three_fingers() {
    // The GDQuest mannequin's kind of hand: no little finger.
    let built = right_hand(&[
        (-28.0, -8.0, 78.0, 9.0),
        (0.0, 0.0, 88.0, 9.5),
        (27.0, 10.0, 80.0, 9.0),
    ]);
    let mesh = built.shape.mesh(2.5 * MM);
    let opts = FindOptions {
        fingers: 4,
        ..FindOptions::default()
    };
    check(&find_hand(&mesh, &opts).unwrap(), &built, Side::Right);
    // Asked for five, it says what it found.
    let e = error_of(&mesh, &FindOptions::default());
    assert_eq!(
        e.to_string(),
        "found 4 extremities beyond the wrist; a hand has 5: are two fingers fused, or does \
         the hand have 4 (give the count)?"
    );
}

#[test]
fn the_side_given_decides_only_when_the_skin_cannot() {
    let right = five();
    let mesh = right.shape.mesh(2.5 * MM);
    // Given the wrong side, the side given is kept and the disagreement noted.
    let opts = FindOptions {
        side: Some(Side::Left),
        ..FindOptions::default()
    };
    let found = find_hand(&mesh, &opts).unwrap();
    assert_eq!(found.side, Side::Left);
    assert!(
        found
            .notes
            .iter()
            .any(|n| n.contains("reads as a right hand")),
        "{:?}",
        found.notes
    );
    // A left hand's palm side is then +z: its thumb (at -x) lies on the side
    // of distal x normal, and a left hand has it on the other.
    assert!(found.palm_normal.dot(DVec3::Z) > 0.95);
    // A flat hand (the thumb in the palm's plane, no fingertip off it) has no
    // palm side: the side must be given.
    let mut flat = five();
    let dir = DVec3::new(-0.6, 0.8, 0.0);
    let base = v(-33.0, -18.0, 0.0);
    flat.shape.parts[2] = Part::Capsule(base, base + dir * 62.0 * MM, 10.0 * MM);
    flat.fingers[0] = (Finger::Thumb, base, base + dir * 62.0 * MM, 10.0 * MM);
    let mesh = flat.shape.mesh(2.5 * MM);
    assert_eq!(error_of(&mesh, &FindOptions::default()), FindError::NoSide);
    let found = find_hand(
        &mesh,
        &FindOptions {
            side: Some(Side::Right),
            ..FindOptions::default()
        },
    )
    .unwrap();
    check(&found, &flat, Side::Right);
}

#[test]
fn shapes_that_are_not_a_hand_at_rest_are_refused_each_with_its_reason() {
    // A cube and a sphere: no fingers.
    let cube = Shape::new(vec![Part::Box(DVec3::ZERO, v(50.0, 50.0, 50.0), 0.0)], 0.0);
    let e = error_of(&cube.mesh(5.0 * MM), &FindOptions::default());
    assert!(
        matches!(e, FindError::TooFew { .. } | FindError::NoWrist(_)),
        "{e}"
    );
    let sphere = Shape::new(vec![Part::Sphere(DVec3::ZERO, 60.0 * MM)], 0.0);
    let e = error_of(&sphere.mesh(5.0 * MM), &FindOptions::default());
    // The far side of a sphere from any cut is one maximum: one extremity.
    assert!(matches!(e, FindError::TooFew { found: 0 | 1, .. }), "{e}");
    assert!(e.to_string().contains("a hand?"), "{e}");
    // A mitten: the four fingers one slab.
    let mut mitten = five();
    mitten.shape.parts.truncate(3);
    mitten
        .shape
        .parts
        .push(Part::Box(v(0.0, 70.0, 0.0), v(42.0, 45.0, 10.0), 9.0 * MM));
    let e = error_of(&mitten.shape.mesh(2.5 * MM), &FindOptions::default());
    assert!(matches!(e, FindError::TooFew { found: 1 | 2, .. }), "{e}");
    assert!(e.to_string().contains("mitten"), "{e}");
    let e = error_of(
        &mitten.shape.mesh(2.5 * MM),
        &FindOptions {
            wrist: Some(mitten.wrist),
            ..FindOptions::default()
        },
    );
    assert!(matches!(e, FindError::TooFew { found: 2, .. }), "{e}");
    // Two fingers fused side by side: one wide finger among narrow ones.
    let mut fused = right_hand(&[
        (-32.0, -8.0, 78.0, 8.0),
        (-5.0, 0.0, 88.0, 8.5),
        (30.0, 15.0, 66.0, 7.0),
        (-11.0, 10.0, 60.0, 6.0),
    ]);
    // The middle and ring as one slab 36 mm wide instead.
    fused.shape.parts[4] = Part::Box(v(1.0, 72.0, 0.0), v(19.0, 40.0, 9.0), 9.0 * MM);
    fused.shape.parts.pop();
    fused.shape.parts.push(Part::Capsule(
        v(50.0, 25.0, 0.0),
        v(70.0, 75.0, 0.0),
        7.0 * MM,
    ));
    let e = error_of(&fused.shape.mesh(2.5 * MM), &FindOptions::default());
    assert!(matches!(e, FindError::Fused { .. }), "{e}");
    // A fist: every finger turned 70, 100 and 60 degrees at its joints
    // towards the palm (230 in all), its tip hanging over the palm.
    let mut fist = Shape::new(five().shape.parts[..3].to_vec(), 4.0 * MM);
    for (x, r) in [(-32.0, 8.0), (-11.0, 8.5), (10.0, 8.0), (30.0, 7.0)] {
        let mut at = v(x, 30.0, 0.0);
        let mut angle: f64 = 0.0;
        for (bend, len) in [(70.0, 42.0), (100.0, 26.0), (60.0, 20.0)] {
            angle += bend;
            let d = DVec3::new(0.0, angle.to_radians().cos(), -angle.to_radians().sin());
            let next = at + d * len * MM;
            fist.parts.push(Part::Capsule(at, next, r * MM));
            at = next;
        }
    }
    let e = error_of(&fist.mesh(2.5 * MM), &FindOptions::default());
    assert!(matches!(e, FindError::Fist(_)), "{e}");
    assert!(
        e.to_string().starts_with("the hand is posed in a fist"),
        "{e}"
    );
}

fn opts_for(side: Side) -> FindOptions {
    FindOptions {
        side: Some(side),
        ..FindOptions::default()
    }
}

#[test]
fn two_hands_in_one_mesh() {
    let right = five();
    let left = right.mirrored();
    let shift = v(250.0, 0.0, 0.0);
    let both = Shape::new(
        right
            .shape
            .parts
            .iter()
            .copied()
            .chain(left.shape.moved(shift).parts)
            .collect(),
        4.0 * MM,
    );
    let mesh = both.mesh(2.5 * MM);
    let e = error_of(&mesh, &FindOptions::default());
    assert!(matches!(e, FindError::TwoHands { found: 10 }), "{e}");
    assert!(e.to_string().contains("give --side to take one"), "{e}");
    assert_eq!(
        e.in_file("hands.glb").to_string(),
        format!("1 problem in hands.glb:\n  hands.glb: {e}")
    );
    // Joined by a bar, one skin: --side cannot take one.
    let mut joined = both.clone();
    joined.parts.push(Part::Capsule(
        v(0.0, -75.0, 0.0),
        v(250.0, -75.0, 0.0),
        15.0 * MM,
    ));
    let e = error_of(&joined.mesh(2.5 * MM), &opts_for(Side::Left));
    assert!(matches!(e, FindError::TwoHandsJoined { .. }), "{e}");
    // Given a side, that hand.
    let found = find_hand(&mesh, &opts_for(Side::Left)).unwrap();
    let mut moved = left.mirrored().mirrored();
    moved.shape = left.shape.moved(shift);
    for f in &mut moved.fingers {
        f.1 += shift;
        f.2 += shift;
    }
    check(&found, &moved, Side::Left);
    // Given a wrist, the hand there.
    let opts = FindOptions {
        wrist: Some(right.wrist),
        ..FindOptions::default()
    };
    check(&find_hand(&mesh, &opts).unwrap(), &right, Side::Right);
}

#[test]
fn bad_meshes_are_refused_without_a_panic() {
    let opts = FindOptions::default();
    let empty = HandMesh::default();
    assert_eq!(error_of(&empty, &opts), FindError::Empty);
    let one = HandMesh {
        positions: vec![DVec3::ZERO],
        ..HandMesh::default()
    };
    assert_eq!(error_of(&one, &opts), FindError::Empty);
    let mut hand = five().shape.mesh(2.5 * MM);
    hand.positions[7] = DVec3::new(f64::NAN, 0.0, 0.0);
    assert_eq!(error_of(&hand, &opts), FindError::NotFinite(7));
    hand.positions[7] = DVec3::new(0.0, f64::INFINITY, 0.0);
    assert_eq!(error_of(&hand, &opts), FindError::NotFinite(7));
    let mut hand = five().shape.mesh(2.5 * MM);
    let n = hand.positions.len();
    hand.triangles[3][1] = n as u32;
    assert_eq!(
        error_of(&hand, &opts).to_string(),
        format!("triangle 3 names vertex {n}, but the mesh has {n}")
    );
    // Every vertex at one point; a flat sheet.
    let point = HandMesh {
        positions: vec![DVec3::ONE; 3],
        triangles: vec![[0, 1, 2]],
        ..HandMesh::default()
    };
    assert_eq!(error_of(&point, &opts), FindError::Flat);
    let sheet = HandMesh {
        positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE.with_z(0.0)],
        triangles: vec![[0, 1, 2], [1, 3, 2]],
        ..HandMesh::default()
    };
    assert!(find_hand(&sheet, &opts).is_err());
    // A wrist far from the hand.
    let hand = five().shape.mesh(2.5 * MM);
    let far = FindOptions {
        wrist: Some(v(0.0, -55.0, 1000.0)),
        ..opts.clone()
    };
    let e = error_of(&hand, &far);
    assert!(matches!(e, FindError::WristOff { .. }), "{e}");
    // 1000 mm above the forearm's axis, whose skin lies 24 mm from it (by hand,
    // within the grid's faceting).
    assert!(
        e.to_string().starts_with("the wrist given lies 976 mm"),
        "{e}"
    );
    // Options out of range.
    for fingers in [0, 1, 6] {
        let e = error_of(
            &sheet,
            &FindOptions {
                fingers,
                ..opts.clone()
            },
        );
        assert!(matches!(e, FindError::Options(_)), "{e}");
    }
    // Fins (an edge of three triangles, the third's corner 1 mm off the
    // skin) on every 50th triangle and a stray triangle far away leave the
    // same hand.
    let right = five();
    let mut hand = right.shape.mesh(2.5 * MM);
    for t in hand.triangles.clone().iter().step_by(50) {
        let [a, b, c] = t.map(|i| hand.positions[i as usize]);
        let n = (b - a).cross(c - a).normalize_or_zero();
        hand.positions.push((a + b) / 2.0 + n * MM);
        let m = hand.positions.len() as u32 - 1;
        hand.triangles.push([t[0], t[1], m]);
    }
    let far = hand.positions.len() as u32;
    hand.positions.extend([
        DVec3::splat(1.0),
        DVec3::new(1.0, 1.001, 1.0),
        DVec3::new(1.0, 1.0, 1.001),
    ]);
    hand.triangles.push([far, far + 1, far + 2]);
    let found = find_hand(&hand, &opts).unwrap();
    check(&found, &right, Side::Right);
    assert!(
        found
            .notes
            .iter()
            .any(|n| n.contains("too small to be a hand")),
        "{:?}",
        found.notes
    );
    // Random soups of points and triangles: an answer, never a panic.
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for case in 0..40 {
        let n = 1 + (next() % 60) as usize;
        let positions: Vec<DVec3> = (0..n)
            .map(|_| {
                let mut c = || (next() % 2001) as f64 / 1000.0 - 1.0;
                DVec3::new(c(), c(), c()) * if case % 3 == 0 { 1e-30 } else { 0.1 }
            })
            .collect();
        let triangles: Vec<[u32; 3]> = (0..(next() % 120))
            .map(|_| [0, 1, 2].map(|_| (next() % n as u64) as u32))
            .collect();
        let mesh = HandMesh {
            positions,
            triangles,
            ..HandMesh::default()
        };
        let _ = find_hand(&mesh, &opts);
    }
}
