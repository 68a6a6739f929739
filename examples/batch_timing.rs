//! The Rust side of the Python package's benchmark (`crates/screwkit-py/benchmarks/bench.py`):
//! times `fk_batch` and `ik_batch` on the very inputs the Python side uses, so the two can be
//! compared in one run.
//!
//! Run: `cargo run --release --example batch_timing -- URDF QS.f64 TARGETS.f64 REPS`
//! (QS: N × dof and TARGETS: M × 16 raw little-endian f64, as numpy's `tofile` writes them).
//! Prints one JSON line: the minimum wall time over REPS of each batch, output allocated per
//! call as the Python call does (IK: LM, tolerances 1e-9, no timeout, restart seed 0 — the
//! Python defaults).

use std::time::Instant;

use screwkit::prelude::*;
use screwkit::solve::batch::{fk_batch, ik_batch};

fn read_f64(path: &str) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    let bytes = std::fs::read(path)?;
    if bytes.len() % 8 != 0 {
        return Err(format!("{path}: {} bytes is not a whole number of f64", bytes.len()).into());
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [urdf, qs, targets, reps] = args.as_slice() else {
        return Err("usage: batch_timing URDF QS.f64 TARGETS.f64 REPS".into());
    };
    let reps: usize = reps.parse()?;
    let kin = Kinematics::new(&load_chain(urdf, None, None)?);
    let (qs, targets) = (read_f64(qs)?, read_f64(targets)?);
    let (n, m, dof) = (qs.len() / kin.dof(), targets.len() / 16, kin.dof());
    let opts = IkOptions {
        timeout: None,
        ..IkOptions::default()
    };
    let (mut fk_best, mut ik_best) = (f64::INFINITY, f64::INFINITY);
    let mut solved = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let mut poses = vec![0.0; n * 16];
        fk_batch(&kin, &qs, &mut poses)?;
        fk_best = fk_best.min(t0.elapsed().as_secs_f64());
        std::hint::black_box(&poses);

        let t0 = Instant::now();
        let mut q = vec![0.0; m * dof];
        let mut status = vec![IkStatus::default(); m];
        ik_batch(&kin, &targets, None, &opts, &mut q, &mut status, None)?;
        ik_best = ik_best.min(t0.elapsed().as_secs_f64());
        solved = status.iter().filter(|s| s.converged).count();
    }
    println!(
        "{{\"fk_batch_s\": {fk_best}, \"fk_rows\": {n}, \"ik_batch_s\": {ik_best}, \"ik_rows\": {m}, \"ik_solved\": {solved}, \"threads\": {}}}",
        rayon::current_num_threads()
    );
    Ok(())
}
