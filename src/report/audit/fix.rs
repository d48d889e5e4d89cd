//! What `audit --fix` moved, and how the fingers stand after it.

use super::MM;
use super::words::*;
use crate::format::num;

/// Each moved finger's T^2 against its bound, judged again `when` ("after
/// the fix"): "; each moved finger after the fix: right index T^2 1.2 of 25.5
/// (0.05), right ring T^2 30.1 of 25.5 (1.18, outside)"; empty for none.
pub(crate) fn moved_fingers_words(
    fingers: &[crate::rig::session::MovedFinger],
    when: &str,
) -> String {
    if fingers.is_empty() {
        return String::new();
    }
    let each: Vec<String> = fingers
        .iter()
        .map(|f| match f.t2 {
            Some((t2, bound)) => format!(
                "{} T^2 {} of {} ({}{})",
                f.label,
                num(t2, 1),
                num(bound, 1),
                num(t2 / bound, 2),
                if f.inside { "" } else { ", outside" }
            ),
            None => format!(
                "{} {}",
                f.label,
                if f.inside { "inside" } else { "outside" }
            ),
        })
        .collect();
    format!("; each moved finger {when}: {}", each.join(", "))
}

/// What the result line of `audit --fix` adds after its counts: each moved
/// finger's T^2 against its bound in the re-audit ("; each moved finger
/// after the fix: right index T^2 1.2 of 25.5 (0.05)"), every moved joint's
/// distance to where its skin bends before and after ("right index PIP 0.2
/// mm -> 0.4 mm"), and any bend defect the re-audit flags that the rig as
/// given did not have.
pub(crate) fn fix_after_words(fix: &crate::rig::session::FixOutcome) -> String {
    let mm = |d: Option<f64>| {
        d.map_or("not found".to_string(), |x| {
            format!("{} mm", num(x * MM, 1))
        })
    };
    let mut out = moved_fingers_words(&fix.fingers, "after the fix");
    if !fix.bends.is_empty() {
        let each: Vec<String> = fix
            .bends
            .iter()
            .map(|b| {
                let carried = match b.reweighted {
                    0 => String::new(),
                    n => format!(" ({n} vertices reweighted)"),
                };
                format!("{} {} -> {}{carried}", b.joint, mm(b.before), mm(b.after))
            })
            .collect();
        out.push_str(&format!(
            "; each moved joint's distance to where its skin bends, before -> after: {}",
            each.join(", ")
        ));
    }
    if fix.new_defects.is_empty() {
        out.push_str("; no new bend defect");
    } else {
        out.push_str(&format!(
            "; new bend defects the original did not have: {} (further than the bend tolerance \
             from where their skin bends)",
            and_list(&fix.new_defects)
        ));
    }
    out
}
