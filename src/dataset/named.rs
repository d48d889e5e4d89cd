//! Values of a closed set written by name, in JSON as in data files: one serde and JSON
//! Schema implementation for them all ([`serde_by_name`]).

/// Implements `Serialize`, `JsonSchema` and `Deserialize` for `$ty`, a closed set of values
/// with `ALL`, `name(self) -> &'static str` and `parse(&str) -> Option<Self>`:
///
/// - `Serialize` writes the value's `name()`;
/// - `JsonSchema` is a string, one of the `name()`s of `ALL`, described by `$description`;
/// - `Deserialize` reads a name `parse` accepts, else fails with "unknown `$kind` 'TEXT',
///   expected one of `$expected`" (`$expected` is evaluated only then).
macro_rules! serde_by_name {
    ($ty:ident, $kind:literal, $description:literal, $expected:expr) => {
        impl ::serde::Serialize for $ty {
            /// The value's name.
            fn serialize<S: ::serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }

        impl ::schemars::JsonSchema for $ty {
            fn schema_name() -> ::std::borrow::Cow<'static, str> {
                stringify!($ty).into()
            }

            /// The names `serialize` writes: the name of each value.
            fn json_schema(_: &mut ::schemars::SchemaGenerator) -> ::schemars::Schema {
                ::schemars::json_schema!({
                    "description": $description,
                    "type": "string",
                    "enum": $ty::ALL.map($ty::name),
                })
            }
        }

        impl<'de> ::serde::Deserialize<'de> for $ty {
            /// Reads a name `parse` accepts (phalanx writes `name`).
            fn deserialize<D: ::serde::Deserializer<'de>>(d: D) -> Result<$ty, D::Error> {
                let text = <String as ::serde::Deserialize>::deserialize(d)?;
                $ty::parse(&text).ok_or_else(|| {
                    <D::Error as ::serde::de::Error>::custom(format!(
                        "unknown {} '{text}', expected one of {}",
                        $kind, $expected
                    ))
                })
            }
        }
    };
}
pub(crate) use serde_by_name;
