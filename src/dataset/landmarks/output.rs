//! Imported rows written in the measurement format.
//!
//! Columns, in this order: `xray,finger,j1,j2,j3,mc,sex,age,side,source,unit,tip`: the
//! measurement format's columns with two more, `mc` (the metacarpal, CMC to MCP, in the
//! row's unit; empty when the CMC is not marked) after `j3`, and `tip` (where the
//! fingertips are: `bone`, `skin`, or empty when unknown) at the end. `j3` is empty for the
//! thumb; `sex` and `age` are empty (landmark files do not hold them).
//!
//! Lengths are written by [`crate::format::measured`]: at least 6 decimals and 7 significant digits,
//! trailing zeros dropped. A pixel distance of 339.96000412 px is written `339.960004`: the
//! written value is within 5e-7 of the unit (a millionth of a pixel) for lengths of 1 and
//! over, and within a relative 5e-7 below, far finer than any landmark is clicked.

use super::LandmarkRow;
use crate::dataset::Finger;
use crate::format::measured as length_text;
use std::io::Write;

/// The columns written, in order.
pub const OUTPUT_COLUMNS: [&str; 12] = [
    "xray", "finger", "j1", "j2", "j3", "mc", "sex", "age", "side", "source", "unit", "tip",
];

/// Writes a header and one line per row (CSV, LF line ends, fields quoted where needed).
pub fn write_csv(rows: &[LandmarkRow], out: impl Write) -> std::io::Result<()> {
    let mut w = csv::Writer::from_writer(out);
    w.write_record(OUTPUT_COLUMNS)?;
    for r in rows {
        let opt = |x: Option<&str>| x.unwrap_or("").to_string();
        let j3 = if r.finger == Finger::Thumb {
            String::new()
        } else {
            length_text(r.lengths[2])
        };
        w.write_record([
            r.image.to_string(),
            r.finger.name().to_string(),
            length_text(r.lengths[0]),
            length_text(r.lengths[1]),
            j3,
            r.mc.map_or(String::new(), length_text),
            String::new(),
            String::new(),
            opt(r.side.map(|s| s.name())),
            opt(r.source.as_deref()),
            r.unit.to_string(),
            opt(r.tip.map(|t| t.name())),
        ])?;
    }
    w.flush()
}
