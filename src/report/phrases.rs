//! Sentences shared by the terminal ([`super::text`]) and the report ([`super::view`]).

use crate::analysis::{Analysis, Quantity};
use crate::dataset::history::Snapshot;

/// What a dataset whose rows are in several units means for its statistics, when it is:
/// the rows per unit, that relative values and ratios pool, and which fingers lose their
/// total J.
pub fn units_note(a: &Analysis) -> Option<String> {
    if !a.mixed_units() {
        return None;
    }
    let units: Vec<String> = a
        .units
        .iter()
        .map(|(u, n)| {
            format!(
                "{} ({n} row{})",
                u.as_deref().map_or("no unit named", |u| u),
                if *n == 1 { "" } else { "s" }
            )
        })
        .collect();
    let without: Vec<&str> = a
        .fingers
        .iter()
        .filter(|f| f.quantity(Quantity::Total).is_none())
        .map(|f| f.finger.name())
        .collect();
    Some(format!(
        "the rows give their lengths in {} units: {}. The relative values and ratios have no unit and pool across them; lengths in different units are never averaged, so the total length J is left out for {} (measured in more than one unit). For J in one unit, run phalanx on a file of that unit's rows",
        a.units.len(),
        units.join(", "),
        if without.is_empty() {
            "no finger".to_string()
        } else {
            without.join(", ")
        }
    ))
}

/// What one history record changed, in words: the rows and X-rays added or removed, the
/// file, the rows let in flagged, the note. Empty for a snapshot without a note.
pub(crate) fn record_change(s: &Snapshot) -> String {
    let mut parts: Vec<String> = Vec::new();
    if let Some(c) = &s.change {
        let ids = if c.xrays.len() <= 4 {
            c.xrays.join(", ")
        } else {
            format!(
                "{} ... {}",
                c.xrays[..2].join(", "),
                c.xrays[c.xrays.len() - 1]
            )
        };
        let sign = match s.event {
            crate::dataset::history::Event::Remove => "-",
            _ => "+",
        };
        let of = match c.xrays.len() {
            1 => format!("X-ray {ids}"),
            n => format!("{n} X-rays: {ids}"),
        };
        let what = format!(
            "{sign}{} row{} ({of})",
            c.rows,
            if c.rows == 1 { "" } else { "s" }
        );
        parts.push(match (&c.file, s.event) {
            (Some(f), _) => format!("{what} from {f}"),
            (None, crate::dataset::history::Event::Remove) => what,
            (None, _) => format!("{what} typed as options"),
        });
        if !c.flagged.is_empty() {
            let rows: Vec<String> = c
                .flagged
                .iter()
                .map(|f| format!("{} {}", f.xray, f.finger.name()))
                .collect();
            parts.push(match s.event {
                crate::dataset::history::Event::Remove => {
                    format!("had been added flagged: {}", rows.join(", "))
                }
                _ => format!("added though flagged: {}", rows.join(", ")),
            });
        }
    }
    if let Some(n) = &s.note {
        parts.push(format!("note: {n}"));
    }
    parts.join("; ")
}
