//! FK and Jacobians of the bundled UR5 at a configuration, with a singularity analysis, and
//! a check a person can do: the body Jacobian is [Ad_{T⁻¹}] times the space Jacobian.
//!
//! Run: `cargo run --example fk_and_jacobian`

use screwkit::prelude::*;
use screwkit::solve::analysis::analyze;
use screwkit::solve::jacobian::fk_jacobian;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let chain = load_chain("assets/urdf/ur5.urdf", None, None)?;
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    let q = [0.0, -1.2, 1.5, -0.3, std::f64::consts::FRAC_PI_2, 0.0];
    let space = fk_jacobian(&kin, &mut ws, &q, Frame::Space)?;
    let (t_sb, j_s) = (space.pose, space.jacobian.clone());
    println!("T_sb(q) =\n{t_sb:.4}");
    println!("J_s(q) (rows ω, v) =\n{:.4}", j_s);
    let j_b = jacobian(&kin, &mut ws, &q, Frame::Body)?;
    let diff = (t_sb.inverse().adjoint() * &j_s - j_b).amax();
    println!("max |Ad_(T^-1) J_s - J_b| = {diff:.1e}");
    let a = analyze(&kin, &mut ws, &q, Frame::Space)?;
    println!(
        "singular values {:.4?}\nrank {}  manipulability {:.5}  condition number {:.2}",
        a.singular_values, a.rank, a.manipulability, a.condition_number
    );
    // Move the wrist into its singularity (q5 = 0: joints 4 and 6 align).
    let q_sing = [0.0, -1.2, 1.5, -0.3, 0.0, 0.0];
    let a = analyze(&kin, &mut ws, &q_sing, Frame::Space)?;
    println!(
        "at q5 = 0: rank {}, lost twist direction ({}); {}",
        a.rank,
        screwkit::lie::display::fixed_list(a.lost_directions[0].as_slice(), 3),
        a.verdict()
    );
    Ok(())
}
