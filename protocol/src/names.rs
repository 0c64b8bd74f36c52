//! The words enums of the wire formats are written as in files and on the command line.
//!
//! The raster file parser, `fpgfx`'s flags and the tools' reports all go through
//! [`Named`], so a value is spelled the same way everywhere and a misspelling is answered
//! with the same list of choices. [`named!`](crate::named) writes an enum's table once and
//! derives the rest from it (`Display`, `FromStr`, and with the `clap` feature the flags'
//! possible values), for this crate's enums and for other crates' alike.

use core::fmt;
use core::marker::PhantomData;

/// An enum whose values are written as fixed words.
pub trait Named: Copy + 'static {
    /// What a value is, for messages ("number format").
    const WHAT: &'static str;
    /// Every value, in the order the words are listed in messages and help.
    const VALUES: &'static [Self];
    /// Whether a word matches whatever its ASCII case (the CLI has always taken `F32`).
    const IGNORE_CASE: bool;

    /// The words accepted for this value; the first is how it is written.
    fn spellings(self) -> &'static [&'static str];

    /// How the value is written.
    fn name(self) -> &'static str {
        self.spellings()[0]
    }

    /// The value `word` names.
    fn from_name(word: &str) -> Result<Self, UnknownName<Self>> {
        let matches = |s: &&str| {
            if Self::IGNORE_CASE {
                s.eq_ignore_ascii_case(word)
            } else {
                *s == word
            }
        };
        Self::VALUES
            .iter()
            .copied()
            .find(|v| v.spellings().iter().any(matches))
            .ok_or(UnknownName(PhantomData))
    }
}

/// A word that names no value of `T`. It holds no copy of the word (the crate has no
/// allocator): a caller that wants the word in its message adds it, with
/// [`UnknownName::expected`] for the choices.
pub struct UnknownName<T>(PhantomData<T>);

impl<T: Named> UnknownName<T> {
    /// The words of every value of `T`, comma-separated.
    pub fn expected(&self) -> Names<T> {
        Names(PhantomData)
    }
}

impl<T> Clone for UnknownName<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for UnknownName<T> {}

impl<T> PartialEq for UnknownName<T> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl<T> Eq for UnknownName<T> {}

impl<T: Named> fmt::Debug for UnknownName<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("UnknownName").field(&T::WHAT).finish()
    }
}

impl<T: Named> fmt::Display for UnknownName<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown {} (expected {})", T::WHAT, self.expected())
    }
}

impl<T: Named> core::error::Error for UnknownName<T> {}

/// The words of every value of `T`, written comma-separated.
pub struct Names<T>(PhantomData<T>);

impl<T: Named> fmt::Display for Names<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, v) in T::VALUES.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(v.name())?;
        }
        Ok(())
    }
}

/// `v` as a flag value: its word, the other spellings as hidden aliases. A flag of a
/// [`Named::IGNORE_CASE`] type also needs `ignore_case = true` (clap matches case per
/// argument, not per value).
#[cfg(feature = "clap")]
pub fn possible_value<T: Named>(v: T) -> clap::builder::PossibleValue {
    clap::builder::PossibleValue::new(v.name()).aliases(v.spellings()[1..].iter().copied())
}

/// Gives an enum its words: [`Named`] from one table (what it is, whether case matters,
/// the list of values, each value's spellings with the written one first), and through
/// it `Display`, `FromStr` and, where protocol is built with its `clap` feature,
/// `clap::ValueEnum`. Every user-facing enum of fpgfx goes through this one macro, in
/// this crate or in the crate that owns the enum, so a value is spelled once:
///
/// ```
/// #[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// enum Fruit { Apple, Pear }
///
/// protocol::named! {
///     Fruit, what = "fruit", ignore_case = false, values = [Fruit::Apple, Fruit::Pear],
///     { Apple => ["apple"], Pear => ["pear", "poire"] }
/// }
///
/// assert_eq!("poire".parse::<Fruit>(), Ok(Fruit::Pear));
/// assert_eq!(Fruit::Apple.to_string(), "apple");
/// assert_eq!(
///     "plum".parse::<Fruit>().unwrap_err().to_string(),
///     "unknown fruit (expected apple, pear)"
/// );
/// ```
#[macro_export]
macro_rules! named {
    (
        $t:ident, what = $what:literal, ignore_case = $ic:literal, values = $values:expr,
        { $($v:ident => [$($s:literal),+ $(,)?]),+ $(,)? }
    ) => {
        impl $crate::names::Named for $t {
            const WHAT: &'static str = $what;
            const VALUES: &'static [Self] = &$values;
            const IGNORE_CASE: bool = $ic;

            fn spellings(self) -> &'static [&'static str] {
                match self {
                    $($t::$v => &[$($s),+],)+
                }
            }
        }

        impl core::fmt::Display for $t {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str($crate::names::Named::name(*self))
            }
        }

        impl core::str::FromStr for $t {
            type Err = $crate::names::UnknownName<$t>;

            fn from_str(s: &str) -> Result<Self, Self::Err> {
                <$t as $crate::names::Named>::from_name(s)
            }
        }

        $crate::__named_value_enum!($t);
    };
}

/// `clap::ValueEnum` through [`Named`] for [`named!`]: expands to the impl only when
/// protocol has its `clap` feature, so the caller's own features do not matter, and
/// names clap through protocol so the caller needs no clap dependency of its own.
#[cfg(feature = "clap")]
#[doc(hidden)]
#[macro_export]
macro_rules! __named_value_enum {
    ($t:ident) => {
        impl $crate::names::clap::ValueEnum for $t {
            fn value_variants<'a>() -> &'a [Self] {
                <$t as $crate::names::Named>::VALUES
            }

            fn to_possible_value(&self) -> Option<$crate::names::clap::builder::PossibleValue> {
                Some($crate::names::possible_value(*self))
            }
        }
    };
}

/// Without the `clap` feature there are no flags to give values to.
#[cfg(not(feature = "clap"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __named_value_enum {
    ($t:ident) => {};
}

/// clap as [`named!`] names it (not part of the API).
#[cfg(feature = "clap")]
#[doc(hidden)]
pub use clap;
