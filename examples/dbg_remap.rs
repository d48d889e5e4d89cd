use phalanx::rig::judge::carry;
use phalanx::rig::{Rig, bend};
use std::path::Path;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rig = Rig::load(Path::new(&args[1]), None).unwrap();
    let w = rig.weights.as_ref().unwrap();
    let c = rig
        .chains
        .iter()
        .find(|c| format!("{:?}", c.finger) == args[2])
        .unwrap();
    let k: usize = args[3].parse().unwrap();
    let d: f64 = args[4].parse().unwrap();
    let bends = bend::bends(c, w, 0.003);
    let dir = (c.joints[k].position - c.joints[k - 1].position).normalize();
    let target = c.joints[k].position + dir * d / 1000.0;
    let m = carry::FingerMove::of(c, &bends, |j| (j == c.joints[k].joint).then_some(target));
    let (out, offs, notes) = carry::carry_finger(w, &m, 0.003);
    println!("offsets {:?} notes {:?}", offs, notes);
    let mut moved = c.clone();
    moved.joints[k].position = target;
    let (nodes, before) = bend::finger_nodes(&moved).unwrap();
    let pts: Vec<_> = moved.joints.iter().map(|j| j.position).collect();
    let axis = bend::FingerAxis::new(&pts, moved.has_tip).unwrap();
    let vs = bend::finger_vertices_with(&axis, w, &nodes, &before, Some(&out));
    let pj = axis.joint(k);
    let mut rows: Vec<(f64, f64, f64)> = vs
        .iter()
        .filter_map(|v| {
            let (mut dd, mut pp) = (0.0, 0.0);
            for &(n, wt) in v.influences {
                if nodes[k..].contains(&n) {
                    dd += wt
                } else if nodes[..k].contains(&n) || before.contains(&n) {
                    pp += wt
                }
            }
            (dd + pp >= 0.5
                && v.u >= axis.joint(k - 1)
                && v.u <= axis.joint(k).max(axis.joint(k)) + 0.03)
                .then(|| (v.u - pj, dd / (dd + pp), v.radial))
        })
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (u, s, r) in rows {
        print!("{:.1}:{:.2}(r{:.1}) ", u * 1000.0, s, r * 1000.0);
    }
    println!();
}
