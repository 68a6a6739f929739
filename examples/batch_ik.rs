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
    let n = 10_000;
    // Reproducible configurations within the limits.
    let qs = screwkit::solve::protocol::sample_configurations(&kin, n, 0x2545_F491_4F6C_DD1D);
    let mut targets = vec![Se3::identity(); n];
    fk_batch(&kin, &qs, &mut targets)?;
    let t0 = Instant::now();
    let results = ik_batch(&kin, &targets, None, &IkOptions::default())?;
    let secs = t0.elapsed().as_secs_f64();
    let mut solved = 0;
    let mut worst: f64 = 0.0;
    for (r, t) in results.iter().zip(&targets) {
        let r = r.as_ref().map_err(|e| e.to_string())?;
        if r.converged {
            solved += 1;
            worst = worst.max(fk(&kin, &r.q)?.max_abs_diff(t));
        }
    }
    println!(
        "{solved}/{n} solved ({:.2} %) in {secs:.2} s on {} threads: {:.0} solves/s; worst FK error of a solution {worst:.1e}",
        100.0 * solved as f64 / n as f64,
        rayon_threads(),
        n as f64 / secs
    );
    Ok(())
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}
