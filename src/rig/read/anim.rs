//! Animation channels of a rig, read from the file's JSON rather than
//! through the gltf crate (whose `Target::property` panics on a path it does
//! not know: a misspelt `rottaion`, or KHR_animation_pointer's `pointer`).
//! Such channels are reported and left alone.

use super::naming::shown;
use serde_json::Value;
use std::collections::BTreeMap;

/// The four paths glTF 2.0 animates.
const PATHS: [&str; 4] = ["translation", "rotation", "scale", "weights"];

/// One channel as the JSON has it.
#[derive(Debug, Clone)]
pub struct Channel {
    pub animation: usize,
    pub channel: usize,
    pub sampler: Option<usize>,
    pub node: Option<usize>,
    pub path: Option<String>,
}

/// The name of animation `a` for messages.
pub(crate) fn animation_name(json: &Value, a: usize) -> String {
    json["animations"][a]["name"]
        .as_str()
        .map_or_else(|| format!("#{a}"), shown)
}

/// Every channel of every animation. O(channels).
pub fn channels(json: &Value) -> Vec<Channel> {
    let mut out = Vec::new();
    for (a, anim) in json["animations"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        for (c, ch) in anim["channels"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            out.push(Channel {
                animation: a,
                channel: c,
                sampler: ch["sampler"].as_u64().map(|s| s as usize),
                node: ch["target"]["node"].as_u64().map(|n| n as usize),
                path: ch["target"]["path"].as_str().map(str::to_string),
            });
        }
    }
    out
}

/// True when a channel names a node and a path glTF 2.0 knows: the gltf
/// crate may read it.
pub fn is_plain(ch: &Value) -> bool {
    ch["target"]["node"].is_u64()
        && ch["target"]["path"]
            .as_str()
            .is_some_and(|p| PATHS.contains(&p))
}

/// One remark per animation with channels the audit leaves alone: unknown
/// paths (misspelt, or an extension's such as KHR_animation_pointer).
pub fn unknown_paths(json: &Value) -> Vec<String> {
    let mut by_anim: BTreeMap<usize, Vec<String>> = BTreeMap::new();
    for ch in channels(json) {
        let known = ch.path.as_deref().is_some_and(|p| PATHS.contains(&p));
        if !known || ch.node.is_none() {
            let what = match ch.path.as_deref() {
                Some("pointer") => format!("channel {} (KHR_animation_pointer)", ch.channel),
                Some(p) => format!("channel {} (path {})", ch.channel, shown(p)),
                None => format!("channel {} (no path)", ch.channel),
            };
            by_anim.entry(ch.animation).or_default().push(what);
        }
    }
    by_anim
        .into_iter()
        .map(|(a, list)| {
            format!(
                "animation {}: {} target no node path glTF 2.0 defines (translation, rotation, \
                 scale, weights); left alone: if one animates a moved joint, re-bake it",
                animation_name(json, a),
                list.join(", ")
            )
        })
        .collect()
}
