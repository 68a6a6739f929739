//! The IK benchmark protocol of BENCHMARKS.md, shared by `screwkit bench` and the benches:
//! q* uniform within the limits (continuous joints in [−π, π]) from a fixed seed,
//! target = FK(q*), initial guess = the midpoint of the limits (0 for continuous), success =
//! rotation error ≤ 1e-5 rad and position error ≤ 1e-5 m checked by an FK call independent of
//! the solver's bookkeeping, with the solution within limits; every query timed, failures
//! included.

use std::time::Instant;

use screwkit_solve::batch::row_seed;
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve_into, IkOptions};
use screwkit_solve::jacobian::fk_jacobian;
use screwkit_solve::sample::configurations;
use screwkit_solve::{Frame, Kinematics, Workspace};

/// Success thresholds of the protocol.
pub const SUCCESS_ROT: f64 = 1e-5;
/// Success thresholds of the protocol.
pub const SUCCESS_POS: f64 = 1e-5;

/// Results of [`run`].
#[derive(Debug, Clone, PartialEq)]
pub struct ProtocolReport {
    /// Queries run.
    pub queries: usize,
    /// Queries that met the success criterion.
    pub solved: usize,
    /// Mean wall time per query (µs).
    pub mean_us: f64,
    /// Median wall time (µs).
    pub median_us: f64,
    /// 99th percentile wall time (µs).
    pub p99_us: f64,
    /// Mean solver iterations per query.
    pub mean_iterations: f64,
    /// FK of the tip, ns per call (mean over the query configurations).
    pub fk_ns: f64,
    /// FK + space Jacobian, ns per call.
    pub jacobian_ns: f64,
}

impl ProtocolReport {
    /// solved / queries.
    pub fn solve_rate(&self) -> f64 {
        if self.queries == 0 {
            0.0
        } else {
            self.solved as f64 / self.queries as f64
        }
    }
}

/// The protocol's wall-time cap per query (TRAC-IK's default): what `screwkit bench` and the
/// benches give IK, so their figures compare with the peers'.
pub const TIME_CAP: std::time::Duration = std::time::Duration::from_millis(5);

/// Runs the protocol with `queries` targets drawn from `seed`, solving with `opts`.
pub fn run(kin: &Kinematics, queries: usize, seed: u64, opts: &IkOptions) -> ProtocolReport {
    let n = kin.dof();
    let qs = configurations(kin, queries, seed);
    let mut ws = Workspace::new(kin);
    let mid = kin.midpoint();
    let mut times = Vec::with_capacity(queries);
    let (mut solved, mut iterations) = (0usize, 0usize);
    let mut sol = vec![0.0; n];
    for (k, q_star) in qs.chunks(n.max(1)).enumerate().take(queries) {
        let target = fk(kin, &mut ws, q_star).expect("sampled within limits");
        let o = IkOptions {
            seed: row_seed(opts.seed, k),
            ..opts.clone()
        };
        let t0 = Instant::now();
        let r = solve_into(kin, &mut ws, &target, &mid, &o, &mut sol);
        times.push(t0.elapsed().as_secs_f64() * 1e6);
        if let Ok(status) = r {
            iterations += status.iterations;
            let t = fk(kin, &mut ws, &sol).expect("solutions are finite");
            let d = t.inverse_compose(&target);
            let rot = screwkit_lie::so3::log(d.rotation()).norm();
            let pos = (t.translation() - target.translation()).norm();
            if rot <= SUCCESS_ROT && pos <= SUCCESS_POS && kin.within_limits(&sol, 0.0) {
                solved += 1;
            }
        }
    }
    // Per-call FK and FK+J costs over the same configurations (the public, checked calls).
    // About 20,000 timed calls of each kind.
    let reps = (20_000 / queries.max(1)).max(1);
    let t0 = Instant::now();
    let mut sink = 0.0;
    for _ in 0..reps {
        for q in qs.chunks(n.max(1)) {
            sink += fk(kin, &mut ws, q).map_or(0.0, |t| t.translation().x);
        }
    }
    let fk_ns = t0.elapsed().as_secs_f64() * 1e9 / (reps * queries.max(1)) as f64;
    let t0 = Instant::now();
    for _ in 0..reps {
        for q in qs.chunks(n.max(1)) {
            sink +=
                fk_jacobian(kin, &mut ws, q, Frame::Space).map_or(0.0, |r| r.pose.translation().y);
        }
    }
    let jacobian_ns = t0.elapsed().as_secs_f64() * 1e9 / (reps * queries.max(1)) as f64;
    std::hint::black_box(sink);
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let pick = |p: f64| {
        if sorted.is_empty() {
            0.0
        } else {
            sorted[((sorted.len() as f64 * p) as usize).min(sorted.len() - 1)]
        }
    };
    ProtocolReport {
        queries,
        solved,
        mean_us: if queries > 0 {
            times.iter().sum::<f64>() / queries as f64
        } else {
            0.0
        },
        median_us: pick(0.5),
        p99_us: pick(0.99),
        mean_iterations: if queries > 0 {
            iterations as f64 / queries as f64
        } else {
            0.0
        },
        fk_ns,
        jacobian_ns,
    }
}

/// Where a benchmark runs, in one line: the CPU's model (Linux's `/proc/cpuinfo`), whether it
/// has AVX-512, its hardware threads and the kernel path chosen
/// ([`screwkit_lie::fma::kernel_path`]). Figures are only comparable on one host class.
pub fn host() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    #[cfg(target_arch = "x86_64")]
    let avx512 = std::arch::is_x86_feature_detected!("avx512f");
    #[cfg(not(target_arch = "x86_64"))]
    let avx512 = false;
    format!(
        "{model}{}, {} hardware threads, kernels {}",
        if avx512 { " (AVX-512)" } else { "" },
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        screwkit_lie::fma::kernel_path()
    )
}
