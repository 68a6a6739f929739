//! Inverse kinematics on the bundled Panda: a target from a known configuration, solved from
//! the limit midpoints with each method, checked by FK.
//!
//! Run: `cargo run --release --example ik`

use screwkit::prelude::*;
use screwkit::solve::ik;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let chain = load_chain("assets/urdf/panda.urdf", None, None)?;
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    let q_star = [0.4, -0.3, 0.2, -2.1, 0.1, 1.9, 0.6];
    let target = fk(&kin, &mut ws, &q_star)?;
    println!("target T_sd =\n{target:.4}");
    for (name, method) in [
        ("Levenberg–Marquardt", IkMethod::LM),
        ("Newton–Raphson (pinv)", IkMethod::NewtonRaphson),
        ("damped least squares", IkMethod::DLS),
    ] {
        let opts = IkOptions {
            method,
            ..IkOptions::default()
        };
        let r = ik::solve(&kin, &mut ws, &target, &kin.midpoint(), &opts)?;
        let err = fk(&kin, &mut ws, &r.q)?.max_abs_diff(&target);
        let st = &r.status;
        println!(
            "{name:<24} converged {:<5} iterations {:>3} restarts {}  q = {:.4?}  max |FK(q) - T_sd| = {err:.1e}",
            st.converged, st.iterations, st.restarts, r.q
        );
    }
    Ok(())
}
