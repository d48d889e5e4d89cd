//! What `phalanx deform` shows: the measures table (one rig, or two side by
//! side with a verdict per joint), the figures (PNG, both rigs posed, from the
//! side and from above, coloured by strain) and the JSON document.
//!
//! Rig coordinates are metres (the glTF unit), shown in millimetres; volume
//! loss as a percentage of the rest cross-section; strain as |ln(posed / rest
//! edge length)|, unitless.

mod figures;
mod section;
mod text;

pub(crate) use figures::{figure, figure_file, figures, label_font};
pub(crate) use section::{SectionInputs, section};
pub(crate) use text::{
    CAVEATS, DeformDocument, HandVerdicts, RigView, json, pose_line, text_one, text_two,
};
