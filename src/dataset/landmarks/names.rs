//! The joints of a hand and the names annotation tools give them.
//!
//! A landmark is the wrist or one joint of one finger. Names are matched case- and
//! separator-insensitively (`INDEX_FINGER_PIP`, `index-pip`, `IndexPip` are one name):
//!
//! - MediaPipe's: `WRIST`, `THUMB_CMC`, `THUMB_MCP`, `THUMB_IP`, `THUMB_TIP`,
//!   `INDEX_FINGER_MCP` .. `INDEX_FINGER_TIP`, `MIDDLE_FINGER_*`, `RING_FINGER_*`, `PINKY_*`;
//! - plain ones: a finger (`thumb`, `index`, `middle`, `ring`, `little`, with the aliases of
//!   [`Finger::parse`]), an optional word `finger`, and a joint (`cmc`, `mcp`, `pip`, `dip`,
//!   `tip`; the thumb's are `cmc`, `mcp`, `ip`, `tip`): `index_pip`, `little_tip`, `thumb_ip`;
//! - numbered ones, as MMPose's 21-point hands name them: `thumb1` .. `thumb4` (CMC, MCP, IP,
//!   tip) and `forefinger1` .. `pinky_finger4` (MCP, PIP, DIP, tip).

use crate::dataset::Finger;
use std::fmt;

/// A joint of a finger, from the wrist outwards.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Joint {
    /// Carpometacarpal joint: the base of the metacarpal.
    Cmc,
    /// Metacarpophalangeal joint.
    Mcp,
    /// Proximal interphalangeal joint (not the thumb's).
    Pip,
    /// Distal interphalangeal joint (not the thumb's).
    Dip,
    /// The thumb's interphalangeal joint.
    Ip,
    /// The tip of the distal phalanx.
    Tip,
}

impl Joint {
    /// Upper-case abbreviation, or `tip`, as messages name it.
    pub fn name(self) -> &'static str {
        match self {
            Joint::Cmc => "CMC",
            Joint::Mcp => "MCP",
            Joint::Pip => "PIP",
            Joint::Dip => "DIP",
            Joint::Ip => "IP",
            Joint::Tip => "tip",
        }
    }

    fn plain(self) -> &'static str {
        match self {
            Joint::Cmc => "cmc",
            Joint::Mcp => "mcp",
            Joint::Pip => "pip",
            Joint::Dip => "dip",
            Joint::Ip => "ip",
            Joint::Tip => "tip",
        }
    }
}

/// The joints of a finger in order from the wrist: CMC, MCP, PIP, DIP, tip, or for the
/// thumb CMC, MCP, IP, tip. J_k runs from joint k to joint k + 1 counting from the MCP;
/// the metacarpal from the CMC to the MCP.
pub fn chain(finger: Finger) -> &'static [Joint] {
    match finger {
        Finger::Thumb => &[Joint::Cmc, Joint::Mcp, Joint::Ip, Joint::Tip],
        _ => &[Joint::Cmc, Joint::Mcp, Joint::Pip, Joint::Dip, Joint::Tip],
    }
}

/// One landmark of a hand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Landmark {
    /// The wrist (read and checked, but no length uses it).
    Wrist,
    /// A joint of a finger; the joint is always one of [`chain`]`(finger)`.
    Joint(Finger, Joint),
}

impl Landmark {
    /// The plain name: `wrist`, `index_pip`, `thumb_ip`, `little_tip`.
    pub fn plain_name(self) -> String {
        match self {
            Landmark::Wrist => "wrist".into(),
            Landmark::Joint(f, j) => format!("{}_{}", f.name(), j.plain()),
        }
    }

    /// The position of a joint in its finger's [`chain`]; `None` for the wrist.
    pub fn slot(self) -> Option<(Finger, usize)> {
        match self {
            Landmark::Wrist => None,
            Landmark::Joint(f, j) => chain(f).iter().position(|&c| c == j).map(|s| (f, s)),
        }
    }
}

impl fmt::Display for Landmark {
    /// "wrist", "index PIP", "thumb tip".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Landmark::Wrist => f.write_str("wrist"),
            Landmark::Joint(finger, joint) => write!(f, "{} {}", finger.name(), joint.name()),
        }
    }
}

/// The standard 21-point hand, in MediaPipe's order: wrist; thumb CMC, MCP, IP, tip; then
/// MCP, PIP, DIP, tip of the index, middle, ring and little finger. The order of COCO hand
/// keypoints that carry no names (COCO-WholeBody's `lefthand_kpts`, `righthand_kpts`).
pub const STANDARD_21: [Landmark; 21] = {
    use Finger::*;
    use Joint::*;
    use Landmark::Joint as J;
    [
        Landmark::Wrist,
        J(Thumb, Cmc),
        J(Thumb, Mcp),
        J(Thumb, Ip),
        J(Thumb, Tip),
        J(Index, Mcp),
        J(Index, Pip),
        J(Index, Dip),
        J(Index, Tip),
        J(Middle, Mcp),
        J(Middle, Pip),
        J(Middle, Dip),
        J(Middle, Tip),
        J(Ring, Mcp),
        J(Ring, Pip),
        J(Ring, Dip),
        J(Ring, Tip),
        J(Little, Mcp),
        J(Little, Pip),
        J(Little, Dip),
        J(Little, Tip),
    ]
};

/// The names accepted, for error messages.
pub const ACCEPTED: &str = "MediaPipe's (WRIST, THUMB_CMC, THUMB_IP, INDEX_FINGER_PIP, PINKY_TIP, ...) or plain ones (wrist, thumb_cmc, thumb_ip, index_pip, little_tip, ...), any case and separators";

/// Parses a landmark name (see the module documentation); `None` when it names no landmark.
pub fn parse(name: &str) -> Option<Landmark> {
    let key: String = name
        .chars()
        .filter(|c| c.is_alphanumeric())
        .flat_map(char::to_lowercase)
        .collect();
    if key == "wrist" {
        return Some(Landmark::Wrist);
    }
    // Numbered joints: thumb1..4 = CMC, MCP, IP, tip; finger1..4 = MCP, PIP, DIP, tip.
    if let Some(last) = key.chars().last().and_then(|c| c.to_digit(10)) {
        let finger = finger_of(&key[..key.len() - 1])?;
        let k = usize::try_from(last).ok()?.checked_sub(1)?;
        let joints = chain(finger);
        let skip = usize::from(finger != Finger::Thumb);
        return joints.get(k + skip).map(|&j| Landmark::Joint(finger, j));
    }
    // Longer suffixes first: "tip", "pip" and "dip" all end in "ip".
    const SUFFIXES: [(&str, Joint); 6] = [
        ("cmc", Joint::Cmc),
        ("mcp", Joint::Mcp),
        ("pip", Joint::Pip),
        ("dip", Joint::Dip),
        ("tip", Joint::Tip),
        ("ip", Joint::Ip),
    ];
    let (rest, joint) = SUFFIXES
        .iter()
        .find_map(|&(s, j)| key.strip_suffix(s).map(|rest| (rest, j)))?;
    let finger = finger_of(rest)?;
    chain(finger)
        .contains(&joint)
        .then_some(Landmark::Joint(finger, joint))
}

/// A finger name with an optional trailing word "finger" ("indexfinger", "forefinger").
fn finger_of(text: &str) -> Option<Finger> {
    Finger::parse(text).or_else(|| Finger::parse(text.strip_suffix("finger")?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use Finger::*;

    fn j(f: Finger, j: Joint) -> Option<Landmark> {
        Some(Landmark::Joint(f, j))
    }

    #[test]
    fn mediapipe_plain_and_numbered_names() {
        assert_eq!(parse("WRIST"), Some(Landmark::Wrist));
        assert_eq!(parse("THUMB_CMC"), j(Thumb, Joint::Cmc));
        assert_eq!(parse("THUMB_IP"), j(Thumb, Joint::Ip));
        assert_eq!(parse("THUMB_TIP"), j(Thumb, Joint::Tip));
        assert_eq!(parse("INDEX_FINGER_PIP"), j(Index, Joint::Pip));
        assert_eq!(parse("MIDDLE_FINGER_DIP"), j(Middle, Joint::Dip));
        assert_eq!(parse("RING_FINGER_MCP"), j(Ring, Joint::Mcp));
        assert_eq!(parse("PINKY_TIP"), j(Little, Joint::Tip));
        assert_eq!(parse("index_pip"), j(Index, Joint::Pip));
        assert_eq!(parse("Little-Tip"), j(Little, Joint::Tip));
        assert_eq!(parse("thumb ip"), j(Thumb, Joint::Ip));
        assert_eq!(parse("IndexPip"), j(Index, Joint::Pip));
        assert_eq!(parse("grooming.dip"), j(Index, Joint::Dip));
        assert_eq!(parse("index_cmc"), j(Index, Joint::Cmc));
        assert_eq!(parse("thumb1"), j(Thumb, Joint::Cmc));
        assert_eq!(parse("thumb4"), j(Thumb, Joint::Tip));
        assert_eq!(parse("forefinger1"), j(Index, Joint::Mcp));
        assert_eq!(parse("middle_finger3"), j(Middle, Joint::Dip));
        assert_eq!(parse("pinky_finger4"), j(Little, Joint::Tip));
    }

    #[test]
    fn names_that_are_no_landmark() {
        for bad in [
            "",
            "nose",
            "index",
            "thumb_pip",
            "thumb_dip",
            "index_ip",
            "toe_tip",
            "thumb5",
            "index0",
            "index_finger",
            "tip",
            "wrist2",
        ] {
            assert_eq!(parse(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn standard_order_round_trips_through_plain_names() {
        for (k, l) in STANDARD_21.iter().enumerate() {
            assert_eq!(parse(&l.plain_name()), Some(*l), "keypoint {k}");
        }
        assert_eq!(STANDARD_21[6].to_string(), "index PIP");
        assert_eq!(STANDARD_21[20].plain_name(), "little_tip");
        assert_eq!(STANDARD_21[3].slot(), Some((Thumb, 2)));
        assert_eq!(STANDARD_21[8].slot(), Some((Index, 4)));
        assert_eq!(Landmark::Wrist.slot(), None);
    }
}
