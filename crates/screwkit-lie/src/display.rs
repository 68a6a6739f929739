//! Number formatting shared by every human-readable output of the workspace.

/// `x` with `precision` decimals, never printing a negative zero: values that round to zero
/// (−0.0, −1e-17, …) print as `0.000…`.
///
/// ```
/// assert_eq!(screwkit_lie::display::fixed(-1e-17, 3), "0.000");
/// assert_eq!(screwkit_lie::display::fixed(-0.0005, 3), "-0.001");
/// assert_eq!(screwkit_lie::display::fixed(-0.0004, 3), "0.000");
/// ```
pub fn fixed(x: f64, precision: usize) -> String {
    let s = format!("{x:.precision$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => s,
    }
}

/// Formats a list of numbers with [`fixed`], separated by `", "`.
pub fn fixed_list(xs: &[f64], precision: usize) -> String {
    xs.iter()
        .map(|&x| fixed(x, precision))
        .collect::<Vec<_>>()
        .join(", ")
}
