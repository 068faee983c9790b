//! Parameter tables: one row per user-settable value (name, type, range, default, doc, what a
//! change re-does), read by every front end. The CLI's flags, scene-file keys, the page's URL
//! keys and controls, and the error text all come from these rows, so a parameter is added in
//! one place. [`crate::params::PARAMS`] is the scene's table; the window adds its own rows.

use crate::error::{Error, Result};

/// How a parameter's text is read and what range it accepts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// An integer in `min..=max`.
    Int {
        /// Smallest value.
        min: u32,
        /// Largest value.
        max: u32,
    },
    /// A finite number in `min..=max`.
    Float {
        /// Smallest value.
        min: f32,
        /// Largest value.
        max: f32,
    },
    /// Two finite numbers written `X,Y`, each with `|v| <= max`.
    Pair {
        /// Largest magnitude of either number.
        max: f64,
    },
    /// One of a fixed set of names.
    Choice(&'static [&'static str]),
    /// On or off: `1`, `true`, `yes`, `on` or `0`, `false`, `no`, `off`.
    Bool,
}

/// A parameter value, typed by its [`Kind`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// For [`Kind::Int`].
    Int(u32),
    /// For [`Kind::Float`].
    Float(f32),
    /// For [`Kind::Pair`].
    Pair([f64; 2]),
    /// For [`Kind::Choice`]: the chosen name.
    Choice(&'static str),
    /// For [`Kind::Bool`].
    Bool(bool),
}

impl std::fmt::Display for Value {
    /// The text that reads back as the same value (`1.5,-2` for a pair, `1`/`0` for a bool).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Value::Int(v) => write!(f, "{v}"),
            Value::Float(v) => write!(f, "{v}"),
            Value::Pair([x, y]) => write!(f, "{x},{y}"),
            Value::Choice(s) => f.write_str(s),
            Value::Bool(b) => f.write_str(if b { "1" } else { "0" }),
        }
    }
}

/// What the page shows for a parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// No control: set through the URL (or the CLI and scene files) only.
    None,
    /// A slider over `min..=max` in steps of `step`: a part of the allowed range that is
    /// comfortable to drag; the URL still accepts the whole range.
    Slider {
        /// Left end.
        min: f64,
        /// Right end.
        max: f64,
        /// Step.
        step: f64,
    },
    /// A number field.
    Number,
    /// A drop-down of the [`Kind::Choice`] names.
    Select,
    /// A checkbox.
    Checkbox,
}

/// One user-settable parameter of a `T` (the scene, or the window's options).
pub struct Param<T: 'static> {
    /// The key in scene files and URLs (`height_scale`); the CLI flag is the same with dashes.
    pub key: &'static str,
    /// One line for `--help`, the README and the page's tooltips.
    pub doc: &'static str,
    /// Its type and range.
    pub kind: Kind,
    /// The control the page shows for it.
    pub control: Control,
    /// Reads it from a `T`.
    pub get: fn(&T) -> Value,
    /// Writes it into a `T` (the value is already checked against [`Param::kind`]).
    pub set: fn(&mut T, Value),
}

impl<T> Param<T> {
    /// The CLI flag's name, without the leading dashes: the key with `-` for `_`.
    pub fn flag(&self) -> String {
        self.key.replace('_', "-")
    }

    /// The allowed values, in words, for errors and help.
    pub fn allowed(&self) -> String {
        self.kind.allowed()
    }

    /// Reads `text` (as typed on the command line, in a URL or a control) into a checked value.
    pub fn parse(&self, text: &str) -> Result<Value> {
        self.kind.parse(text).ok_or_else(|| self.invalid(text))
    }

    /// Checks a typed value (as a program builds it) against the range.
    pub fn check(&self, value: Value) -> Result<()> {
        if self.kind.accepts(value) {
            Ok(())
        } else {
            Err(self.invalid(&value_text(value)))
        }
    }

    /// Parses `text` and sets it on `target`; on error `target` is unchanged.
    pub fn set_text(&self, target: &mut T, text: &str) -> Result<()> {
        let v = self.parse(text)?;
        (self.set)(target, v);
        Ok(())
    }

    /// The error for a bad value of this parameter.
    pub fn invalid(&self, text: &str) -> Error {
        Error::invalid(self.key, shorten(text), self.allowed())
    }
}

/// Finds the row for `key` (scene-file spelling; dashes are accepted for underscores).
pub fn find<'a, T>(table: &'a [Param<T>], key: &str) -> Option<&'a Param<T>> {
    let key = key.trim().replace('-', "_");
    table.iter().find(|p| p.key == key)
}

impl Kind {
    /// The allowed values in words (`0..=1`, `differences or analytic`).
    pub fn allowed(&self) -> String {
        match *self {
            Kind::Int { min, max } => format!("{min}..={max}"),
            Kind::Float { min, max } => format!("{min}..={max}"),
            Kind::Pair { max } => format!("X,Y, each within ±{max:.0}"),
            Kind::Choice(names) => match names {
                [] => String::new(),
                [one] => (*one).to_owned(),
                [init @ .., last] => format!("{} or {last}", init.join(", ")),
            },
            Kind::Bool => "1 or 0 (true/false, yes/no, on/off)".to_owned(),
        }
    }

    /// The value `text` stands for, if it is one this kind accepts.
    pub fn parse(&self, text: &str) -> Option<Value> {
        let t = text.trim();
        let v = match *self {
            Kind::Int { .. } => Value::Int(t.parse().ok()?),
            Kind::Float { .. } => Value::Float(t.parse().ok()?),
            Kind::Pair { .. } => {
                let (x, y) = t.split_once(',')?;
                Value::Pair([x.trim().parse().ok()?, y.trim().parse().ok()?])
            }
            Kind::Choice(names) => Value::Choice(names.iter().find(|n| **n == t)?),
            Kind::Bool => Value::Bool(match t.to_ascii_lowercase().as_str() {
                "1" | "true" | "yes" | "on" => true,
                "0" | "false" | "no" | "off" => false,
                _ => return None,
            }),
        };
        self.accepts(v).then_some(v)
    }

    /// Whether `value` has this kind and lies in its range.
    pub fn accepts(&self, value: Value) -> bool {
        match (*self, value) {
            (Kind::Int { min, max }, Value::Int(v)) => (min..=max).contains(&v),
            (Kind::Float { min, max }, Value::Float(v)) => {
                v.is_finite() && (min..=max).contains(&v)
            }
            (Kind::Pair { max }, Value::Pair(v)) => {
                v.iter().all(|c| c.is_finite() && c.abs() <= max)
            }
            (Kind::Choice(names), Value::Choice(v)) => names.contains(&v),
            (Kind::Bool, Value::Bool(_)) => true,
            _ => false,
        }
    }
}

/// A value as an error message shows it: numbers short (`1e300`, not 301 digits).
fn value_text(v: Value) -> String {
    match v {
        Value::Float(x) => number(f64::from(x)),
        Value::Pair([x, y]) => format!("{},{}", number(x), number(y)),
        other => other.to_string(),
    }
}

/// A number as people read it: plain where short, in exponent form where plain would be long.
pub fn number(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 12 {
        plain
    } else {
        let e = format!("{x:.6e}");
        // "1.000000e300" -> "1e300"
        match e.split_once('e') {
            Some((m, exp)) => {
                let m = m.trim_end_matches('0').trim_end_matches('.');
                format!("{m}e{exp}")
            }
            None => e,
        }
    }
}

/// Most characters of a user's value an error line repeats.
pub(crate) const MAX_VALUE_CHARS: usize = 32;

/// `text` cut to `MAX_VALUE_CHARS` characters (with `...` and the total length) and on one
/// line, so an error about a megabyte value is still one short line.
pub fn shorten(text: &str) -> String {
    shorten_to(text, MAX_VALUE_CHARS)
}

/// [`shorten`] with a limit.
pub fn shorten_to(text: &str, max: usize) -> String {
    let one_line: String = text
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let n = one_line.chars().count();
    if n <= max {
        return one_line;
    }
    let suffix = format!("... ({n} chars)");
    let head: String = one_line
        .chars()
        .take(max.saturating_sub(suffix.len()).max(8))
        .collect();
    format!("{head}{suffix}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_parse_and_check() {
        let k = Kind::Int { min: 1, max: 16 };
        assert_eq!(k.parse(" 3 "), Some(Value::Int(3)));
        for bad in ["0", "17", "-1", "3.0", "x", "", "99999999999999999999"] {
            assert_eq!(k.parse(bad), None, "{bad}");
        }
        let f = Kind::Float { min: 0.0, max: 1.0 };
        assert_eq!(f.parse("0.5"), Some(Value::Float(0.5)));
        for bad in ["nan", "inf", "-0.1", "1.01", "1e300"] {
            assert_eq!(f.parse(bad), None, "{bad}");
        }
        let p = Kind::Pair { max: 10.0 };
        assert_eq!(p.parse("1.5, -2"), Some(Value::Pair([1.5, -2.0])));
        for bad in ["1", "1,2,3", "nan,0", "11,0", ","] {
            assert_eq!(p.parse(bad), None, "{bad}");
        }
        let b = Kind::Bool;
        assert_eq!(b.parse("YES"), Some(Value::Bool(true)));
        assert_eq!(b.parse("0"), Some(Value::Bool(false)));
        assert_eq!(b.parse("maybe"), None);
        let c = Kind::Choice(&["a", "b", "c"]);
        assert_eq!(c.allowed(), "a, b or c");
        assert_eq!(c.parse("b"), Some(Value::Choice("b")));
        assert_eq!(c.parse("d"), None);
    }

    #[test]
    fn values_round_trip_through_text() {
        for (k, v) in [
            (
                Kind::Int {
                    min: 0,
                    max: u32::MAX,
                },
                Value::Int(u32::MAX),
            ),
            (
                Kind::Float {
                    min: -1.0,
                    max: 1.0,
                },
                Value::Float(0.47),
            ),
            (Kind::Pair { max: 1e12 }, Value::Pair([0.1 + 0.2, -1e11])),
            (Kind::Bool, Value::Bool(true)),
        ] {
            assert_eq!(k.parse(&v.to_string()), Some(v));
        }
    }

    #[test]
    fn shortening() {
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(0.25), "0.25");
        assert_eq!(number(-1.5e-20), "-1.5e-20");
        let long = "x".repeat(1_000_000);
        let s = shorten(&long);
        assert!(
            s.chars().count() <= MAX_VALUE_CHARS && s.contains("1000000 chars"),
            "{s}"
        );
        assert_eq!(shorten("a\nb"), "a b");
    }
}
