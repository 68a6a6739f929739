//! The values of the expression language: numbers, integers, booleans, strings; literals as
//! xacro reads property text.

use super::*;

/// A value of a `${…}` expression.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value {
    Int(i64),
    Float(f64),
    Bool(bool),
    Str(String),
}

impl Value {
    /// As Python's `str()` writes it (floats shortest round-trip, as Python's repr).
    pub(crate) fn to_text(&self) -> String {
        match self {
            Value::Int(i) => i.to_string(),
            Value::Float(x) => python_repr(*x),
            Value::Bool(b) => if *b { "True" } else { "False" }.into(),
            Value::Str(s) => s.clone(),
        }
    }

    pub(crate) fn num(&self) -> Option<f64> {
        match self {
            Value::Int(i) => Some(*i as f64),
            Value::Float(x) => Some(*x),
            Value::Bool(b) => Some(f64::from(u8::from(*b))),
            Value::Str(_) => None,
        }
    }

    pub(crate) fn truth(&self) -> Result<bool, String> {
        match self {
            Value::Bool(b) => Ok(*b),
            Value::Int(i) => Ok(*i != 0),
            Value::Float(x) => Ok(*x != 0.0),
            // xacro's get_boolean_value: true/false words, else an integer's truth.
            Value::Str(s) => match s.trim() {
                "true" | "True" => Ok(true),
                "false" | "False" => Ok(false),
                other => other
                    .parse::<i64>()
                    .map(|i| i != 0)
                    .map_err(|_| format!("\"{other}\" is not a boolean")),
            },
        }
    }
}

/// xacro's literal conversion of a property's text: 'quoted' → the string, then int, float,
/// boolean, else the string itself.
pub(crate) fn literal(v: Value) -> Value {
    let Value::Str(s) = &v else { return v };
    let t = s.trim();
    if t.len() >= 2 && t.starts_with('\'') && t.ends_with('\'') {
        return Value::Str(t[1..t.len() - 1].to_string());
    }
    // As xacro: text with an underscore stays text (Python would read `1_0` as 10).
    if t.contains('_') {
        return v;
    }
    if let Ok(i) = t.parse::<i64>() {
        return Value::Int(i);
    }
    if let Some(x) = python_float(t) {
        return Value::Float(x);
    }
    match t {
        "true" | "True" => Value::Bool(true),
        "false" | "False" => Value::Bool(false),
        _ => v,
    }
}
