//! Making a rig's fingers from its skin and the statistics: [`place`] puts
//! each finger's joints on the axis `find` traced (the paper's rule), and
//! the rest (the skin's weights, the written nodes) follows. Uses `read`,
//! `find`, `judge` (its chain geometry) and `fix` (the one glTF writer).

pub mod names;
pub mod place;
pub mod weights;
