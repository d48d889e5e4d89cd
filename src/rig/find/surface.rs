//! The mesh as [`super::find`] searches it: checked (finite positions,
//! triangles naming vertices it has), as a graph of its edges with the
//! bridges across small gaps between its pieces ([`super::graph`]), and cut
//! into objects, the bridged pieces, each searched for a hand.

use super::graph::{Extremity, Graph, bridges, mesh_edges, pieces};
use super::hand::FindError;
use super::mesh::HandMesh;
use glam::DVec3;

/// The mesh checked, with its graph.
pub(super) struct Surface<'a> {
    pub(super) positions: &'a [DVec3],
    pub(super) triangles: &'a [[u32; 3]],
    pub(super) graph: Graph,
    pub(super) median_edge: f64,
    /// Each vertex's object (bridged piece), as its lowest vertex.
    pub(super) object: Vec<u32>,
}

/// One bridged piece of the mesh.
pub(super) struct Object {
    pub(super) vertices: Vec<u32>,
    /// Per vertex of the mesh, whether it belongs here.
    pub(super) mask: Vec<bool>,
    pub(super) tris: Vec<[u32; 3]>,
}

impl Object {
    /// The distance from `p` to the object's nearest vertex.
    pub(super) fn distance(&self, s: &Surface<'_>, p: DVec3) -> f64 {
        self.vertices
            .iter()
            .map(|&v| s.positions[v as usize].distance(p))
            .fold(f64::INFINITY, f64::min)
    }
}

impl<'a> Surface<'a> {
    pub(super) fn new(mesh: &'a HandMesh) -> Result<Surface<'a>, FindError> {
        let n = mesh.positions.len();
        if mesh.triangles.is_empty() || n == 0 {
            return Err(FindError::Empty);
        }
        if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(FindError::NotFinite(v));
        }
        for (i, t) in mesh.triangles.iter().enumerate() {
            if let Some(&v) = t.iter().find(|&&v| v as usize >= n) {
                return Err(FindError::BadTriangle {
                    triangle: i,
                    vertex: v,
                    vertices: n,
                });
            }
        }
        let mut edges = mesh_edges(&mesh.positions, &mesh.triangles);
        let mut lengths: Vec<f64> = edges.iter().map(|e| e.2).filter(|l| *l > 0.0).collect();
        if lengths.is_empty() {
            return Err(FindError::Flat);
        }
        let mid = lengths.len() / 2;
        let median_edge = *lengths.select_nth_unstable_by(mid, f64::total_cmp).1;
        let (lo, hi) = mesh.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let size = (hi - lo).length();
        if !(size > 0.0 && size.is_finite()) {
            return Err(FindError::Flat);
        }
        let piece = pieces(n, &edges);
        let gap = (2.0 * median_edge).max(0.02 * size);
        edges.extend(bridges(&mesh.positions, &piece, gap, median_edge));
        let graph = Graph::new(n, &edges);
        let object = pieces(n, &edges);
        Ok(Surface {
            positions: &mesh.positions,
            triangles: &mesh.triangles,
            graph,
            median_edge,
            object,
        })
    }

    /// The objects with triangles, largest (most vertices) first.
    pub(super) fn objects(&self) -> Vec<Object> {
        let n = self.positions.len();
        let mut index: rustc_hash::FxHashMap<u32, usize> = rustc_hash::FxHashMap::default();
        let mut out: Vec<Object> = Vec::new();
        for t in self.triangles {
            let o = self.object[t[0] as usize];
            let i = *index.entry(o).or_insert_with(|| {
                out.push(Object {
                    vertices: Vec::new(),
                    mask: vec![false; n],
                    tris: Vec::new(),
                });
                out.len() - 1
            });
            let obj = &mut out[i];
            obj.tris.push(*t);
            for &v in t {
                if !obj.mask[v as usize] {
                    obj.mask[v as usize] = true;
                    obj.vertices.push(v);
                }
            }
        }
        out.sort_by_key(|o| std::cmp::Reverse(o.vertices.len()));
        out
    }
}

/// The object's extent along `dir`: (lowest, highest) projection of its vertices.
pub(super) fn extent(s: &Surface<'_>, obj: &Object, dir: DVec3) -> (f64, f64) {
    obj.vertices
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            let x = s.positions[v as usize].dot(dir);
            (lo.min(x), hi.max(x))
        })
}

/// True when the tops of `extremities` fall into two clusters of at least
/// `wanted - 1` each (two-means along the line through the two farthest).
pub(super) fn two_clusters(s: &Surface<'_>, extremities: &[Extremity], wanted: usize) -> bool {
    let pts: Vec<DVec3> = extremities
        .iter()
        .map(|e| s.positions[e.top as usize])
        .collect();
    let mut far = (0, 0, 0.0);
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            let d = pts[i].distance(pts[j]);
            if d > far.2 {
                far = (i, j, d);
            }
        }
    }
    let (mut a, mut b) = (pts[far.0], pts[far.1]);
    let mut side = vec![false; pts.len()];
    for _ in 0..10 {
        for (k, p) in pts.iter().enumerate() {
            side[k] = p.distance(b) < p.distance(a);
        }
        let mean = |which: bool| {
            let sel: Vec<DVec3> = pts
                .iter()
                .zip(&side)
                .filter(|(_, s)| **s == which)
                .map(|(p, _)| *p)
                .collect();
            (!sel.is_empty()).then(|| sel.iter().copied().sum::<DVec3>() / sel.len() as f64)
        };
        match (mean(false), mean(true)) {
            (Some(x), Some(y)) => (a, b) = (x, y),
            _ => return false,
        }
    }
    let nb = side.iter().filter(|s| **s).count();
    let na = side.len() - nb;
    // Two clusters: each big enough, and farther apart than they are wide.
    let spread = |which: bool, c: DVec3| {
        pts.iter()
            .zip(&side)
            .filter(|(_, s)| **s == which)
            .map(|(p, _)| p.distance(c))
            .fold(0.0, f64::max)
    };
    na + 1 >= wanted && nb + 1 >= wanted && a.distance(b) > spread(false, a) + spread(true, b)
}
