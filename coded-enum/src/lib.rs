// SPDX-License-Identifier: MIT OR Apache-2.0
//! Enums over wire integers with an `Unknown` catch-all: one macro, [`coded_enum!`], for
//! every codec of the workspace (PROFINET's block types, frame IDs and codes, the GS20-PN
//! host link's frame codes, AgentX's PDU types and errors), so that parsing never fails on a
//! value without a name and every raw value emits back as it came.
#![no_std]

/// Defines a `Copy` enum over a wire integer with an `Unknown` catch-all, so that parsing
/// never fails on a value the enum does not name and every raw value round-trips.
///
/// Generates the enum (each variant with its doc comment, value and readable text), the
/// conversions both ways as `From` and as `const fn`s (`from_raw`, `raw`) for `const`
/// contexts and sub-byte fields, and `name()` with the readable text of the known values.
/// Extra attributes before `pub enum` (docs, further derives) go onto the enum; it always
/// derives `Clone, Copy, Debug, PartialEq, Eq, Hash`. With `display "FORMAT"` after the wire
/// type, it also implements `Display`: the readable text of a known value, FORMAT with the
/// raw value for an unknown one.
#[macro_export]
macro_rules! coded_enum {
    (
        $(#[$m:meta])*
        pub enum $name:ident($ty:ty) display $unknown:literal { $($body:tt)+ }
    ) => {
        $crate::coded_enum! { $(#[$m])* pub enum $name($ty) { $($body)+ } }

        impl core::fmt::Display for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                match self.name() {
                    Some(name) => f.write_str(name),
                    None => write!(f, $unknown, self.raw()),
                }
            }
        }
    };
    (
        $(#[$m:meta])*
        pub enum $name:ident($ty:ty) {
            $( $(#[$vm:meta])* $var:ident = $val:literal => $text:literal, )+
        }
    ) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum $name {
            $( $(#[$vm])* $var, )+
            /// Any other value (never one of the above).
            Unknown($ty),
        }

        impl $name {
            /// The variant of a raw wire value (`Unknown` for values without a name).
            pub const fn from_raw(v: $ty) -> $name {
                match v {
                    $( $val => $name::$var, )+
                    other => $name::Unknown(other),
                }
            }

            /// The raw wire value.
            pub const fn raw(self) -> $ty {
                match self {
                    $( $name::$var => $val, )+
                    $name::Unknown(other) => other,
                }
            }

            /// The readable text of a known value; `None` for `Unknown`.
            pub const fn name(self) -> Option<&'static str> {
                match self {
                    $( $name::$var => Some($text), )+
                    $name::Unknown(_) => None,
                }
            }
        }

        impl From<$ty> for $name {
            fn from(v: $ty) -> $name {
                $name::from_raw(v)
            }
        }

        impl From<$name> for $ty {
            fn from(v: $name) -> $ty {
                v.raw()
            }
        }
    };
}

#[cfg(test)]
mod tests {
    coded_enum! {
        /// A test code.
        pub enum Colour(u8) display "colour {}" {
            /// Red.
            Red = 1 => "red",
            /// Green.
            Green = 2 => "green",
        }
    }

    #[test]
    fn every_raw_value_round_trips() {
        for v in 0..=u8::MAX {
            assert_eq!(Colour::from_raw(v).raw(), v);
            assert_eq!(u8::from(Colour::from(v)), v);
        }
        assert_eq!(Colour::from_raw(2), Colour::Green);
        assert_eq!(Colour::Green.name(), Some("green"));
        assert_eq!(Colour::Unknown(9).name(), None);
    }
}
