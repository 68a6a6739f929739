//! The README's "Library in a few lines", compiled (tests/readme_library.rs keeps the two
//! identical). Run: `cargo run --release --example readme_library`

use screwkit::prelude::*;
use screwkit::solve::ik;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let chain = load_chain("assets/urdf/panda.urdf", None, None)?; // base = root, tip = only leaf
    let kin = Kinematics::new(&chain); // the model: immutable, shareable
    let mut ws = Workspace::new(&kin); // per-thread scratch
    let q = [0.1, -0.4, 0.2, -2.0, 0.3, 1.8, 0.5];
    let t_sb = fk(&kin, &mut ws, &q)?; // e^[S1]q1 ⋯ e^[S7]q7 M
    let j_body = jacobian(&kin, &mut ws, &q, Frame::Body)?; // 6x7 J_b, rows (ω, v)
    println!(
        "T_sb =\n{t_sb:.4}J_b column 1 = {:.4}",
        j_body.column(0).transpose()
    );
    let sol = ik::solve(&kin, &mut ws, &t_sb, &kin.midpoint(), &IkOptions::default())?;
    assert!(sol.status.converged && fk(&kin, &mut ws, &sol.q)?.max_abs_diff(&t_sb) < 1e-8);
    // The Lie-group layer: frame changes V_s = [Ad_{T_sb}] V_b, F_b = [Ad_{T_sb}]ᵀ F_s.
    let v_s = t_sb.adjoint_apply(&Twist::new(Vector3::z(), Vector3::zeros()));
    let f_b = t_sb.adjoint_transpose_apply(&Wrench::new(Vector3::zeros(), Vector3::x()));
    println!("V_s = {v_s:.3}, F_b = {f_b:.3}");
    Ok(())
}
