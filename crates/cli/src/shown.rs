//! A TOML value as an error shows it.

use relief::table;

/// A TOML value as an error shows it (short, in TOML's own spelling).
pub(crate) fn toml_shown(v: &toml::Value) -> String {
    let s = match v {
        toml::Value::String(s) => format!("{s:?}"),
        toml::Value::Table(_) => "a table".to_owned(),
        toml::Value::Array(a) => format!("an array of {}", a.len()),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => format!("{f:?}"),
        toml::Value::Boolean(b) => b.to_string(),
        toml::Value::Datetime(d) => d.to_string(),
    };
    table::shorten(&s)
}
