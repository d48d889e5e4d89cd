//! Recognising finger joints by the names common rigs give them.
//!
//! Names are compared after dropping any namespace (`mixamorig:`, `Armature|`),
//! lower-casing and removing separators, so `mixamorig:RightHandIndex1`,
//! `DEF-f_index.01.R`, `index_01_r`, `rightIndexProximal`, `J_Bip_R_Index1` and
//! `index-finger-phalanx-proximal` all read as a side, a finger and a part.
//!
//! Numbered parts mean the same in Mixamo, Rigify, Unreal, VRoid and Daz: for
//! index to little 1 = MCP, 2 = PIP, 3 = DIP, 4 = tip; for the thumb
//! 1 = CMC (carpometacarpal, not used), 2 = MCP, 3 = IP, 4 = tip. A `_end`,
//! `_nub` or `_leaf` suffix (Blender's leaf bones) is the tail of that bone,
//! the next joint; but a suffix followed by the side (UE5's `index_04_leaf_l`)
//! marks a leaf bone that is itself the numbered part, so `_04_leaf_l` is the
//! tip. Metacarpal bones: `index_metacarpal_r` (UE5), `index-finger-metacarpal`
//! (WebXR), Rigify's `palm.01.R` .. `palm.04.R` (index .. little; its thumb's
//! metacarpal is `thumb.01`). Named parts follow VRM and WebXR: metacarpal, proximal
//! (MCP), intermediate (PIP), distal (DIP), tip; for the thumb VRM 1.0 and
//! WebXR read metacarpal = CMC, proximal = MCP, distal = IP, while VRM 0.x
//! reads proximal = CMC, intermediate = MCP, distal = IP (told apart by whether
//! the thumb has an `intermediate`). Any prefix may come before the side
//! (`Character1_`, `b_`, `Armature/`); a name with a word like MCH, IK, CTRL,
//! target, pole or twist is a control or helper and never a joint.
//!
//! Blender's duplicate names give the first bone of a finger no number
//! (`Index.L`, then `Index.L.001`, `Index.L.002`: a cartoon robot's hand);
//! [`parse_bare`] reads their side and finger, and [`super::recognise`] their
//! part from their place in the chain.
//!
//! Three conventions number their bones otherwise and are read first, on the
//! whole name:
//! - SteamVR (its gloves): `finger_index_meta_r` (the metacarpal), then
//!   `finger_index_0_r` .. `_2_r` counted from 0 (0 = MCP for index to pinky,
//!   0 = CMC for the thumb, as Mixamo's 1) and the tip `finger_index_r_end`.
//! - Oculus / Meta hand tracking: `b_l_index1` .. `3` and `b_r_thumb1` .. `3`
//!   are numbered as Mixamo's (the thumb's 1 is its metacarpal bone, whose
//!   origin is the CMC); the tip is `b_l_index_null` (`_null_end` lies past
//!   it); `b_l_pinky0` is the little finger's metacarpal; `b_l_thumb0` is the
//!   trapezium, a carpal bone whose origin is not a joint of the thumb (its
//!   bind pose puts it 25 mm before the CMC), so it is not read.
//! - Unity's Robot Kyle: `Left_Index_Finger_Joint_01a` .. `01c` (MCP, PIP,
//!   DIP; `01d` a tip) and a two-joint thumb `Left_Thumb_Joint_01a`, `01b`
//!   read as its MCP and IP.
//!
//! Unity's Ethan (`EthanLeftHandIndex1`) and prefix-less Mixamo / HumanIK
//! (`LeftHandIndex1`, Blender's `LeftHandIndex4_end`) read as Mixamo does.
//!
//! The wrist (hand) bone of each convention is read by [`parse_hand`]:
//! Mixamo `mixamorig:RightHand`, Rigify `hand.R` / `DEF-hand.R`, VRM
//! `rightHand`, Unreal `hand_r`, WebXR `wrist`, SteamVR `wrist_r`, Oculus
//! `b_l_wrist`, Robot Kyle `Left_Wrist_Joint_01`; its origin is the wrist joint.

use crate::dataset::Finger;
use regex::Regex;
use std::sync::LazyLock;

/// Which hand (the dataset's side, re-exported where rigs name it).
pub use crate::dataset::landmarks::Side;

/// Which hand a hand of a file is: the side its joint names say (`named`),
/// else the side given (`--side`), else the side its file name says
/// ([`side_from_label`]); `None` when none of them says. The one rule for
/// every command: `deform` curls by it (and refuses a hand it leaves
/// unknown), `audit` states it.
pub fn hand_side(named: Option<Side>, given: Option<Side>, label: &str) -> Option<Side> {
    named.or(given).or_else(|| side_from_label(label))
}

/// `left`/`right` in a file name, when exactly one of them is.
pub fn side_from_label(label: &str) -> Option<Side> {
    let stem = std::path::Path::new(label)
        .file_stem()?
        .to_string_lossy()
        .to_ascii_lowercase();
    match (stem.contains("left"), stem.contains("right")) {
        (true, false) => Some(Side::Left),
        (false, true) => Some(Side::Right),
        _ => None,
    }
}

/// A node name fit for a message or a terminal: quoted, control characters
/// replaced, at most 80 characters.
pub(crate) fn shown(name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| if c.is_control() { '\u{FFFD}' } else { c })
        .collect();
    crate::dataset::csvinput::quote(&clean)
}

/// A joint position along a finger, including the thumb's CMC that is not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum Slot {
    /// Carpometacarpal (or a finger's metacarpal bone): before the root, unused.
    Carpal,
    Mcp,
    /// PIP of a finger, IP of the thumb.
    First,
    /// DIP of a finger.
    Second,
    Tip,
}

/// A part as the name spells it, before the finger decides its meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Part {
    /// Numbered 1..=5 (a suffix like `_end` already added one).
    Number(u8),
    Metacarpal,
    Proximal,
    Intermediate,
    Distal,
    Tip,
}

/// What a name says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Parsed {
    pub side: Option<Side>,
    pub finger: Finger,
    pub part: Part,
    /// A Rigify deform bone (`DEF-`), preferred over its twins.
    pub deform: bool,
}

/// The name pattern, with single-letter sides before the finger allowed or not.
fn pattern(sides: &str) -> Regex {
    Regex::new(&format!(
        r"(?x)^
        (?P<prefix>.*?)
        (?:hand)?
        (?P<s1>{sides})?
        (?:hand)?
        (?:f)?
        (?P<finger>thumb|index|middle|mid|ring|pinky|little)
        (?:finger)?
        (?:phalanx)?
        (?P<part>0?[1-4]|metacarpal|proximal|intermediate|distal|tip)
        (?P<s2>right|left|r|l)?
        (?P<end>end|nub|leaf|tip)?
        (?P<s3>right|left|r|l)?
        $"
    ))
    .expect("the name pattern is valid")
}

static PATTERN: LazyLock<Regex> = LazyLock::new(|| pattern("right|left|r|l"));
static PATTERN_WORDS: LazyLock<Regex> = LazyLock::new(|| pattern("right|left"));

/// Rigify's metacarpals: `palm.01` (index) .. `palm.04` (little).
static PALM: LazyLock<Regex> = LazyLock::new(|| {
    Regex::new(r"^(?P<prefix>.*?)palm0?(?P<n>[1-4])(?P<s2>right|left|r|l)?$")
        .expect("the palm pattern is valid")
});

/// The wrist or hand bone, with single-letter sides before it allowed or not.
fn hand_pattern(sides: &str) -> Regex {
    Regex::new(&format!(
        r"^(?P<prefix>.*?)(?P<s1>{sides})?(?:hand|wrist)(?P<s2>right|left|r|l)?$"
    ))
    .expect("the hand pattern is valid")
}

static HAND: LazyLock<Regex> = LazyLock::new(|| hand_pattern("right|left|r|l"));
static HAND_WORDS: LazyLock<Regex> = LazyLock::new(|| hand_pattern("right|left"));

/// The name compared (namespace dropped, lower case, letters and digits only)
/// and, for each of its characters, the one before it in the name without the
/// namespace (`None` at the start).
fn compact_with_origin(name: &str) -> (String, Vec<Option<char>>) {
    let base = name.rsplit([':', '|']).next().unwrap_or(name);
    let mut out = String::new();
    let mut before = Vec::new();
    let mut prev = None;
    for c in base.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
            before.push(prev);
        }
        prev = Some(c);
    }
    (out, before)
}

/// True when a one-letter side at compact position `i` starts a word of the
/// name: at its start, after a separator, or as a capital after a small letter
/// (`J_Bip_R_Index1`, `b_r_index1`, `bipRIndex`), so `Finger_Index1` has no side.
fn starts_word(name: &str, before: &[Option<char>], i: usize) -> bool {
    let base = name.rsplit([':', '|']).next().unwrap_or(name);
    let this = base.chars().filter(char::is_ascii_alphanumeric).nth(i);
    match (before.get(i).copied().flatten(), this) {
        (None, _) => true,
        (Some(p), _) if !p.is_ascii_alphanumeric() => true,
        (Some(p), Some(c)) => p.is_ascii_lowercase() && c.is_ascii_uppercase(),
        _ => false,
    }
}

/// Words that mark a bone as a control, mechanism or helper rather than a joint
/// of the skin (Rigify's `MCH-`, IK targets, twist helpers).
/// Oculus's `*_marker` nodes (fingertip, pad and axis markers) and SteamVR's `*_aux`
/// bones (at the DIPs, under the root) are helpers too.
const NOT_JOINTS: [&str; 14] = [
    "mch", "ik", "fk", "ctrl", "ctl", "control", "target", "pole", "tweak", "twist", "helper",
    "vis", "marker", "aux",
];

/// Names longer than this are never joint names (and are not run through the pattern).
const MAX_NAME: usize = 256;

/// The name as compared ([`compact_with_origin`]); `None` for a name too long to be a
/// joint's or with a word of a control or helper ([`NOT_JOINTS`]).
fn compared(name: &str) -> Option<(String, Vec<Option<char>>)> {
    if name.len() > MAX_NAME {
        return None;
    }
    let base = name.rsplit([':', '|']).next().unwrap_or(name);
    if base
        .split(|c: char| !c.is_ascii_alphanumeric())
        .any(|w| NOT_JOINTS.contains(&w.to_ascii_lowercase().as_str()))
    {
        return None;
    }
    Some(compact_with_origin(name))
}

/// `pattern`'s match of the compared name `c`; when its side `s1` is one letter that
/// does not start a word of `name` (the `r` of `finger`), `words`' match (sides spelt out).
fn sided_captures<'c>(
    name: &str,
    c: &'c str,
    before: &[Option<char>],
    pattern: &Regex,
    words: &Regex,
) -> Option<regex::Captures<'c>> {
    let m = pattern.captures(c)?;
    match m.name("s1") {
        Some(s1) if s1.len() == 1 && !starts_word(name, before, s1.start()) => words.captures(c),
        _ => Some(m),
    }
}

/// Reads a node name; `None` when it names no finger joint.
pub(crate) fn parse(name: &str) -> Option<Parsed> {
    let (c, before) = compared(name)?;
    if let Some(p) = parse_numbered_otherwise(name) {
        return p;
    }
    if let Some(p) = parse_palm(&c) {
        return Some(p);
    }
    let m = sided_captures(name, &c, &before, &PATTERN, &PATTERN_WORDS)?;
    let side = one_side(&[m.name("s1"), m.name("s2"), m.name("s3")])?;
    let finger = match &m["finger"] {
        "mid" => Finger::Middle,
        f => Finger::parse(f)?,
    };
    // A suffix then the side (UE5's `_04_leaf_l`) is a leaf bone named for
    // its own part; a suffix after the side is the tail of the bone before.
    let end = m.name("end").is_some() && m.name("s3").is_none();
    let part = match &m["part"] {
        "metacarpal" => Part::Metacarpal,
        "proximal" => Part::Proximal,
        "intermediate" => Part::Intermediate,
        "distal" if end => Part::Tip,
        "distal" => Part::Distal,
        "tip" if end => return None,
        "tip" => Part::Tip,
        digits => Part::Number(digits.parse::<u8>().ok()? + u8::from(end)),
    };
    if end && matches!(part, Part::Metacarpal | Part::Proximal | Part::Intermediate) {
        return None;
    }
    Some(Parsed {
        side,
        finger,
        part,
        deform: deform_bone(&m),
    })
}

/// True when the name matched by `m` (the finger pattern or the bare one)
/// begins with Rigify's `DEF` before its finger word: `DEF-f_index.01.R`, and
/// `DEF-thumb.02.R`, whose `f` the pattern's optional `f_` takes from the prefix.
fn deform_bone(m: &regex::Captures<'_>) -> bool {
    m.get(0).is_some_and(|all| all.as_str().starts_with("def"))
        && m.name("finger").is_some_and(|f| f.start() >= 3)
}

/// SteamVR's names (the whole name after any namespace, lower case).
static STEAMVR: LazyLock<Regex> = LazyLock::new(|| {
    Regex::new(
        r"^(?:.*[^a-z0-9])?finger_(?P<finger>thumb|index|middle|ring|pinky)_(?:(?P<part>meta|[0-2])_(?P<s2>[lr])|(?P<s3>[lr])_end)$",
    )
    .expect("the SteamVR pattern is valid")
});

/// Oculus's metacarpal (`0`) and tip (`_null`) names; their `1` .. `3` read as Mixamo's.
static OCULUS: LazyLock<Regex> = LazyLock::new(|| {
    Regex::new(
        r"^(?:.*[^a-z0-9])?b_(?P<s>[lr])_(?P<finger>thumb|index|middle|ring|pinky)(?P<part>0|_null)(?P<end>_end)?$",
    )
    .expect("the Oculus pattern is valid")
});

/// Robot Kyle's lettered joints.
static KYLE: LazyLock<Regex> = LazyLock::new(|| {
    Regex::new(
        r"^(?:.*[^a-z0-9])?(?P<s>left|right)_(?P<finger>thumb|index|middle|ring|pinky)(?:_finger)?_joint_0?1(?P<letter>[a-d])$",
    )
    .expect("the Kyle pattern is valid")
});

/// The name after any namespace (`mixamorig:`, `Armature|`), lower case.
fn base_lower(name: &str) -> String {
    name.rsplit([':', '|'])
        .next()
        .unwrap_or(name)
        .to_ascii_lowercase()
}

/// Reads the conventions that number their bones otherwise than the pattern
/// (see the module doc): `Some(parsed)` when the name is in one of them
/// (`Some(None)`: in one, but not a finger joint, as Oculus's trapezium);
/// `None` when it is in none.
fn parse_numbered_otherwise(name: &str) -> Option<Option<Parsed>> {
    let base = base_lower(name);
    let finger = |f: &str| Finger::parse(f);
    let parsed = |side: &str, f: &str, part: Part| {
        Some(Parsed {
            side: Side::parse(side),
            finger: finger(f)?,
            part,
            deform: false,
        })
    };
    if let Some(m) = STEAMVR.captures(&base) {
        let side = m.name("s2").or(m.name("s3")).map_or("", |s| s.as_str());
        let part = match m.name("part").map(|p| p.as_str()) {
            Some("meta") => Part::Metacarpal,
            Some(d) => Part::Number(d.parse::<u8>().ok()? + 1),
            None => Part::Number(4),
        };
        return Some(parsed(side, &m["finger"], part));
    }
    if let Some(m) = OCULUS.captures(&base) {
        let thumb = &m["finger"] == "thumb";
        let part = match (&m["part"], m.name("end").is_some()) {
            // The trapezium: a carpal bone before the thumb's CMC.
            ("0", _) if thumb => return Some(None),
            ("0", false) => Part::Metacarpal,
            ("_null", false) => Part::Tip,
            _ => return Some(None),
        };
        return Some(parsed(&m["s"], &m["finger"], part));
    }
    if let Some(m) = KYLE.captures(&base) {
        let k = m["letter"].bytes().next()? - b'a';
        // a is the MCP of every digit: a finger's part 1, the thumb's part 2.
        let first = if &m["finger"] == "thumb" { 2 } else { 1 };
        return Some(parsed(&m["s"], &m["finger"], Part::Number(first + k)));
    }
    None
}

/// Robot Kyle's wrist, `Left_Wrist_Joint_01`.
static KYLE_WRIST: LazyLock<Regex> = LazyLock::new(|| {
    Regex::new(r"^(?:.*[^a-z0-9])?(?P<s>left|right)_wrist_joint_0?1$")
        .expect("the Kyle wrist pattern is valid")
});

/// The names that are generic joint names, as Maya gives the joints it creates
/// (`joint1`, `joint21`, `Joint_3`): nothing in them says which finger or joint.
pub(crate) fn generic_joint_names(names: &[String]) -> Vec<String> {
    static GENERIC: LazyLock<Regex> =
        LazyLock::new(|| Regex::new(r"^(?:joint|bone)_?[0-9]+$").expect("the pattern is valid"));
    names
        .iter()
        .filter(|n| GENERIC.is_match(&base_lower(n)))
        .cloned()
        .collect()
}

/// The one side the captured side words name; `Some(None)` when none does,
/// `None` when two disagree.
fn one_side(captures: &[Option<regex::Match<'_>>]) -> Option<Option<Side>> {
    let mut side = None;
    for m in captures.iter().flatten() {
        let s = Side::parse(m.as_str());
        if side.is_some() && s != side {
            return None;
        }
        side = s;
    }
    Some(side)
}

/// Rigify's `palm.0N` metacarpal bones (compact name `c`).
fn parse_palm(c: &str) -> Option<Parsed> {
    let m = PALM.captures(c)?;
    let finger = match &m["n"] {
        "1" => Finger::Index,
        "2" => Finger::Middle,
        "3" => Finger::Ring,
        _ => Finger::Little,
    };
    let prefix = m.name("prefix").map_or("", |p| p.as_str());
    Some(Parsed {
        side: one_side(&[m.name("s2")])?,
        finger,
        part: Part::Metacarpal,
        deform: prefix.starts_with("def"),
    })
}

/// A finger bone named without its part (`Index.L`, `Thumb.L.001`,
/// `IndexFinger.R`): Blender's duplicate names, where the first bone of a
/// finger has no number and the bones extruded from it get `.001`, `.002`.
/// Those numbers are no ordinals (Blender counts on across fingers:
/// `middle.L.004`), so the part is the bone's place in its chain
/// ([`super::recognise`] reads it from the hierarchy). `mid` is not read
/// here (`Spine_Mid`): only whole finger words. Single-letter sides
/// before the finger allowed or not, as in [`pattern`].
fn bare_pattern(sides: &str) -> Regex {
    Regex::new(&format!(
        r"(?x)^
        (?P<prefix>.*?)
        (?:hand)?
        (?P<s1>{sides})?
        (?:hand)?
        (?:f)?
        (?P<finger>thumb|index|middle|ring|pinky|little)
        (?:finger)?
        (?P<s2>right|left|r|l)?
        (?:[0-9]{{1,4}})?
        (?P<end>end|nub|leaf)?
        $"
    ))
    .expect("the bare pattern is valid")
}

static BARE: LazyLock<Regex> = LazyLock::new(|| bare_pattern("right|left|r|l"));
static BARE_WORDS: LazyLock<Regex> = LazyLock::new(|| bare_pattern("right|left"));

/// What a finger bone's name without a part says: side, finger, whether it is
/// a Rigify deform bone, and whether it is a leaf (`_end`: the tail of the bone above).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Bare {
    pub side: Option<Side>,
    pub finger: Finger,
    pub deform: bool,
    pub leaf: bool,
}

/// Reads a name that gives a finger and a side but no part (see [`bare_pattern`]);
/// `None` for names [`parse`] reads, and for controls and helpers.
pub(crate) fn parse_bare(name: &str) -> Option<Bare> {
    if parse(name).is_some() {
        return None;
    }
    let (c, before) = compared(name)?;
    let m = sided_captures(name, &c, &before, &BARE, &BARE_WORDS)?;
    bare_of(&m)
}

/// The [`Bare`] of a match of the bare pattern.
fn bare_of(m: &regex::Captures<'_>) -> Option<Bare> {
    let finger = Finger::parse(&m["finger"])?;
    Some(Bare {
        side: one_side(&[m.name("s1"), m.name("s2")])?,
        finger,
        deform: deform_bone(m),
        leaf: m.name("end").is_some(),
    })
}

/// A wrist or hand bone as its name says: the side and whether it is a
/// Rigify deform bone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HandBone {
    pub side: Option<Side>,
    pub deform: bool,
}

/// Reads a node name as the wrist (hand) bone of a hand; `None` otherwise.
/// The same rules as [`parse`]: namespace dropped, controls and helpers
/// refused, a one-letter side only at the start of a word.
pub fn parse_hand(name: &str) -> Option<HandBone> {
    let (c, before) = compared(name)?;
    if let Some(m) = KYLE_WRIST.captures(&base_lower(name)) {
        return Some(HandBone {
            side: Side::parse(&m["s"]),
            deform: false,
        });
    }
    let m = sided_captures(name, &c, &before, &HAND, &HAND_WORDS)?;
    let prefix = m.name("prefix").map_or("", |p| p.as_str());
    // A prefix that ends in a finger's name is no hand (`RightIndexHand`?):
    // only plain prefixes (namespaces, `def`, `jbip`, `ccbase`) are read.
    if [
        "thumb", "index", "middle", "ring", "pinky", "little", "finger",
    ]
    .iter()
    .any(|f| prefix.contains(f))
    {
        return None;
    }
    Some(HandBone {
        side: one_side(&[m.name("s1"), m.name("s2")])?,
        deform: prefix.starts_with("def"),
    })
}

/// The slot of a part on `finger`; `vrm0_thumb` when the thumb's names follow
/// VRM 0.x (it has an `intermediate`). `None` past the tip.
pub(crate) fn slot(finger: Finger, part: Part, vrm0_thumb: bool) -> Option<Slot> {
    let thumb = finger == Finger::Thumb;
    Some(match part {
        Part::Number(1) if thumb => Slot::Carpal,
        Part::Number(2) if thumb => Slot::Mcp,
        Part::Number(3) if thumb => Slot::First,
        Part::Number(1) => Slot::Mcp,
        Part::Number(2) => Slot::First,
        Part::Number(3) => Slot::Second,
        Part::Number(4) => Slot::Tip,
        Part::Number(_) => return None,
        Part::Metacarpal => Slot::Carpal,
        Part::Proximal if thumb && vrm0_thumb => Slot::Carpal,
        Part::Proximal => Slot::Mcp,
        Part::Intermediate if thumb => Slot::Mcp,
        Part::Intermediate => Slot::First,
        Part::Distal if thumb => Slot::First,
        Part::Distal => Slot::Second,
        Part::Tip => Slot::Tip,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(name: &str) -> Option<(Option<Side>, Finger, Option<Slot>)> {
        let p = parse(name)?;
        Some((p.side, p.finger, slot(p.finger, p.part, false)))
    }

    #[test]
    fn conventions_read_alike() {
        use Finger::*;
        use Side::*;
        let cases: &[(&str, Option<Side>, Finger, Slot)] = &[
            ("mixamorig:RightHandIndex1", Some(Right), Index, Slot::Mcp),
            ("mixamorig1:LeftHandThumb2", Some(Left), Thumb, Slot::Mcp),
            ("mixamorig:RightHandPinky4", Some(Right), Little, Slot::Tip),
            ("DEF-f_index.02.R", Some(Right), Index, Slot::First),
            ("f_ring.03.L", Some(Left), Ring, Slot::Second),
            ("f_ring.03.L_end", Some(Left), Ring, Slot::Tip),
            ("thumb.01.R", Some(Right), Thumb, Slot::Carpal),
            ("thumb.03.R_end", Some(Right), Thumb, Slot::Tip),
            ("index_01_r", Some(Right), Index, Slot::Mcp),
            ("ring_02_l", Some(Left), Ring, Slot::First),
            ("pinky_03_r", Some(Right), Little, Slot::Second),
            ("index_metacarpal_r", Some(Right), Index, Slot::Carpal),
            ("rightIndexProximal", Some(Right), Index, Slot::Mcp),
            ("leftLittleDistal", Some(Left), Little, Slot::Second),
            ("rightThumbProximal", Some(Right), Thumb, Slot::Mcp),
            ("J_Bip_R_Index1", Some(Right), Index, Slot::Mcp),
            ("J_Bip_L_Little3", Some(Left), Little, Slot::Second),
            (
                "index-finger-phalanx-intermediate",
                None,
                Index,
                Slot::First,
            ),
            ("index-finger-tip", None, Index, Slot::Tip),
            ("thumb-phalanx-distal", None, Thumb, Slot::First),
            ("CC_Base_R_Mid2", Some(Right), Middle, Slot::First),
            ("RIGHT_HAND_INDEX_3", Some(Right), Index, Slot::Second),
            ("Character1_RightHandIndex1", Some(Right), Index, Slot::Mcp),
            ("Armature/RightHandIndex1", Some(Right), Index, Slot::Mcp),
            ("Hand_R_Index_01", Some(Right), Index, Slot::Mcp),
            ("hand_l_thumb_2", Some(Left), Thumb, Slot::Mcp),
            ("b_r_index1", Some(Right), Index, Slot::Mcp),
            ("ORG-f_index.01.R", Some(Right), Index, Slot::Mcp),
            ("thumb-metacarpal", None, Thumb, Slot::Carpal),
            ("thumb-phalanx-proximal", None, Thumb, Slot::Mcp),
            ("thumb-tip", None, Thumb, Slot::Tip),
            ("rightThumbMetacarpal", Some(Right), Thumb, Slot::Carpal),
            ("thumb_01_r", Some(Right), Thumb, Slot::Carpal),
            ("thumb_03_l", Some(Left), Thumb, Slot::First),
            ("Left_Hand_Index_1", Some(Left), Index, Slot::Mcp),
        ];
        for &(name, side, finger, slot) in cases {
            assert_eq!(read(name), Some((side, finger, Some(slot))), "{name}");
        }
    }

    #[test]
    fn other_names_are_not_joints() {
        for name in [
            "Hips",
            "RightHand",
            "mixamorig:RightForeArm",
            "index",
            "Ring",
            "rightIndex",
            "MCH-thumb.01.R",
            "MCH-f_index.01.R",
            "IK_RightHandIndex1",
            "index_01_r_twist",
            "Finger_Index1x",
            "f_index.01.R.001x",
            "RightHandIndex1L",
        ] {
            assert_eq!(read(name), None, "{name}");
        }
        // A word ending in r or l before the finger is not a side.
        assert_eq!(
            read("Finger_Index1"),
            Some((None, Finger::Index, Some(Slot::Mcp)))
        );
        assert_eq!(
            read("Bar_Ring2"),
            Some((None, Finger::Ring, Some(Slot::First)))
        );
        assert_eq!(read("bipRIndex1").unwrap().0, Some(Side::Right));
        // Past the tip: Mixamo's leaf after Index4.
        assert_eq!(read("mixamorig:RightHandIndex4_End").unwrap().2, None);
    }

    #[test]
    fn names_without_a_part_read_side_and_finger_only() {
        let bare = |n: &str| parse_bare(n).map(|b| (b.side, b.finger, b.leaf));
        assert_eq!(
            bare("Index.L"),
            Some((Some(Side::Left), Finger::Index, false))
        );
        assert_eq!(
            bare("Thumb.R.001"),
            Some((Some(Side::Right), Finger::Thumb, false))
        );
        assert_eq!(
            bare("IndexFinger.L.002"),
            Some((Some(Side::Left), Finger::Index, false))
        );
        assert_eq!(
            bare("middle.L.004"),
            Some((Some(Side::Left), Finger::Middle, false))
        );
        assert_eq!(
            bare("Pinky.R.002_end"),
            Some((Some(Side::Right), Finger::Little, true))
        );
        assert_eq!(bare("DEF-ring.R").map(|b| b.1), Some(Finger::Ring));
        assert!(parse_bare("DEF-ring.R").unwrap().deform);
        // A numbered name is read by `parse`, never here; controls and words
        // that are not fingers are nothing.
        for no in [
            "Index2.L",
            "mixamorig:RightHandIndex1",
            "MCH-index.L",
            "Index.L_ik",
            "Spine_Mid",
            "Hand.L",
            "Finger.L",
        ] {
            assert_eq!(bare(no), None, "{no}");
        }
        // `Finger` ends in r: no side there.
        assert_eq!(bare("Finger_Index"), Some((None, Finger::Index, false)));
    }

    #[test]
    fn fbx_conventions_read_alike() {
        use Finger::*;
        use Side::*;
        let cases: &[(&str, Option<Side>, Finger, Slot)] = &[
            // SteamVR gloves: counted from 0, `_meta` metacarpals, `_end` tips.
            ("finger_index_meta_r", Some(Right), Index, Slot::Carpal),
            ("finger_index_0_r", Some(Right), Index, Slot::Mcp),
            ("finger_index_1_r", Some(Right), Index, Slot::First),
            ("finger_index_2_r", Some(Right), Index, Slot::Second),
            ("finger_index_r_end", Some(Right), Index, Slot::Tip),
            ("finger_pinky_0_l", Some(Left), Little, Slot::Mcp),
            ("finger_thumb_0_l", Some(Left), Thumb, Slot::Carpal),
            ("finger_thumb_1_l", Some(Left), Thumb, Slot::Mcp),
            ("finger_thumb_2_l", Some(Left), Thumb, Slot::First),
            ("finger_thumb_l_end", Some(Left), Thumb, Slot::Tip),
            // Oculus hand tracking.
            ("b_l_index1", Some(Left), Index, Slot::Mcp),
            ("b_l_index3", Some(Left), Index, Slot::Second),
            ("b_l_index_null", Some(Left), Index, Slot::Tip),
            ("b_r_pinky0", Some(Right), Little, Slot::Carpal),
            ("b_r_pinky1", Some(Right), Little, Slot::Mcp),
            ("b_r_thumb1", Some(Right), Thumb, Slot::Carpal),
            ("b_r_thumb2", Some(Right), Thumb, Slot::Mcp),
            ("b_r_thumb3", Some(Right), Thumb, Slot::First),
            ("b_r_thumb_null", Some(Right), Thumb, Slot::Tip),
            // Unity Standard Assets: Ethan, Robot Kyle.
            ("EthanLeftHandIndex1", Some(Left), Index, Slot::Mcp),
            ("EthanRightHandThumb2", Some(Right), Thumb, Slot::Mcp),
            ("EthanRightHandPinky4", Some(Right), Little, Slot::Tip),
            ("Left_Index_Finger_Joint_01a", Some(Left), Index, Slot::Mcp),
            (
                "Left_Index_Finger_Joint_01c",
                Some(Left),
                Index,
                Slot::Second,
            ),
            (
                "Right_Pinky_Finger_Joint_01b",
                Some(Right),
                Little,
                Slot::First,
            ),
            ("Right_Thumb_Joint_01a", Some(Right), Thumb, Slot::Mcp),
            ("Right_Thumb_Joint_01b", Some(Right), Thumb, Slot::First),
            // Prefix-less Mixamo / HumanIK, with Blender's leaf bones.
            ("LeftHandIndex1", Some(Left), Index, Slot::Mcp),
            ("RightHandThumb1", Some(Right), Thumb, Slot::Carpal),
            ("LeftHandMiddle3_end", Some(Left), Middle, Slot::Tip),
        ];
        for &(name, side, finger, slot) in cases {
            assert_eq!(read(name), Some((side, finger, Some(slot))), "{name}");
        }
        for name in [
            // Oculus: the thumb's trapezium, the leaf past the tip, markers.
            "b_l_thumb0",
            "b_l_pinky_null_end",
            "l_index_finger_tip_marker",
            "l_thumb_knuckle_marker",
            "l_index_mcp_fe_axis_marker",
            // SteamVR's helper bones at the DIPs.
            "finger_index_r_aux",
            "finger_thumb_l_aux",
            // Maya's default names.
            "joint1",
            "joint21",
        ] {
            assert_eq!(read(name), None, "{name}");
        }
        assert_eq!(read("LeftHandIndex4_end").unwrap().2, None);
        for (name, side) in [
            ("wrist_r", Some(Right)),
            ("b_l_wrist", Some(Left)),
            ("Left_Wrist_Joint_01", Some(Left)),
            ("EthanRightHand", Some(Right)),
            ("LeftHand", Some(Left)),
        ] {
            assert_eq!(parse_hand(name).map(|h| h.side), Some(side), "{name}");
        }
        assert_eq!(parse_hand("Left_Wrist_Joint_01b"), None);
        let maya: Vec<String> = ["Hips", "joint1", "Joint_2", "rig:joint21", "jointy"]
            .map(String::from)
            .to_vec();
        assert_eq!(
            generic_joint_names(&maya),
            ["joint1", "Joint_2", "rig:joint21"]
        );
    }

    #[test]
    fn vrm0_thumb_shifts_by_one() {
        let p = parse("rightThumbProximal").unwrap();
        assert_eq!(slot(p.finger, p.part, true), Some(Slot::Carpal));
        let p = parse("rightThumbIntermediate").unwrap();
        assert_eq!(slot(p.finger, p.part, true), Some(Slot::Mcp));
        assert!(parse("DEF-f_middle.01.L").unwrap().deform);
        assert!(parse("DEF-thumb.02.R").unwrap().deform);
        assert!(!parse("f_index.01.R").unwrap().deform);
    }
}
