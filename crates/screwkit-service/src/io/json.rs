//! The JSON number rule of every report: a float is written as the shortest text that reads
//! back to the same f64 (serde_json's `float_roundtrip`), −0 as 0, and NaN or infinity as
//! `null` (JSON has no such numbers).

use serde::Serializer;
use serde_json::Value;

/// A JSON number by the rule: −0 becomes 0, non-finite values `null`.
pub fn num(x: f64) -> Value {
    if x == 0.0 {
        Value::from(0.0)
    } else {
        Value::from(x)
    }
}

/// A JSON array of numbers by the rule.
pub fn nums(xs: &[f64]) -> Value {
    Value::Array(xs.iter().map(|&x| num(x)).collect())
}

/// Rows of `cols` numbers (a row-major matrix) as a JSON array of arrays.
pub fn rows(m: &[f64], cols: usize) -> Value {
    Value::Array(m.chunks(cols.max(1)).map(nums).collect())
}

/// serde's form of [`num`], for report fields: `#[serde(serialize_with = "json::number")]`.
pub fn number<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(if *x == 0.0 { 0.0 } else { *x })
    } else {
        s.serialize_none()
    }
}

/// serde's form of [`nums`], for report fields holding a list of numbers.
pub fn numbers<S: Serializer>(xs: &[f64], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(xs.len()))?;
    for x in xs {
        seq.serialize_element(&num(*x))?;
    }
    seq.end()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule() {
        assert_eq!(
            nums(&[-0.0, 1.5, f64::NAN, f64::INFINITY]).to_string(),
            "[0.0,1.5,null,null]"
        );
        #[derive(serde::Serialize)]
        struct R {
            #[serde(serialize_with = "number")]
            a: f64,
            #[serde(serialize_with = "numbers")]
            b: Vec<f64>,
        }
        let r = R {
            a: -0.0,
            b: vec![0.1, f64::NAN],
        };
        assert_eq!(
            serde_json::to_string(&r).unwrap(),
            r#"{"a":0.0,"b":[0.1,null]}"#
        );
    }
}
