//! Fieldless enums chosen by name (a spec value, a command-line flag): one table of names gives
//! `NAMES`, `name`, [`std::str::FromStr`] and [`std::fmt::Display`], so the binary's flag
//! parsers and the library agree on the spelling without the library knowing about clap.

/// The error of parsing a name that is not one of the choices.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("`{given}`: expected one of {}", expected.join(", "))]
pub struct UnknownChoice {
    /// The text given.
    pub given: String,
    /// The names accepted.
    pub expected: &'static [&'static str],
}

/// Implements the named-choice items for a fieldless enum: `$ty::NAMES` (in declaration
/// order), `$ty::name`, `FromStr` (exact names, surrounding blanks ignored) and `Display`.
macro_rules! named_choices {
    ($ty:ident { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            /// The name of this choice (in specs, on the command line, in output).
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::choice::UnknownChoice;

            fn from_str(s: &str) -> Result<Self, Self::Err> {
                match s.trim() {
                    $($name => Ok($ty::$variant),)+
                    _ => Err($crate::choice::UnknownChoice {
                        given: s.to_string(),
                        expected: $ty::NAMES,
                    }),
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

pub(crate) use named_choices;

#[cfg(test)]
mod tests {
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    enum Shade {
        Light,
        Dark,
    }
    named_choices!(Shade { Light => "light", Dark => "dark" });

    #[test]
    fn names_round_trip_and_unknown_names_list_the_choices() {
        for name in Shade::NAMES {
            let s: Shade = name.parse().unwrap();
            assert_eq!(s.to_string(), *name);
        }
        assert_eq!(" dark ".parse::<Shade>(), Ok(Shade::Dark));
        let e = "grey".parse::<Shade>().unwrap_err().to_string();
        assert_eq!(e, "`grey`: expected one of light, dark");
    }
}
