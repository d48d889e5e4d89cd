//! Views, cameras and the meshes they see: orthographic projection in the hand's own frame.

use crate::rig::deform::PalmFrame;
use glam::{DVec2, DVec3};

/// An orthographic view direction: screen right and up in world space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub name: &'static str,
    pub right: DVec3,
    pub up: DVec3,
}

impl View {
    /// From the little finger's side, looking along the flexion axes (a curled
    /// finger shows its profile), the back of the hand up: a right hand's
    /// fingers point right, a left hand's left (the mirror image).
    pub fn side(frame: &PalmFrame) -> View {
        let up = -frame.normal;
        let toward = -frame.radial;
        View {
            name: "side",
            right: up.cross(toward),
            up,
        }
    }

    /// Looking down at the back of the hand, fingers up.
    pub fn above(frame: &PalmFrame) -> View {
        let up = frame.distal;
        let toward = -frame.normal;
        View {
            name: "above",
            right: up.cross(toward),
            up,
        }
    }

    /// The direction from the scene to the viewer (right x up).
    pub fn toward(&self) -> DVec3 {
        self.right.cross(self.up)
    }
}

/// Where a view puts points on the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub view: View,
    /// Pixels per world unit.
    pub scale: f64,
    /// The world point (in view coordinates right, up) drawn at `at`.
    pub centre: DVec2,
    /// Its pixel position in the image.
    pub at: DVec2,
}

impl Camera {
    /// Projects `p`: (x pixels, y pixels downwards, depth; larger is farther).
    pub fn project(&self, p: DVec3) -> (f64, f64, f64) {
        let v = DVec2::new(p.dot(self.view.right), p.dot(self.view.up)) - self.centre;
        (
            self.at.x + v.x * self.scale,
            self.at.y - v.y * self.scale,
            -p.dot(self.view.toward()),
        )
    }
}

/// A posed mesh to draw, with one strain value per vertex.
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a> {
    pub positions: &'a [DVec3],
    pub triangles: &'a [[u32; 3]],
    pub strain: &'a [f64],
    /// The vertices a panel is framed on (a hand's, in a whole body's mesh),
    /// one flag per vertex; empty, or none set: every vertex. The rest of
    /// the mesh is drawn too, cut at the panel's edges.
    pub focus: &'a [bool],
}

impl MeshView<'_> {
    /// The vertices to frame: the focus, or every vertex without one.
    pub(super) fn framed(&self) -> impl Iterator<Item = &DVec3> + '_ {
        let all = !self.focus.iter().any(|&f| f);
        self.positions
            .iter()
            .enumerate()
            .filter(move |(i, _)| all || self.focus.get(*i).copied().unwrap_or(false))
            .map(|(_, p)| p)
    }
}
