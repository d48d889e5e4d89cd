//! The words and tables of a rig audit (`phalanx audit`, and the report's rig section).
//!
//! Rig coordinates are taken as metres (the glTF unit) and shown in millimetres.

mod compact;
mod explanation;
mod fix;
mod table;
mod words;

pub(crate) use compact::compact;
pub(crate) use fix::{fix_after_words, moved_fingers_words};
pub(crate) use table::{brief, outside_of, text};
pub(crate) use words::{
    caveats, finger_summary, joint_standing, metacarpal_values, unit_words, value_of,
};

/// Millimetres per rig unit (glTF units are metres).
pub(crate) const MM: f64 = 1000.0;
