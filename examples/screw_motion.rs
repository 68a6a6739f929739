//! The worked examples of the screw-motion lesson, computed with screwkit-lie.
//!
//! Run: `cargo run --example screw_motion`

use nalgebra::{Matrix4, Vector3};
use screwkit::lie::{Se3, Twist};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A transform → its screw motion (matrix logarithm).
    let t_sb = Se3::from_homogeneous(&Matrix4::new(
        0.0, -1.0, 0.0, 3.0, //
        0.0, 0.0, -1.0, 0.0, //
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    ))?;
    println!("T_sb =\n{t_sb:.4}");
    let (s, theta) = t_sb.log_screw().ok_or("identity has no screw axis")?;
    println!("S     = {:.7}", s.twist());
    println!("θ     = {theta:.7} rad ({:.2}°)", theta.to_degrees());
    println!("axis  : {s:.7}");

    // Exponential coordinates → a transform (matrix exponential).
    let xi = Twist::new(Vector3::new(0.0, 1.0, 2.0), Vector3::new(3.0, 0.0, 0.0));
    println!("\nexp of Sθ = {xi:.1}:\n{:.4}", Se3::exp(&xi));
    Ok(())
}
