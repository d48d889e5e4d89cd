//! Section 13, popular rigs against the X-rays: each reference rig's fingers judged.

use super::inputs::ReferenceAudit;
use crate::analysis::Quantity;
use crate::format::num;
use serde::Serialize;

/// The section "Popular rigs against the X-rays".
#[derive(Debug, Clone, Serialize)]
pub struct RigsView {
    pub rigs: Vec<RigView>,
    pub caveats: Vec<String>,
}

/// One reference rig.
#[derive(Debug, Clone, Serialize)]
pub struct RigView {
    pub id: String,
    pub name: String,
    pub source: String,
    pub url: String,
    pub notes: String,
    /// "2 of 5 judged fingers outside the 95% joint region", ...
    pub summary: String,
    pub fingers: Vec<RigFingerView>,
}

/// One finger of a reference rig.
#[derive(Debug, Clone, Serialize)]
pub struct RigFingerView {
    pub finger: String,
    /// J~1 / J~2 / J~3 (or "no tip").
    pub relative: String,
    pub ratio_j2_j1: String,
    pub ratio_j3_j2: String,
    /// One phrase, naming whatever lies outside the prediction interval.
    pub standing: String,
}

/// The section on reference rigs, judged against the data at `data` (its path).
pub(crate) fn rigs_view(rigs: &[ReferenceAudit], data: &str, confidence: f64) -> Option<RigsView> {
    use crate::report::audit::{finger_summary, value_of};
    use crate::rig::judge::Basis;
    let first = rigs.first()?;
    let views = rigs
        .iter()
        .map(|r| {
            let judged = r
                .audit
                .fingers
                .iter()
                .filter(|f| f.audit.basis != Basis::None)
                .count();
            let fingers = r
                .audit
                .fingers
                .iter()
                .map(|f| {
                    let a = &f.audit;
                    let rel: Vec<String> = [Quantity::RelJ1, Quantity::RelJ2, Quantity::RelJ3]
                        .iter()
                        .filter_map(|&q| value_of(a, q).map(|v| num(v, 4)))
                        .collect();
                    let ratio = |q| value_of(a, q).map_or("n/a".to_string(), |v| num(v, 4));
                    RigFingerView {
                        finger: f.chain.finger.name().to_string(),
                        relative: if rel.is_empty() {
                            "n/a (no tip)".into()
                        } else {
                            rel.join(" / ")
                        },
                        ratio_j2_j1: ratio(Quantity::RatioJ2J1),
                        ratio_j3_j2: ratio(Quantity::RatioJ3J2),
                        standing: finger_summary(a),
                    }
                })
                .collect();
            RigView {
                id: r.rig.id.clone(),
                name: r.rig.name.clone(),
                source: r.rig.source.clone(),
                url: r.rig.url.clone(),
                notes: std::iter::once(r.rig.notes.clone())
                    .chain(r.audit.notes.iter().cloned())
                    .filter(|n| !n.is_empty())
                    .collect::<Vec<_>>()
                    .join(" "),
                summary: format!(
                    "{} of {judged} judged fingers outside {}",
                    r.audit.outside(),
                    crate::report::audit::outside_of(&r.audit, confidence)
                ),
                fingers,
            }
        })
        .collect();
    Some(RigsView {
        rigs: views,
        caveats: crate::report::audit::caveats(&first.audit.tips, data),
    })
}
