//! Python's number semantics the expressions follow: `round` (half to even, on the exact
//! binary value), `float()` of text, `repr` of floats.

/// Python's `round`: halves to even.
pub(crate) fn round_half_even(x: f64) -> f64 {
    let r = x.round();
    if (x - x.trunc()).abs() == 0.5 && r % 2.0 != 0.0 {
        r - x.signum()
    } else {
        r
    }
}

/// Python's `round(x, n)` for a float: the exact binary value rounded to n decimals, halves
/// to even (so `round(2.675, 2)` is 2.67: 2.675 is stored as 2.67499999…).
pub(crate) fn python_round(x: f64, n: i64) -> f64 {
    if !x.is_finite() || n > 330 {
        return x;
    }
    if n >= 0 {
        // Rust's fixed-precision formatting rounds the exact value, ties to even.
        format!("{x:.prec$}", prec = n as usize)
            .parse()
            .unwrap_or(x)
    } else {
        let p = 10f64.powi((-n).min(400) as i32);
        if p.is_infinite() {
            return 0.0 * x;
        }
        round_half_even(x / p) * p
    }
}

/// Python's `float(text)`: surrounding whitespace, `inf`/`nan`/`infinity` in any case, no
/// underscores (PEP 515 digits are not accepted here).
pub(crate) fn python_float(s: &str) -> Option<f64> {
    let t = s.trim();
    if t.contains('_') {
        return None;
    }
    t.parse::<f64>().ok()
}

/// Python's `repr` of a float (which `str` gives too): the shortest digits that read back
/// the same, fixed notation for 1e-4 ≤ |x| < 1e16, else `d.ddde±XX` with at least two
/// exponent digits (`1e-07`, `1.5e+16`).
pub(crate) fn python_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return if x.is_sign_negative() { "-0.0" } else { "0.0" }.into();
    }
    // Shortest round-trip digits and the decimal exponent, from Rust's `{:e}`.
    let sci = format!("{x:e}");
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let (sign, mantissa) = match mantissa.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", mantissa),
    };
    let digits: String = mantissa.chars().filter(|c| *c != '.').collect();
    if (-4..16).contains(&exp) {
        let n = digits.len() as i32;
        let s = if exp < 0 {
            format!("0.{}{}", "0".repeat((-exp - 1) as usize), digits)
        } else if exp + 1 >= n {
            format!("{}{}.0", digits, "0".repeat((exp + 1 - n) as usize))
        } else {
            let (a, b) = digits.split_at((exp + 1) as usize);
            format!("{a}.{b}")
        };
        format!("{sign}{s}")
    } else {
        let m = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits
        };
        let es = if exp < 0 { '-' } else { '+' };
        format!("{sign}{m}e{es}{:02}", exp.abs())
    }
}
