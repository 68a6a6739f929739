//! Batches over many configurations or targets, in parallel with rayon, on flat row-major
//! buffers (so that numpy arrays and memory-mapped files pass without copies):
//!
//! | function | input | output |
//! |---|---|---|
//! | [`fk_batch`] | q: N × dof | poses: N × 16 (each a row-major 4 × 4 `[[R, p], [0, 1]]`) |
//! | [`fk_all_links_batch`] | q: N × dof | poses: N × L × 16 (L links, [`Kinematics::links`] order) |
//! | [`jacobian_batch`] | q: N × dof | Jacobians: N × 6 × dof (row-major, rows (ω, v)), poses: N × 16 (optional) |
//! | [`ik_batch`] | targets: N × 16, seeds: N × dof (optional) | q: N × dof, status: N, times: N (optional) |
//!
//! Every batch function has the shape `batch(&kin, inputs, outputs) -> Result<(), SolveError>`:
//! the workspaces are per worker, inside. A buffer of the wrong length is an error before any
//! work. A bad row (a NaN in q, a target that is not finite) does not stop the others: its
//! output is NaN, every other row is computed, and the call returns [`SolveError::Rows`]
//! listing the bad rows in order. Row k's result equals the single call on row k bit for bit,
//! whatever the number of threads; IK row k uses the restart seed [`row_seed`]`(opts.seed, k)`
//! (with `timeout: None` IK is fully deterministic; a wall-time budget can bind differently
//! under load).

use std::time::Instant;

use nalgebra::Matrix6xX;
use rayon::prelude::*;
use screwkit_lie::lanes::dispatch_lanes;
use screwkit_lie::{Frame, Se3};

use crate::block::{SpaceJacobianBlock, TipBlock, W};
use crate::error::{RowError, SolveError};
use crate::fk::{fk_unchecked, link_poses_unchecked};
use crate::ik::{
    check_options, check_target, solve_unchecked, Clearance, IkOptions, IkStatus, NoBody,
};
use crate::jacobian::{fk_jacobian_into, JacobianKind};
use crate::kinematics::Kinematics;
use crate::sample::SplitMix64;
use crate::workspace::Workspace;

/// Rows per rayon task for the cheap kernels (FK, Jacobians, chain or tree): large enough to
/// amortise scheduling, small enough to balance. A batch of at most this many rows is one task,
/// so it runs on the calling thread, with no thread pool involved: handing it over would cost
/// more than the rows (measured from Python: 18–20 µs, against 0.3 µs per Panda FK row).
pub const INLINE_ROWS: usize = 256;
pub(crate) const CHUNK: usize = INLINE_ROWS;

/// An IK batch of at most this many targets runs on the calling thread, one after another: a
/// solve costs a few µs, and up to this count handing the targets to a pool's threads costs
/// about what sharing them saves (measured on a 2-vCPU virtual machine, from Python: the pool's
/// threads wake 20–60 µs after the hand-off, each; 64 Panda targets took 0.43 ms either way,
/// 16 took 0.15 ms through the pool against 0.11 ms in turn).
pub const IK_INLINE_ROWS: usize = 64;

/// The number of rows of a flat buffer of `len` values with `width` per row.
pub(crate) fn rows_of(len: usize, width: usize, what: &'static str) -> Result<usize, SolveError> {
    if width == 0 || !len.is_multiple_of(width) {
        return Err(SolveError::WrongLength {
            what,
            expected: width * (len / width.max(1)),
            got: len,
            names: format!("a multiple of {width}"),
        });
    }
    Ok(len / width)
}

/// The number of rows of a batch: from q (N × dof), or for a chain without joints (whose q
/// rows are empty) from the output buffer (N × `out_width`).
fn batch_rows(
    kin: &Kinematics,
    qs: &[f64],
    out_len: usize,
    out_width: usize,
) -> Result<usize, SolveError> {
    if kin.dof() > 0 {
        rows_of(qs.len(), kin.dof(), "joint values (N × dof)")
    } else if qs.is_empty() {
        rows_of(out_len, out_width, "output values")
    } else {
        Err(SolveError::WrongLength {
            what: "joint values",
            expected: 0,
            got: qs.len(),
            names: "the chain has no joints".into(),
        })
    }
}

/// An output buffer must hold `rows` × `width` values.
pub(crate) fn check_out(
    len: usize,
    rows: usize,
    width: usize,
    what: &'static str,
) -> Result<(), SolveError> {
    if len == rows * width {
        Ok(())
    } else {
        Err(SolveError::WrongLength {
            what,
            expected: rows * width,
            got: len,
            names: format!("{rows} rows of {width}"),
        })
    }
}

/// Collects the rows that failed (in row order) into [`SolveError::Rows`].
pub(crate) fn finish(errors: Vec<RowError>) -> Result<(), SolveError> {
    if errors.is_empty() {
        Ok(())
    } else {
        Err(SolveError::Rows(errors))
    }
}

/// Runs `f(ws, q_row, out_row, extra_row)` over the rows of `qs` in parallel chunks, the
/// checked rows only; a row that fails the check gets NaN output and an entry in the returned
/// list (in row order). `extra` is an optional second output of `width` values per row.
fn for_each_row(
    kin: &Kinematics,
    rows: usize,
    qs: &[f64],
    (out, out_width): (&mut [f64], usize),
    extra: Option<(&mut [f64], usize)>,
    f: impl Fn(&mut Workspace, &[f64], &mut [f64], Option<&mut [f64]>) + Sync,
) -> Vec<RowError> {
    let n = kin.dof();
    if n == 0 || out_width == 0 {
        // A chain without joints: every row is the same constant work; no row can be bad.
        let mut ws = Workspace::new(kin);
        let extra_width = extra.as_ref().map_or(0, |e| e.1);
        let mut extra = extra.map(|e| e.0);
        for k in 0..rows {
            let e = extra
                .as_deref_mut()
                .map(|e| &mut e[k * extra_width..(k + 1) * extra_width]);
            f(
                &mut ws,
                &qs[k * n..(k + 1) * n],
                &mut out[k * out_width..(k + 1) * out_width],
                e,
            );
        }
        return Vec::new();
    }
    for_each_block(kin, qs, (out, out_width), extra, None, f)
}

/// A block kernel of [`for_each_block`]: W rows of q, their outputs, their extra outputs;
/// false (and nothing written) when a value of q is not finite.
type BlockFn<'a> = &'a (dyn Fn(&[f64], &mut [f64], Option<&mut [f64]>) -> bool + Sync);

/// Rows in parallel chunks (dof > 0): with a `block` kernel, every W = [`W`] consecutive
/// checked rows go through it (the structure-of-arrays kernels, each row bit for bit its
/// single call); other rows (all of them without a block kernel, a block holding a bad row,
/// the last < W rows) through `row` one by one. A bad row gets NaN output and an entry in the
/// returned list (in row order).
fn for_each_block(
    kin: &Kinematics,
    qs: &[f64],
    (out, out_width): (&mut [f64], usize),
    extra: Option<(&mut [f64], usize)>,
    block: Option<BlockFn<'_>>,
    row: impl Fn(&mut Workspace, &[f64], &mut [f64], Option<&mut [f64]>) + Sync,
) -> Vec<RowError> {
    let n = kin.dof();
    let chunks = qs.len().div_ceil(CHUNK * n);
    let extra_width = extra.as_ref().map_or(0, |e| e.1);
    let mut extra_chunks: Vec<Option<&mut [f64]>> = match extra {
        Some((buf, w)) => buf.chunks_mut(CHUNK * w).map(Some).collect(),
        None => (0..chunks).map(|_| None).collect(),
    };
    // One chunk's rows (chunk `chunk`: rows from chunk × CHUNK).
    let work = |ws: &mut Workspace,
                chunk: usize,
                o: &mut [f64],
                mut e: Option<&mut [f64]>,
                q: &[f64]|
     -> Vec<RowError> {
        let mut errors = Vec::new();
        let here = q.len() / n;
        let mut r = 0;
        while r < here {
            let size = (here - r).min(W);
            let rows = |w: usize| r * w..(r + size) * w;
            // The block kernel checks that every value is finite itself, on the vector unit
            // (a pass over the block here, compiled for baseline x86-64, took 2.6 of the FK
            // block's 18 ns per configuration); a block it refuses goes row by row.
            if let (Some(block), true) = (block, size == W) {
                if block(
                    &q[rows(n)],
                    &mut o[rows(out_width)],
                    e.as_deref_mut().map(|e| &mut e[rows(extra_width)]),
                ) {
                    r += size;
                    continue;
                }
            }
            for i in r..r + size {
                let one = |w: usize| i * w..(i + 1) * w;
                let row_extra = e.as_deref_mut().map(|e| &mut e[one(extra_width)]);
                match kin.check_q(&q[one(n)]) {
                    Ok(()) => row(ws, &q[one(n)], &mut o[one(out_width)], row_extra),
                    Err(error) => {
                        o[one(out_width)].fill(f64::NAN);
                        if let Some(x) = row_extra {
                            x.fill(f64::NAN);
                        }
                        errors.push(RowError {
                            row: chunk * CHUNK + i,
                            error,
                        });
                    }
                }
            }
            r += size;
        }
        errors
    };
    // A batch of one chunk (at most CHUNK rows) runs on the calling thread: handing it to the
    // pool and waiting costs more than the rows (a small batch would cost more per row than
    // single calls). The same kernels either way: the rows are bit for bit the same.
    if chunks <= 1 {
        let e = extra_chunks.pop().flatten();
        return Workspace::local(kin, |ws| work(ws, 0, out, e, qs));
    }
    out.par_chunks_mut(CHUNK * out_width)
        .zip(extra_chunks)
        .zip(qs.par_chunks(CHUNK * n))
        .enumerate()
        .map_init(
            || Workspace::new(kin),
            |ws, (chunk, ((o, e), q))| work(ws, chunk, o, e, q),
        )
        .flatten()
        .collect()
}

/// Tip poses of N configurations: `poses[16k..16k+16]` = T(q_k) as a row-major 4 × 4.
/// `qs` holds N × dof values.
pub fn fk_batch(kin: &Kinematics, qs: &[f64], poses: &mut [f64]) -> Result<(), SolveError> {
    let rows = batch_rows(kin, qs, poses.len(), 16)?;
    check_out(poses.len(), rows, 16, "pose values (N × 16)")?;
    let n = kin.dof();
    if n == 0 {
        return finish(for_each_row(
            kin,
            rows,
            qs,
            (poses, 16),
            None,
            |_, q, out, _| fk_unchecked(kin, q).write_row_major(out),
        ));
    }
    finish(for_each_block(
        kin,
        qs,
        (poses, 16),
        None,
        Some(&|q, out, _| dispatch_lanes(TipBlock { kin, qs: q, out })),
        |_, q, out, _| fk_unchecked(kin, q).write_row_major(out),
    ))
}

/// Every link's pose for N configurations: `poses[16(L k + i)..]` = pose of link i (in the order
/// of [`Kinematics::links`]) at q_k, row-major 4 × 4. `qs` holds N × dof values.
pub fn fk_all_links_batch(
    kin: &Kinematics,
    qs: &[f64],
    poses: &mut [f64],
) -> Result<(), SolveError> {
    let links = kin.links().len();
    let rows = batch_rows(kin, qs, poses.len(), 16 * links)?;
    check_out(
        poses.len(),
        rows,
        16 * links,
        "pose values (N × links × 16)",
    )?;
    finish(for_each_row(
        kin,
        rows,
        qs,
        (poses, 16 * links),
        None,
        |ws, q, out, _| {
            link_poses_unchecked(kin, &mut ws.link_columns, &mut ws.links, q);
            for (t, o) in ws.links.iter().zip(out.chunks_mut(16)) {
                t.write_row_major(o);
            }
        },
    ))
}

/// Jacobians of `kind` of N configurations: `jacobians[6n·k..6n·(k+1)]` = J(q_k), row-major
/// 6 × n (rows (ω, v)); with `poses`, also the tip poses (N × 16) from the same pass. Row k
/// equals [`crate::jacobian::jacobian`] on row k bit for bit.
pub fn jacobian_batch(
    kin: &Kinematics,
    qs: &[f64],
    kind: impl Into<JacobianKind>,
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    match kind.into() {
        JacobianKind::WorldAligned => world_aligned_batch(kin, qs, jacobians, poses),
        kind => screw_jacobian_batch(kin, qs, kind.pass(), jacobians, poses),
    }
}

/// [`jacobian_batch`] of the space or body kind (`frame`).
fn screw_jacobian_batch(
    kin: &Kinematics,
    qs: &[f64],
    frame: Frame,
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    let n = kin.dof();
    let rows = match &poses {
        Some(p) if n == 0 => batch_rows(kin, qs, p.len(), 16)?,
        _ => rows_of(qs.len(), n, "joint values (N × dof)")?,
    };
    check_out(
        jacobians.len(),
        rows,
        6 * n,
        "Jacobian values (N × 6 × dof)",
    )?;
    if let Some(p) = &poses {
        check_out(p.len(), rows, 16, "pose values (N × 16)")?;
    }
    let poses = poses.map(|p| (p, 16));
    let single =
        |ws: &mut Workspace, q: &[f64], j_out: &mut [f64], pose_out: Option<&mut [f64]>| {
            let t = fk_jacobian_into(kin, &mut ws.jacobian, q, frame);
            write_jacobian(&ws.jacobian, j_out);
            if let Some(p) = pose_out {
                t.write_row_major(p);
            }
        };
    if frame == Frame::Space && kin.identity_map && n > 0 {
        // W configurations at a time (each row bit for bit the single call).
        return finish(for_each_block(
            kin,
            qs,
            (jacobians, 6 * n),
            poses,
            Some(&|q, jac, poses| {
                dispatch_lanes(SpaceJacobianBlock {
                    kin,
                    qs: q,
                    jac,
                    poses,
                })
            }),
            single,
        ));
    }
    finish(for_each_row(
        kin,
        rows,
        qs,
        (jacobians, 6 * n),
        poses,
        single,
    ))
}

/// Tip-point Jacobians in base axes of N configurations: [`jacobian_batch`] with
/// [`JacobianKind::WorldAligned`].
#[deprecated(note = "use `jacobian_batch(kin, qs, JacobianKind::WorldAligned, jacobians, poses)`")]
pub fn jacobian_world_aligned_batch(
    kin: &Kinematics,
    qs: &[f64],
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    jacobian_batch(kin, qs, JacobianKind::WorldAligned, jacobians, poses)
}

/// The world-aligned kind of [`jacobian_batch`]: the space batch, then each column moved to
/// the tip point ([`crate::jacobian::space_to_world_aligned`]), as the single call does.
fn world_aligned_batch(
    kin: &Kinematics,
    qs: &[f64],
    jacobians: &mut [f64],
    poses: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    let n = kin.dof();
    let mut own = Vec::new();
    let poses = match poses {
        Some(p) => p,
        None => {
            own.resize(jacobians.len() / (6 * n).max(1) * 16, 0.0);
            &mut own[..]
        }
    };
    let result = screw_jacobian_batch(kin, qs, Frame::Space, jacobians, Some(&mut *poses));
    if n > 0 {
        let to_world_aligned = |(j, t): (&mut [f64], &[f64])| {
            let p = nalgebra::Vector3::new(t[3], t[7], t[11]);
            for c in 0..n {
                let mut col = [0.0; 6];
                for (r, x) in col.iter_mut().enumerate() {
                    *x = j[r * n + c];
                }
                crate::jacobian::space_to_world_aligned(&mut col, &p);
                for (r, x) in col.iter().enumerate() {
                    j[r * n + c] = *x;
                }
            }
        };
        // A small batch on the calling thread, as `for_each_block` runs it.
        if jacobians.len() <= CHUNK * 6 * n {
            jacobians
                .chunks_mut(6 * n)
                .zip(poses.chunks(16))
                .for_each(to_world_aligned);
        } else {
            jacobians
                .par_chunks_mut(6 * n)
                .zip(poses.par_chunks(16))
                .for_each(to_world_aligned);
        }
    }
    result
}

/// Writes a 6 × n Jacobian row-major into 6n values: the layout of [`jacobian_batch`]'s rows.
#[inline]
pub fn write_jacobian(j: &Matrix6xX<f64>, out: &mut [f64]) {
    let n = j.ncols();
    for r in 0..6 {
        for c in 0..n {
            out[r * n + c] = j[(r, c)];
        }
    }
}

/// The restart seed of row `index` of a batch: IK row k of a batch with `opts.seed = s` equals
/// the single solve with `opts.seed = row_seed(s, k)`.
pub fn row_seed(seed: u64, index: usize) -> u64 {
    let mut g = SplitMix64(seed ^ (index as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
    g.next_u64()
}

/// IK for N targets (`targets`: N × 16, each a row-major 4 × 4 whose rotation is trusted, as
/// [`Se3`]'s checked constructors or an FK output give it), from `seeds` (N × dof; `None`: the
/// midpoint of the limits). Writes the solutions into `q` (N × dof) and how each solve ended
/// into `status` (N), and with `times_us` each solve's wall time in µs (the one output that
/// differs between runs). Row k uses restart seed [`row_seed`]`(opts.seed, k)`. A target row that
/// is not finite or not a rigid transform, or a seed row with NaN, fails alone (NaN q,
/// [`IkStatus::unsolved`]); a row that does not converge is not a failure (its status
/// says so).
pub fn ik_batch(
    kin: &Kinematics,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    q: &mut [f64],
    status: &mut [IkStatus],
    times_us: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    ik_batch_from(kin, 0, targets, seeds, opts, q, status, times_us)
}

/// [`ik_batch`] for rows `first_row`, `first_row + 1`, … of a larger batch streamed in pieces:
/// row k of this call restarts from [`row_seed`]`(opts.seed, first_row + k)`, so the pieces give
/// what one call on the whole batch gives. Failed rows are reported by their index in this
/// call.
#[allow(clippy::too_many_arguments)]
pub fn ik_batch_from(
    kin: &Kinematics,
    first_row: usize,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    q: &mut [f64],
    status: &mut [IkStatus],
    times_us: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    ik_rows_from(
        kin, first_row, targets, seeds, opts, &NoBody, q, status, times_us,
    )
}

/// [`ik_batch_from`] keeping clear of contact: each row solved by [`crate::ik::solve_clear`]
/// with `body` (one scratch of the body per worker; `times_us` as in [`ik_batch`]). Row k equals the single call with
/// restart seed [`row_seed`]`(opts.seed, first_row + k)`, whatever the thread count.
#[allow(clippy::too_many_arguments)]
pub fn ik_batch_clear_from<B: Clearance>(
    kin: &Kinematics,
    first_row: usize,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    body: &B,
    q: &mut [f64],
    status: &mut [IkStatus],
    times_us: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    ik_rows_from(
        kin, first_row, targets, seeds, opts, body, q, status, times_us,
    )
}

/// The batch of [`ik_batch_from`] with a body.
#[allow(clippy::too_many_arguments)]
fn ik_rows_from<B: Clearance>(
    kin: &Kinematics,
    first_row: usize,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    body: &B,
    q: &mut [f64],
    status: &mut [IkStatus],
    times_us: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    let rows = check_ik_batch(kin, targets, seeds, opts, q, status, times_us.as_deref())?;
    let batch = IkRows::new(
        kin,
        first_row,
        targets,
        seeds,
        opts,
        body,
        times_us.is_some(),
    );
    if rows <= IK_INLINE_ROWS {
        let mut bs = body.scratch();
        return Workspace::local(kin, |ws| batch.in_turn(ws, &mut bs, q, status, times_us));
    }
    let n = kin.dof();
    let mut no_times = Vec::new();
    let times = match times_us {
        Some(t) => t,
        None => {
            no_times.resize(rows, 0.0);
            &mut no_times[..]
        }
    };
    // A chain without joints has empty q rows; give the row iterator one dummy value per row.
    let mut no_q = Vec::new();
    let q = if n == 0 {
        no_q.resize(rows, 0.0);
        &mut no_q[..]
    } else {
        q
    };
    let errors: Vec<RowError> = q
        .par_chunks_mut(n.max(1))
        .zip(status.par_iter_mut())
        .zip(times.par_iter_mut())
        .enumerate()
        // Four targets per task: IK costs are heavy-tailed (a restart can cost 10× a median
        // solve), so coarse chunks leave one worker finishing alone; at four a straggler costs
        // a few solves, and the task overhead of one target per task (measured +3–6 % on one
        // thread against a loop of single solves) shrinks fourfold.
        .with_max_len(4)
        .map_init(
            || (Workspace::new(kin), body.scratch()),
            |(ws, bs), (k, ((q_row, st), time))| {
                let (error, took) = batch.row(ws, bs, k, &mut q_row[..n], st);
                *time = took;
                error
            },
        )
        .flatten()
        .collect();
    finish(errors)
}

/// [`ik_batch_from`] solved in turn on the calling thread, in the caller's workspace: no thread
/// pool, no workspace made. What a front end holding a workspace runs for a batch of at most
/// [`IK_INLINE_ROWS`] targets; each row's answer is the one [`ik_batch_from`] gives.
#[allow(clippy::too_many_arguments)]
pub fn ik_batch_in(
    kin: &Kinematics,
    ws: &mut Workspace,
    first_row: usize,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    q: &mut [f64],
    status: &mut [IkStatus],
    times_us: Option<&mut [f64]>,
) -> Result<(), SolveError> {
    check_ik_batch(kin, targets, seeds, opts, q, status, times_us.as_deref())?;
    ws.fit(kin);
    IkRows::new(
        kin,
        first_row,
        targets,
        seeds,
        opts,
        &NoBody,
        times_us.is_some(),
    )
    .in_turn(ws, &mut (), q, status, times_us)
}

/// The checks of an IK batch's buffers and options; its number of rows.
fn check_ik_batch(
    kin: &Kinematics,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    q: &[f64],
    status: &[IkStatus],
    times_us: Option<&[f64]>,
) -> Result<usize, SolveError> {
    let n = kin.dof();
    check_options(opts)?;
    let rows = rows_of(targets.len(), 16, "target values (N × 16)")?;
    if let Some(s) = seeds {
        check_out(s.len(), rows, n, "seed values (N × dof)")?;
    }
    check_out(q.len(), rows, n, "solution values (N × dof)")?;
    check_out(status.len(), rows, 1, "status entries (N)")?;
    if let Some(t) = times_us {
        check_out(t.len(), rows, 1, "times (N)")?;
    }
    Ok(rows)
}

/// What every row of an IK batch shares: the chain, the rows' inputs, the options, the body.
struct IkRows<'a, B: Clearance> {
    kin: &'a Kinematics,
    first_row: usize,
    targets: &'a [f64],
    seeds: Option<&'a [f64]>,
    opts: &'a IkOptions,
    body: &'a B,
    /// The seed of rows without one: the middle of the limits.
    mid: Vec<f64>,
    timed: bool,
}

impl<'a, B: Clearance> IkRows<'a, B> {
    fn new(
        kin: &'a Kinematics,
        first_row: usize,
        targets: &'a [f64],
        seeds: Option<&'a [f64]>,
        opts: &'a IkOptions,
        body: &'a B,
        timed: bool,
    ) -> Self {
        Self {
            kin,
            first_row,
            targets,
            seeds,
            opts,
            body,
            mid: kin.midpoint(),
            timed,
        }
    }

    /// Row k solved into `q_row` and `st`: the row's error when its target or seed is bad (NaN
    /// q, [`IkStatus::unsolved`]), and the solve's wall time in µs when timed (else 0).
    fn row(
        &self,
        ws: &mut Workspace,
        bs: &mut B::Scratch,
        k: usize,
        q_row: &mut [f64],
        st: &mut IkStatus,
    ) -> (Option<RowError>, f64) {
        let (kin, n) = (self.kin, self.kin.dof());
        let seed = self
            .seeds
            .map_or(self.mid.as_slice(), |s| &s[k * n..(k + 1) * n]);
        let row = target_row(&self.targets[16 * k..16 * (k + 1)])
            .and_then(|t| kin.check_q(seed).map(|()| t));
        match row {
            Ok(target) => {
                let o = IkOptions {
                    seed: row_seed(self.opts.seed, self.first_row + k),
                    ..self.opts.clone()
                };
                if self.timed {
                    let t0 = Instant::now();
                    *st = solve_unchecked(kin, ws, &target, seed, &o, (self.body, &mut *bs), q_row);
                    (None, t0.elapsed().as_secs_f64() * 1e6)
                } else {
                    *st = solve_unchecked(kin, ws, &target, seed, &o, (self.body, &mut *bs), q_row);
                    (None, 0.0)
                }
            }
            Err(error) => {
                q_row.fill(f64::NAN);
                *st = IkStatus::unsolved();
                (Some(RowError { row: k, error }), 0.0)
            }
        }
    }

    /// Every row in turn on this thread, in `ws`.
    fn in_turn(
        &self,
        ws: &mut Workspace,
        bs: &mut B::Scratch,
        q: &mut [f64],
        status: &mut [IkStatus],
        mut times_us: Option<&mut [f64]>,
    ) -> Result<(), SolveError> {
        let n = self.kin.dof();
        let mut errors = Vec::new();
        for (k, st) in status.iter_mut().enumerate() {
            let (error, took) = self.row(ws, bs, k, &mut q[k * n..(k + 1) * n], st);
            if let Some(t) = times_us.as_deref_mut() {
                t[k] = took;
            }
            errors.extend(error);
        }
        finish(errors)
    }
}

/// A target row as an [`Se3`]: finite, last row (0, 0, 0, 1), rotation orthonormal to 1e-6
/// (a rotation orthonormal to 1e-14, as FK gives, is used exactly as given; a looser one is
/// projected onto SO(3) first, [`Se3::from_row_major`]).
pub(crate) fn target_row(v: &[f64]) -> Result<Se3, SolveError> {
    let t = Se3::from_row_major(v, screwkit_lie::so3::TARGET_ROTATION_TOLERANCE)
        .map_err(|e| SolveError::BadTarget(e.into()))?;
    check_target(&t)?;
    Ok(t)
}

/// IK along a path: target k is seeded with the solution of target k − 1 when that converged
/// (warm start), the first with `seed`; restart seeds as in [`ik_batch`]. Sequential by nature.
pub fn ik_path(
    kin: &Kinematics,
    ws: &mut Workspace,
    targets: &[Se3],
    seed: &[f64],
    opts: &IkOptions,
) -> Result<Vec<crate::ik::IkResult>, SolveError> {
    ik_path_from(kin, ws, 0, targets, seed, opts)
}

/// [`ik_path`] for targets `first_row`, `first_row + 1`, … of a longer path streamed in pieces
/// (restart seeds as in [`ik_batch_from`]; the caller carries the warm start across pieces by
/// passing the last converged solution as `seed`).
pub fn ik_path_from(
    kin: &Kinematics,
    ws: &mut Workspace,
    first_row: usize,
    targets: &[Se3],
    seed: &[f64],
    opts: &IkOptions,
) -> Result<Vec<crate::ik::IkResult>, SolveError> {
    ik_path_clear_from(kin, ws, first_row, targets, seed, opts, &NoBody, &mut ())
}

/// [`ik_path_from`] keeping clear of contact (each target by [`crate::ik::solve_clear`] with
/// `body` and its `scratch`).
#[allow(clippy::too_many_arguments)]
pub fn ik_path_clear_from<B: Clearance>(
    kin: &Kinematics,
    ws: &mut Workspace,
    first_row: usize,
    targets: &[Se3],
    seed: &[f64],
    opts: &IkOptions,
    body: &B,
    scratch: &mut B::Scratch,
) -> Result<Vec<crate::ik::IkResult>, SolveError> {
    kin.check_q(seed)?;
    check_options(opts)?;
    for (k, t) in targets.iter().enumerate() {
        check_target(t).map_err(|error| SolveError::Rows(vec![RowError { row: k, error }]))?;
    }
    ws.fit(kin);
    let mut q = seed.to_vec();
    let mut out = Vec::with_capacity(targets.len());
    for (k, target) in targets.iter().enumerate() {
        let o = IkOptions {
            seed: row_seed(opts.seed, first_row + k),
            ..opts.clone()
        };
        let mut sol = vec![0.0; kin.dof()];
        let status = solve_unchecked(kin, ws, target, &q, &o, (body, &mut *scratch), &mut sol);
        if status.converged {
            q.copy_from_slice(&sol);
        }
        out.push(crate::ik::IkResult { q: sol, status });
    }
    Ok(out)
}
