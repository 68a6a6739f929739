//! The tree's algorithms over N configurations, in parallel (rayon), on flat row-major
//! buffers, with the shape and rules of [`crate::batch`] (a bad row gets NaN output and is
//! listed in [`SolveError::Rows`]; the others are computed; row k equals the single call on
//! row k bit for bit whatever the thread count):
//!
//! | function | input | output |
//! |---|---|---|
//! | [`fk_frames_batch`] | q: N × nq | poses: N × F × 16 (every frame, frame order) |
//! | [`fk_frame_batch`] | q: N × nq | poses: N × 16 |
//! | [`frame_jacobian_batch`] | q: N × nq | Jacobians: N × 6 × nv (row-major), poses: N × 16 (optional) |
//! | [`relative_pose_batch`] | q: N × nq | poses (T_B⁻¹ T_A): N × 16 |
//! | [`relative_jacobian_batch`] | q: N × nq | Jacobians: N × 6 × nv, poses (T_B⁻¹ T_A): N × 16 (optional) |

use rayon::prelude::*;

use super::fk::{frame_unchecked, frames_unchecked};
use super::jacobian::{pose_jacobian_unchecked, relative_unchecked};
use super::{TreeKinematics, TreeWorkspace};
use crate::batch::{check_out, finish, rows_of, write_jacobian, CHUNK};
use crate::error::{RowError, SolveError};
use crate::jacobian::JacobianKind;
use screwkit_lie::Se3;

/// One row's work: (workspace, q, base pose, output row, extra output row).
type RowFn<'a> =
    &'a (dyn Fn(&mut TreeWorkspace, &[f64], &Se3, &mut [f64], Option<&mut [f64]>) + Sync);

/// Runs `f` over the rows in parallel chunks of [`CHUNK`] (one chunk on the calling thread);
/// bad rows get NaN and an entry.
fn rows(
    kin: &TreeKinematics,
    qs: &[f64],
    (out, width): (&mut [f64], usize),
    extra: Option<(&mut [f64], usize)>,
    f: RowFn<'_>,
) -> Result<(), SolveError> {
    let nq = kin.nq();
    let n = if nq > 0 {
        rows_of(qs.len(), nq, "configuration values (N × nq)")?
    } else if qs.is_empty() {
        rows_of(out.len(), width, "output values")?
    } else {
        return Err(SolveError::WrongLength {
            what: "configuration values",
            expected: 0,
            got: qs.len(),
            names: "the model has no variables".into(),
        });
    };
    check_out(out.len(), n, width, "output values")?;
    let extra_width = extra.as_ref().map_or(0, |e| e.1);
    if let Some((e, w)) = &extra {
        check_out(e.len(), n, *w, "pose values (N × 16)")?;
    }
    let chunks = n.div_ceil(CHUNK);
    let mut extra_chunks: Vec<Option<&mut [f64]>> = match extra {
        Some((buf, w)) => buf.chunks_mut(CHUNK * w).map(Some).collect(),
        None => Vec::new(),
    };
    extra_chunks.resize_with(chunks, || None);
    let work = |ws: &mut TreeWorkspace,
                (chunk, (o, mut e)): (usize, (&mut [f64], Option<&mut [f64]>))| {
        let mut errors = Vec::new();
        let first = chunk * CHUNK;
        let here = (n - first).min(CHUNK);
        for i in 0..here {
            let q = &qs[(first + i) * nq..(first + i + 1) * nq];
            let row = &mut o[i * width..(i + 1) * width];
            let row_extra = e
                .as_deref_mut()
                .map(|e| &mut e[i * extra_width..(i + 1) * extra_width]);
            match kin.check_q(q) {
                Ok(base) => f(ws, q, &base, row, row_extra),
                Err(error) => {
                    row.fill(f64::NAN);
                    if let Some(x) = row_extra {
                        x.fill(f64::NAN);
                    }
                    errors.push(RowError {
                        row: first + i,
                        error,
                    });
                }
            }
        }
        errors
    };
    // One chunk (at most `INLINE_ROWS` rows) runs on the calling thread: a thread pool's
    // hand-off would cost more than the rows.
    if chunks <= 1 {
        let e = extra_chunks.pop().flatten();
        return finish(TreeWorkspace::local(kin, |ws| work(ws, (0, (out, e)))));
    }
    let errors: Vec<RowError> = out
        .par_chunks_mut(CHUNK * width.max(1))
        .zip(extra_chunks)
        .enumerate()
        .map_init(|| TreeWorkspace::new(kin), work)
        .flatten()
        .collect();
    finish(errors)
}

/// Every frame's pose for N configurations: `poses[16(F k + i)..]` = frame i at q_k.
pub fn fk_frames_batch(
    kin: &TreeKinematics,
    qs: &[f64],
    poses: &mut [f64],
) -> Result<(), SolveError> {
    let width = 16 * kin.frame_count();
    rows(kin, qs, (poses, width), None, &|ws, q, base, out, _| {
        frames_unchecked(kin, ws, q, base);
        for (t, o) in ws.frames.iter().zip(out.chunks_mut(16)) {
            t.write_row_major(o);
        }
    })
}

/// One frame's pose for N configurations (N × 16).
pub fn fk_frame_batch(
    kin: &TreeKinematics,
    frame: usize,
    qs: &[f64],
    poses: &mut [f64],
) -> Result<(), SolveError> {
    kin.check_frame(frame)?;
    rows(kin, qs, (poses, 16), None, &|ws, q, base, out, _| {
        frame_unchecked(kin, ws, q, base, frame).write_row_major(out)
    })
}

/// One frame's Jacobian in `form` for N configurations (N × 6 × nv, row-major), and its pose
/// (N × 16) when `poses` is given.
pub fn frame_jacobian_batch(
    kin: &TreeKinematics,
    frame: usize,
    form: JacobianKind,
    qs: &[f64],
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    kin.check_frame(frame)?;
    jacobian_rows(kin, qs, jacobians, poses, &|ws, q, base| {
        pose_jacobian_unchecked(kin, ws, q, base, frame, form, false)
    })
}

/// Runs `f` (a pose, with the Jacobian left in `ws.jacobian`) over the rows: Jacobians
/// N × 6 × nv, poses N × 16 when given.
fn jacobian_rows(
    kin: &TreeKinematics,
    qs: &[f64],
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
    f: &(dyn Fn(&mut TreeWorkspace, &[f64], &Se3) -> Se3 + Sync),
) -> Result<(), SolveError> {
    rows(
        kin,
        qs,
        (jacobians, 6 * kin.nv()),
        poses.map(|p| (p, 16)),
        &|ws, q, base, out, pose| {
            let t = f(ws, q, base);
            write_jacobian(&ws.jacobian, out);
            if let Some(p) = pose {
                t.write_row_major(p);
            }
        },
    )
}

/// The Jacobian of frame `a` relative to frame `b` in `form` for N configurations
/// (N × 6 × nv), and T_B⁻¹ T_A (N × 16) when `poses` is given.
pub fn relative_jacobian_batch(
    kin: &TreeKinematics,
    (a, b): (usize, usize),
    form: JacobianKind,
    qs: &[f64],
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    kin.check_frame(a)?;
    kin.check_frame(b)?;
    jacobian_rows(kin, qs, jacobians, poses, &|ws, q, base| {
        relative_unchecked(kin, ws, q, base, a, b, form)
    })
}

/// The pose of frame `a` in frame `b` (T_B⁻¹ T_A) for N configurations (N × 16).
pub fn relative_pose_batch(
    kin: &TreeKinematics,
    (a, b): (usize, usize),
    qs: &[f64],
    poses: &mut [f64],
) -> Result<(), SolveError> {
    kin.check_frame(a)?;
    kin.check_frame(b)?;
    rows(kin, qs, (poses, 16), None, &|ws, q, base, out, _| {
        let ta = frame_unchecked(kin, ws, q, base, a);
        let tb = frame_unchecked(kin, ws, q, base, b);
        tb.inverse_compose(&ta).write_row_major(out)
    })
}
