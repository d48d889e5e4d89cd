//! Flat-shaded pictures of posed meshes, coloured by strain, as PNG.
//!
//! Orthographic views in the hand's own frame ([`View::side`] looks along the
//! flexion axes from the little finger's side, so curled fingers show their
//! profile; [`View::above`] looks at the back of the hand). A left hand's
//! views are the mirror images of a right hand's. A [`Figure`] is a grid: one row per view, one
//! column per mesh (rig A, rig B), every panel of a row at one scale so the
//! rigs compare at sight, each centred on its own mesh; a strain colour ramp
//! runs along the bottom.
//!
//! Drawing: the painter's algorithm (triangles sorted by the depth of their
//! centroid, farthest first, with `total_cmp` and the triangle index breaking
//! ties), each filled with one colour: the strain ramp ([`strain_colour`]) of
//! the mean strain of its three vertices, times Lambert shading
//! 0.35 + 0.65 |n . l| with n the triangle's normal and l a light from the
//! viewer's upper left (two-sided: a mesh's winding is not trusted). tiny-skia
//! fills without anti-aliasing (anti-aliased neighbours leave hairline seams)
//! at twice the size, and the image is averaged down 2 x 2, which smooths the
//! edges. Everything is integer or f32 arithmetic in a fixed order, and the
//! PNG encoder has fixed settings: the same input gives the same bytes.

mod camera;
mod figure;
mod marked;
mod raster;
#[cfg(test)]
mod tests;

pub use camera::{Camera, MeshView, View};
pub use figure::{FONT_FILE, Figure, LABELS, LEGEND, SCALE_CAPTION, SCALE_TICKS};
pub use marked::{FINGER_COLOURS, KEY, Marked, MarkedChain};
pub use raster::{RAMP_MAX, strain_colour};
