//! `screwkit exp` and `screwkit log`: the exponential and logarithm of
//! *Modern Robotics* §3.3.3 as a calculator.

use screwkit_lie::{ScrewAxis, Se3, Twist};
use serde_json::{json, Value};

use crate::args::{ExpArgs, Format, LogArgs};
use crate::output::{
    matrix_text, num, nums, pose_json, pose_summary, print_json, tuple, CliResult,
};

/// Runs `exp`: T = e^\[S\]θ (or e^\[ξ\] with θ = 1).
pub fn exp(args: &ExpArgs, format: Format) -> CliResult {
    let s = Twist::try_from_slice(&args.twist.0)?;
    if !args.theta.is_finite() {
        return Err(crate::output::Failure(format!(
            "--theta {}: expected a finite number",
            args.theta
        )));
    }
    let t = Se3::exp(&(s * args.theta));
    if !t.is_finite() {
        return Err(crate::output::Failure(format!(
            "e^[S]θ overflows for S θ = {}: the product is beyond f64",
            tuple((s * args.theta).to_vector().as_slice())
        )));
    }
    if format == Format::Json {
        print_json(&json!({"pose": pose_json(&t)}))?;
    } else {
        crate::output::emit(&format!(
            "e^[S]θ with S = {}, θ = {}:\n{}{}",
            tuple(&args.twist.0),
            args.theta,
            matrix_text(&t),
            pose_summary(&t)
        ))?;
    }
    Ok(())
}

/// Runs `log`: \[S\]θ = log T, with the screw's direction, point and pitch.
pub fn log(args: &LogArgs, format: Format) -> CliResult {
    let t = Se3::from_row_major(&args.matrix.0, 1e-3)?;
    let xi = t.log();
    let screw = ScrewAxis::from_twist(&xi).ok();
    let (axis, theta) = match &screw {
        Some((a, th)) => (Some(a), *th),
        None => (None, 0.0),
    };
    let pure = axis.is_some_and(ScrewAxis::is_pure_translation);
    if format == Format::Json {
        let s = axis.map_or(vec![0.0; 6], |a| a.twist().to_vector().as_slice().to_vec());
        print_json(&json!({
            "theta": num(theta),
            "screw": nums(&s),
            "pitch": axis.and_then(ScrewAxis::pitch).map_or(Value::Null, num),
            "point": axis.and_then(ScrewAxis::point).map_or(Value::Null, |p| nums(p.as_slice())),
            "direction": axis.map_or(nums(&[0.0; 3]), |a| nums(a.direction().as_slice())),
            "pure_translation": pure,
        }))?;
        return Ok(());
    }
    let mut s = format!("T =\n{}", matrix_text(&t));
    match axis {
        None => s.push_str("\nT is the identity: no motion (θ = 0, any axis).\n"),
        Some(a) if pure => s.push_str(&format!(
            "\nPure translation (R = I, infinite pitch):\nS = (ω | v)        {}\nθ                  {} m\ndirection          {}\n",
            tuple(a.twist().to_vector().as_slice()),
            theta,
            tuple(a.direction().as_slice())
        )),
        Some(a) => s.push_str(&format!(
            "\nScrew motion [S]θ = log T:\nS = (ω | v)        {}\nθ                  {:.6} rad ({:.3}°)\ndirection ŝ        {}\npoint q            {} (on the axis, closest to the origin)\npitch h            {:.6} m/rad\n",
            tuple(a.twist().to_vector().as_slice()),
            theta,
            theta.to_degrees(),
            tuple(a.direction().as_slice()),
            tuple(a.point().unwrap_or_default().as_slice()),
            a.pitch().unwrap_or(0.0)
        )),
    }
    crate::output::emit(&s)?;
    Ok(())
}
