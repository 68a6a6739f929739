//! Batched IK on the bundled iiwa14: 10,000 random reachable targets solved on all cores,
//! with the solve rate, throughput and an FK check of every solution.
//!
//! Run: `cargo run --release --example batch_ik`

use std::time::Instant;

use screwkit::prelude::*;
use screwkit::solve::batch::{fk_batch, ik_batch};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let chain = load_chain("assets/urdf/iiwa14.urdf", None, None)?;
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    let (n, dof) = (10_000, kin.dof());
    // Reproducible configurations within the limits, and their tip poses as targets.
    let qs = screwkit::solve::sample::configurations(&kin, n, 0x2545_F491_4F6C_DD1D);
    let mut targets = vec![0.0; n * 16];
    fk_batch(&kin, &qs, &mut targets)?;
    let mut q = vec![0.0; n * dof];
    let mut status = vec![IkStatus::default(); n];
    let t0 = Instant::now();
    ik_batch(
        &kin,
        &targets,
        None,
        &IkOptions::default(),
        &mut q,
        &mut status,
        None,
    )?;
    let secs = t0.elapsed().as_secs_f64();
    let mut solved = 0;
    let mut worst: f64 = 0.0;
    for k in 0..n {
        if status[k].converged {
            solved += 1;
            let t = fk(&kin, &mut ws, &q[k * dof..(k + 1) * dof])?;
            let h = t.to_homogeneous();
            let target = &targets[16 * k..16 * (k + 1)];
            let err = (0..16).fold(0.0f64, |m, i| m.max((h[(i / 4, i % 4)] - target[i]).abs()));
            worst = worst.max(err);
        }
    }
    println!(
        "{solved}/{n} solved ({:.2} %) in {secs:.2} s on {} threads: {:.0} solves/s; worst FK error of a solution {worst:.1e}",
        100.0 * solved as f64 / n as f64,
        rayon::current_num_threads(),
        n as f64 / secs
    );
    Ok(())
}
