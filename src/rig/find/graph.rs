//! The mesh as a graph for [`super::find`]: its edges with their lengths,
//! bridges across the small gaps between separate pieces, geodesic distance
//! (Dijkstra), and the persistence of the distance's maxima.
//!
//! **Bridges.** Some hands are built of pieces: the GDQuest mannequin's
//! phalanges are separate closed shells that touch their neighbours (gaps of
//! 0.6-1.3 mm along a finger, 1.6-5.4 mm to the palm), a glove has its strap.
//! Geodesics must cross those gaps. Every vertex of a piece other than the
//! largest finds its nearest vertex of another piece within `gap` (a uniform
//! grid, 27 cells); the pieces are joined by the shortest such pairs first
//! (Kruskal's minimum spanning forest over the pieces), and each joint is
//! made wide: every pair between the two pieces no longer than twice the
//! shortest (or the shortest plus a quarter of the median edge) becomes an
//! edge. A spanning forest, not every close pair: on the mannequin the
//! fingers' neighbouring phalanges lie 2.5-4.4 mm apart, and joining them
//! would join the fingers above their webs; each finger's shortest way is
//! to its own next phalanx (0.6-1.3 mm) and then to the palm (1.6-2.5 mm).
//! Pieces farther than `gap` from everything stay apart (another object).

use glam::DVec3;
use rustc_hash::FxHashMap;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// An undirected graph over the mesh's vertices in compressed rows.
#[derive(Debug, Clone)]
pub(crate) struct Graph {
    /// `start[v]..start[v + 1]` index `next` and `length`.
    start: Vec<usize>,
    next: Vec<u32>,
    length: Vec<f64>,
}

impl Graph {
    /// The graph of `edges` (each once, either way round) over `n` vertices.
    pub(crate) fn new(n: usize, edges: &[(u32, u32, f64)]) -> Graph {
        let mut degree = vec![0usize; n + 1];
        for &(a, b, _) in edges {
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
        let mut start = vec![0usize; n + 1];
        for v in 0..n {
            start[v + 1] = start[v] + degree[v];
        }
        let mut fill = start.clone();
        let mut next = vec![0u32; start[n]];
        let mut length = vec![0.0; start[n]];
        for &(a, b, l) in edges {
            for (x, y) in [(a, b), (b, a)] {
                let at = fill[x as usize];
                next[at] = y;
                length[at] = l;
                fill[x as usize] += 1;
            }
        }
        Graph {
            start,
            next,
            length,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// The neighbours of `v` with the lengths of the edges to them.
    pub(crate) fn neighbours(&self, v: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (a, b) = (self.start[v], self.start[v + 1]);
        self.next[a..b]
            .iter()
            .zip(&self.length[a..b])
            .map(|(&u, &l)| (u as usize, l))
    }
}

/// The edges of `triangles` (each once, lower index first), with their lengths. O(T).
pub(crate) fn mesh_edges(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32, f64)> {
    let mut seen: FxHashMap<(u32, u32), ()> = FxHashMap::default();
    let mut out = Vec::with_capacity(triangles.len() * 3 / 2 + 1);
    for t in triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let key = (a.min(b), a.max(b));
            if seen.insert(key, ()).is_none() {
                let l = positions[a as usize].distance(positions[b as usize]);
                out.push((key.0, key.1, l));
            }
        }
    }
    out
}

/// Union-find with path halving and union by size.
#[derive(Debug, Clone)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    pub(crate) fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    pub(crate) fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] as usize != x {
            let p = self.parent[x] as usize;
            self.parent[x] = self.parent[p];
            x = self.parent[x] as usize;
        }
        x
    }

    /// Joins the sets of `a` and `b`; false when they were one already.
    pub(crate) fn union(&mut self, a: usize, b: usize) -> bool {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return false;
        }
        if self.size[a] < self.size[b] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b] = a as u32;
        self.size[a] += self.size[b];
        true
    }
}

/// Each vertex's connected piece under `edges`, as the lowest vertex index
/// of the piece. O(E a(V)).
pub(crate) fn pieces(n: usize, edges: &[(u32, u32, f64)]) -> Vec<u32> {
    let mut uf = UnionFind::new(n);
    for &(a, b, _) in edges {
        uf.union(a as usize, b as usize);
    }
    let mut lowest: Vec<u32> = vec![u32::MAX; n];
    let mut out = vec![0u32; n];
    for (v, o) in out.iter_mut().enumerate() {
        let r = uf.find(v);
        if lowest[r] == u32::MAX {
            lowest[r] = v as u32;
        }
        *o = lowest[r];
    }
    out
}

/// The bridges across gaps of at most `gap` between the pieces of the mesh
/// (see the module doc); `median` is the median edge length. O(V) for
/// vertices spread evenly over the grid's cells.
pub(crate) fn bridges(
    positions: &[DVec3],
    piece: &[u32],
    gap: f64,
    median: f64,
) -> Vec<(u32, u32, f64)> {
    let n = positions.len();
    let mut count: FxHashMap<u32, usize> = FxHashMap::default();
    for &p in piece {
        *count.entry(p).or_default() += 1;
    }
    if count.len() < 2 || !(gap > 0.0 && gap.is_finite()) {
        return Vec::new();
    }
    let largest = count
        .iter()
        .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0)))
        .map_or(0, |(&p, _)| p);
    let lo = positions
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |m, p| m.min(*p));
    let cell = |p: DVec3| -> [i64; 3] { ((p - lo) / gap).floor().to_array().map(|x| x as i64) };
    let mut grid: FxHashMap<[i64; 3], Vec<u32>> = FxHashMap::default();
    for (v, &p) in positions.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(v as u32);
    }
    // The nearest vertex of another piece, for every vertex off the largest piece.
    let mut pairs: Vec<(f64, u32, u32)> = Vec::new();
    for v in 0..n {
        if piece[v] == largest {
            continue;
        }
        let c = cell(positions[v]);
        let mut best: Option<(f64, u32)> = None;
        for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                for dz in -1..=1i64 {
                    let k = [
                        c[0].saturating_add(dx),
                        c[1].saturating_add(dy),
                        c[2].saturating_add(dz),
                    ];
                    for &w in grid.get(&k).map_or(&[][..], Vec::as_slice) {
                        if piece[w as usize] == piece[v] {
                            continue;
                        }
                        let d = positions[v].distance(positions[w as usize]);
                        if d <= gap && best.is_none_or(|b| d < b.0) {
                            best = Some((d, w));
                        }
                    }
                }
            }
        }
        if let Some((d, w)) = best {
            pairs.push((d, v as u32, w));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    // Kruskal over the pieces: the shortest pair joining two groups is a joint.
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut uf = UnionFind::new(n);
    let mut joints: FxHashMap<(u32, u32), f64> = FxHashMap::default();
    for &(d, v, w) in &pairs {
        let (a, b) = (piece[v as usize], piece[w as usize]);
        if uf.union(a as usize, b as usize) {
            joints.insert(key(a, b), d);
        }
    }
    let mut out: Vec<(u32, u32, f64)> = pairs
        .iter()
        .filter(|&&(d, v, w)| {
            joints
                .get(&key(piece[v as usize], piece[w as usize]))
                .is_some_and(|&shortest| d <= (2.0 * shortest).max(shortest + 0.25 * median))
        })
        .map(|&(d, v, w)| (v.min(w), v.max(w), d))
        .collect();
    out.sort_by_key(|a| (a.0, a.1));
    out.dedup_by(|a, b| (a.0, a.1) == (b.0, b.1));
    out
}

/// A vertex and its tentative distance in Dijkstra's queue, nearest first.
#[derive(PartialEq)]
struct Queued(f64, u32);

impl Eq for Queued {}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Geodesic distance over the graph's edges from `sources` (vertex, starting
/// distance), visiting only the vertices `allowed` says (all for `None`);
/// infinite where unreached. Dijkstra with a binary heap: O(E log V).
pub(crate) fn dijkstra(
    graph: &Graph,
    sources: &[(u32, f64)],
    allowed: Option<&[bool]>,
) -> Vec<f64> {
    let n = graph.len();
    let ok = |v: usize| allowed.is_none_or(|a| a[v]);
    let mut dist = vec![f64::INFINITY; n];
    let mut heap = BinaryHeap::new();
    for &(s, d) in sources {
        let s = s as usize;
        if s < n && ok(s) && d < dist[s] {
            dist[s] = d;
            heap.push(Queued(d, s as u32));
        }
    }
    while let Some(Queued(d, v)) = heap.pop() {
        let v = v as usize;
        if d > dist[v] {
            continue;
        }
        for (u, l) in graph.neighbours(v) {
            let nd = d + l;
            if nd < dist[u] && ok(u) {
                dist[u] = nd;
                heap.push(Queued(nd, u as u32));
            }
        }
    }
    dist
}

/// One maximum of a function on the graph and its persistence pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Extremity {
    /// The vertex of the maximum.
    pub top: u32,
    /// The function's value there.
    pub birth: f64,
    /// The value at the saddle where its component met an older one
    /// (`None` for the oldest component of each connected piece).
    pub death: Option<f64>,
    /// The saddle vertex (`None` with `death`).
    pub saddle: Option<u32>,
    /// The maximum of the older component it met (`None` with `death`).
    pub into: Option<u32>,
}

impl Extremity {
    /// Birth minus death; for the oldest, birth minus `floor`.
    pub(crate) fn persistence(&self, floor: f64) -> f64 {
        self.birth - self.death.unwrap_or(floor)
    }
}

/// The 0-dimensional persistence of the super-level sets of `f` (finite
/// values only): sweeping f from high to low, each vertex joins the
/// components of its neighbours already swept (union-find over the edges); a
/// component is born at a maximum and dies at the vertex where it meets a
/// component born higher (the elder rule, ties by the lower vertex index).
/// Every maximum is listed, the oldest of each piece without a death.
/// O(V log V + E a(V)).
pub(crate) fn persistence(graph: &Graph, f: &[f64]) -> Vec<Extremity> {
    let n = graph.len();
    let mut order: Vec<u32> = (0..n as u32)
        .filter(|&v| f[v as usize].is_finite())
        .collect();
    order.sort_by(|&a, &b| f[b as usize].total_cmp(&f[a as usize]).then(a.cmp(&b)));
    let mut uf = UnionFind::new(n);
    let mut swept = vec![false; n];
    // The maximum of each component, at its root.
    let mut top: Vec<u32> = (0..n as u32).collect();
    let elder = |a: u32, b: u32| -> bool {
        // True when a was born before (higher than) b.
        match f[a as usize].total_cmp(&f[b as usize]) {
            Ordering::Greater => true,
            Ordering::Less => false,
            Ordering::Equal => a < b,
        }
    };
    let mut out = Vec::new();
    let mut born = vec![false; n];
    for &v in &order {
        let vi = v as usize;
        swept[vi] = true;
        let mut joined = false;
        for (u, _) in graph.neighbours(vi) {
            if !swept[u] {
                continue;
            }
            let (ru, rv) = (uf.find(u), uf.find(vi));
            if ru == rv {
                continue;
            }
            if !joined {
                // v joins its first neighbour's component: no new maximum.
                let t = top[ru];
                uf.union(ru, rv);
                let r = uf.find(vi);
                top[r] = t;
                joined = true;
                continue;
            }
            let (tu, tv) = (top[ru], top[rv]);
            let (old, young) = if elder(tu, tv) { (tu, tv) } else { (tv, tu) };
            out.push(Extremity {
                top: young,
                birth: f[young as usize],
                death: Some(f[vi]),
                saddle: Some(v),
                into: Some(old),
            });
            uf.union(ru, rv);
            let r = uf.find(vi);
            top[r] = old;
        }
        if !joined {
            born[vi] = true;
            top[vi] = v;
        }
    }
    // The survivors: one per piece.
    let mut seen = vec![false; n];
    for &v in &order {
        let r = uf.find(v as usize);
        if !seen[r] {
            seen[r] = true;
            let t = top[r];
            out.push(Extremity {
                top: t,
                birth: f[t as usize],
                death: None,
                saddle: None,
                into: None,
            });
        }
    }
    debug_assert!(out.iter().all(|e| born[e.top as usize]));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path_graph(n: usize) -> Graph {
        let edges: Vec<(u32, u32, f64)> =
            (0..n - 1).map(|i| (i as u32, i as u32 + 1, 1.0)).collect();
        Graph::new(n, &edges)
    }

    #[test]
    fn persistence_of_a_path_with_two_peaks_and_a_bump() {
        // f along a path: 0 1 5 2 4 3.5 3.8 1; maxima at 2 (5), 4 (4), 6 (3.8).
        // Sweeping down: 2 born at 5; 4 born at 4; 6 born at 3.8; 5 (3.5)
        // joins 4 and 6: 6 dies at 3.5 (persistence 0.3); 3 (2) joins 2 and 4:
        // 4 dies at 2 (persistence 2); 2 never dies. By hand.
        let f = [0.0, 1.0, 5.0, 2.0, 4.0, 3.5, 3.8, 1.0];
        let g = path_graph(f.len());
        let mut p = persistence(&g, &f);
        p.sort_by_key(|a| a.top);
        assert_eq!(p.len(), 3);
        assert_eq!((p[0].top, p[0].death), (2, None));
        assert_eq!(
            (p[1].top, p[1].death, p[1].saddle, p[1].into),
            (4, Some(2.0), Some(3), Some(2))
        );
        assert_eq!(
            (p[2].top, p[2].death, p[2].saddle, p[2].into),
            (6, Some(3.5), Some(5), Some(4))
        );
        assert!((p[2].persistence(0.0) - 0.3).abs() < 1e-12);
        assert_eq!(p[0].persistence(0.0), 5.0);
    }

    #[test]
    fn dijkstra_from_two_sources_with_offsets() {
        let g = path_graph(5);
        let d = dijkstra(&g, &[(0, 0.5), (4, 0.0)], None);
        assert_eq!(d, vec![0.5, 1.5, 2.0, 1.0, 0.0]);
        // Vertex 2 not allowed: 0..1 from the first source, 3..4 from the second.
        let allowed = [true, true, false, true, true];
        let d = dijkstra(&g, &[(0, 0.0)], Some(&allowed));
        assert_eq!(d[1], 1.0);
        assert!(d[3].is_infinite());
    }

    #[test]
    fn bridges_join_pieces_along_their_shortest_gaps_only() {
        // Three pieces on a line: A = {0, 1} at x 0, 1; B = {2, 3} at x 1.5,
        // 2.5; C = {4} at x 2.9. Nearest foreign pairs: 1-2 (0.5), 3-4 (0.4).
        // A 4 also sits 1.4 from 2, but A-B and B-C are joined already.
        let p: Vec<DVec3> = [0.0, 1.0, 1.5, 2.5, 2.9]
            .iter()
            .map(|&x| DVec3::new(x, 0.0, 0.0))
            .collect();
        let edges = [(0, 1, 1.0), (2, 3, 1.0)];
        let piece = pieces(5, &edges);
        assert_eq!(piece, vec![0, 0, 2, 2, 4]);
        let b = bridges(&p, &piece, 1.0, 1.0);
        let pairs: Vec<(u32, u32)> = b.iter().map(|x| (x.0, x.1)).collect();
        assert_eq!(pairs, vec![(1, 2), (3, 4)], "{b:?}");
        // Gaps beyond `gap` stay open.
        assert!(bridges(&p, &piece, 0.3, 1.0).is_empty());
    }
}
