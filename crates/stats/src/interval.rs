//! A closed interval of real numbers.

use schemars::{JsonSchema, Schema, SchemaGenerator};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::borrow::Cow;

/// A closed interval `[low, high]`; serialised as a two-element array.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub low: f64,
    pub high: f64,
}

impl Interval {
    pub fn new(low: f64, high: f64) -> Interval {
        Interval { low, high }
    }

    /// A zero-width interval at `x`.
    pub fn point(x: f64) -> Interval {
        Interval { low: x, high: x }
    }

    /// high - low.
    pub fn width(&self) -> f64 {
        self.high - self.low
    }

    /// True when `low <= x <= high`.
    pub fn contains(&self, x: f64) -> bool {
        self.low <= x && x <= self.high
    }

    /// The interval multiplied by a non-negative factor.
    pub fn scaled(&self, k: f64) -> Interval {
        Interval::new(self.low * k, self.high * k)
    }
}

impl Serialize for Interval {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        [self.low, self.high].serialize(s)
    }
}

impl JsonSchema for Interval {
    fn schema_name() -> Cow<'static, str> {
        "Interval".into()
    }

    /// The schema of what [`Interval::serialize`] writes: `[low, high]`.
    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        let mut schema = <[f64; 2]>::json_schema(generator);
        schema.insert(
            "description".into(),
            "A closed interval [low, high].".into(),
        );
        schema
    }
}

impl<'de> Deserialize<'de> for Interval {
    /// Reads `[low, high]`, as written by [`Interval::serialize`].
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Interval, D::Error> {
        let [low, high] = <[f64; 2]>::deserialize(d)?;
        Ok(Interval { low, high })
    }
}
