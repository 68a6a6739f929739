//! Batches over many configurations or targets, in parallel with rayon.
//!
//! Inputs are flat row-major slices (row k = q of configuration k); results come back in input
//! order. Each worker uses its own [`Workspace`]. IK restarts are seeded per row from
//! (seed, row index), so results do not depend on the number of threads (when the wall-time
//! budget does not bind: set `timeout: None` for bit-for-bit reproducibility).

use nalgebra::Matrix6xX;
use rayon::prelude::*;
use screwkit_lie::Se3;

use crate::error::SolveError;
use crate::fk::fk_unchecked;
use crate::ik::{solve_unchecked, IkOptions, IkResult, SplitMix};
use crate::jacobian::{fk_jacobian_into, Frame};
use crate::kinematics::{Kinematics, Workspace};

/// Rows per rayon task: large enough to amortise scheduling, small enough to balance.
const CHUNK: usize = 256;

fn check_rows(kin: &Kinematics, qs: &[f64]) -> Result<usize, SolveError> {
    let n = kin.dof();
    if n == 0 || !qs.len().is_multiple_of(n) {
        return Err(SolveError::WrongLength {
            what: "joint values (a multiple of the DoF)",
            expected: n * (qs.len() / n.max(1)),
            got: qs.len(),
            names: kin.names().join(", "),
        });
    }
    // In parallel too (a serial scan would cap the speed-up of cheap work such as FK); the
    // first bad row in input order is the one reported.
    if let Some(k) = qs
        .par_chunks(n)
        .with_min_len(CHUNK)
        .position_first(|row| row.iter().any(|x| !x.is_finite()))
    {
        kin.check_q(&qs[k * n..(k + 1) * n])?;
    }
    Ok(qs.len() / n)
}

/// Tip poses of many configurations: `out[k] = T(q_k)`.
pub fn fk_batch(kin: &Kinematics, qs: &[f64], out: &mut [Se3]) -> Result<(), SolveError> {
    let rows = check_rows(kin, qs)?;
    if out.len() != rows {
        return Err(SolveError::WrongLength {
            what: "output poses",
            expected: rows,
            got: out.len(),
            names: String::new(),
        });
    }
    let n = kin.dof();
    out.par_chunks_mut(CHUNK)
        .zip(qs.par_chunks(CHUNK * n))
        .for_each(|(o, q)| {
            for (t, row) in o.iter_mut().zip(q.chunks(n)) {
                *t = fk_unchecked(kin, row);
            }
        });
    Ok(())
}

/// Poses and Jacobians of many configurations (Jacobians allocated once per row).
pub fn jacobian_batch(
    kin: &Kinematics,
    qs: &[f64],
    frame: Frame,
) -> Result<Vec<(Se3, Matrix6xX<f64>)>, SolveError> {
    check_rows(kin, qs)?;
    let n = kin.dof();
    Ok(qs
        .par_chunks(n)
        .map(|row| {
            let mut j = Matrix6xX::zeros(n);
            let t = fk_jacobian_into(kin, &mut j, row, frame);
            (t, j)
        })
        .collect())
}

/// The restart seed of row `index` of a batch.
pub fn row_seed(seed: u64, index: usize) -> u64 {
    let mut g = SplitMix(seed ^ (index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    g.next_u64()
}

/// IK for many targets. `seeds`: one row of initial guesses per target, or `None` for the
/// midpoint of the limits. Row k uses restart seed [`row_seed`]`(opts.seed, k)`.
pub fn ik_batch(
    kin: &Kinematics,
    targets: &[Se3],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
) -> Result<Vec<Result<IkResult, SolveError>>, SolveError> {
    let n = kin.dof();
    if let Some(s) = seeds {
        let rows = check_rows(kin, s)?;
        if rows != targets.len() {
            return Err(SolveError::WrongLength {
                what: "seed rows",
                expected: targets.len(),
                got: rows,
                names: String::new(),
            });
        }
    }
    let mid = kin.midpoint();
    Ok(targets
        .par_iter()
        .enumerate()
        // One target per task: IK costs are heavy-tailed (a restart can cost 10× a median
        // solve), so coarse chunks leave one worker finishing alone; work stealing at single
        // targets keeps both busy for a few ns of overhead per ~10 µs solve.
        .with_max_len(1)
        .map_init(
            || Workspace::new(kin),
            |ws, (k, target)| {
                if !target.is_finite() {
                    return Err(SolveError::BadTarget);
                }
                let seed = seeds.map_or(mid.as_slice(), |s| &s[k * n..(k + 1) * n]);
                let o = IkOptions {
                    seed: row_seed(opts.seed, k),
                    ..opts.clone()
                };
                solve_unchecked(kin, ws, target, seed, &o)
            },
        )
        .collect())
}

/// IK along a path: target k is seeded with the solution of target k − 1 (warm start),
/// the first with `seed`. Sequential by nature.
pub fn ik_path(
    kin: &Kinematics,
    targets: &[Se3],
    seed: &[f64],
    opts: &IkOptions,
) -> Result<Vec<IkResult>, SolveError> {
    kin.check_q(seed)?;
    let mut ws = Workspace::new(kin);
    let mut q = seed.to_vec();
    let mut out = Vec::with_capacity(targets.len());
    for (k, target) in targets.iter().enumerate() {
        if !target.is_finite() {
            return Err(SolveError::BadTarget);
        }
        let o = IkOptions {
            seed: row_seed(opts.seed, k),
            ..opts.clone()
        };
        let r = solve_unchecked(kin, &mut ws, target, &q, &o)?;
        if r.converged {
            q.copy_from_slice(&r.q);
        }
        out.push(r);
    }
    Ok(out)
}
