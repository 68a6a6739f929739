//! Batched kernels per configuration, next to a loop of single calls on the same rows writing
//! the same outputs, in one run (interleaved rounds, minimum kept), at two sizes (in cache and
//! streaming to memory, see `SIZES`): tip FK (`fk_batch`, the block kernel), FK + space
//! Jacobian (`jacobian_batch` with poses), on 1 and 2 threads, for the
//! bundled Panda and iiwa14 and, when `SCREWKIT_SHARED_URDF` names the CI data, pybullet's Panda;
//! then IK (`ik_batch`, 2000 targets, no clock) against a loop of single solves.
//! Run: `cargo bench -p screwkit-solve --bench batch_kernels`.

use std::time::Instant;

use screwkit_lie::Se3;
use screwkit_solve::batch::{fk_batch, ik_batch, jacobian_batch, row_seed, write_jacobian};
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve, IkOptions, IkStatus};
use screwkit_solve::jacobian::fk_jacobian;
use screwkit_solve::{Frame, Kinematics, Workspace};

/// The two sizes measured. In cache: 2,048 rows (the FK + J outputs, 0.9 MB for a 7-joint
/// chain, stay in L2), the call repeated; what the kernels cost. Streaming: 100,000 rows, whose
/// outputs (46 MB) go to memory; there both sides write the same outputs, so the loop of single
/// calls stores each result into the batch's layout as a caller would.
const SIZES: [(&str, usize, usize); 2] = [("in cache", 2_048, 50), ("streaming", 100_000, 1)];

/// One chain's rows, buffers and best times (ns per configuration) per size: FK single, batch 1
/// and 2 threads, FK + J single, batch 1 and 2 threads.
struct Case {
    name: &'static str,
    kin: Kinematics,
    qs: Vec<f64>,
    poses: Vec<f64>,
    jac: Vec<f64>,
    best: [[f64; 6]; 2],
}

impl Case {
    fn new(name: &'static str, kin: Kinematics) -> Self {
        let n = kin.dof();
        let rows = SIZES[1].1;
        Self {
            name,
            qs: screwkit_solve::sample::configurations(&kin, rows, 3),
            poses: vec![0.0; rows * 16],
            jac: vec![0.0; rows * 6 * n],
            kin,
            best: [[f64::INFINITY; 6]; 2],
        }
    }

    /// One round of the six measurements at each size; the minimum over rounds is kept.
    fn round(&mut self, pools: &[rayon::ThreadPool]) {
        let (kin, n) = (&self.kin, self.kin.dof());
        let mut ws = Workspace::new(kin);
        for (size, &(_, rows, reps)) in SIZES.iter().enumerate() {
            let qs = &self.qs[..rows * n];
            let (poses, jac) = (&mut self.poses[..rows * 16], &mut self.jac[..rows * 6 * n]);
            let per = |t0: Instant| t0.elapsed().as_secs_f64() / (rows * reps) as f64 * 1e9;
            let best = &mut self.best[size];
            let t0 = Instant::now();
            for _ in 0..reps {
                for k in 0..rows {
                    let t = fk(kin, &mut ws, &qs[k * n..(k + 1) * n]).unwrap();
                    t.write_row_major(&mut poses[16 * k..16 * (k + 1)]);
                }
            }
            best[0] = best[0].min(per(t0));
            for (i, pool) in pools.iter().enumerate() {
                let t0 = Instant::now();
                // The repetitions inside one `install`: waking the pool's thread from outside
                // costs tens of µs on some hosts, which is not the kernels' cost.
                pool.install(|| {
                    for _ in 0..reps {
                        fk_batch(kin, qs, poses).unwrap();
                    }
                });
                best[1 + i] = best[1 + i].min(per(t0));
            }
            let t0 = Instant::now();
            for _ in 0..reps {
                for k in 0..rows {
                    let out =
                        fk_jacobian(kin, &mut ws, &qs[k * n..(k + 1) * n], Frame::Space).unwrap();
                    out.pose.write_row_major(&mut poses[16 * k..16 * (k + 1)]);
                    write_jacobian(out.jacobian, &mut jac[6 * n * k..6 * n * (k + 1)]);
                }
            }
            best[3] = best[3].min(per(t0));
            for (i, pool) in pools.iter().enumerate() {
                let t0 = Instant::now();
                pool.install(|| {
                    for _ in 0..reps {
                        jacobian_batch(kin, qs, Frame::Space, jac, Some(&mut *poses)).unwrap();
                    }
                });
                best[4 + i] = best[4 + i].min(per(t0));
            }
        }
    }

    fn print(&self) {
        for (size, &(label, rows, _)) in SIZES.iter().enumerate() {
            let b = &self.best[size];
            println!(
                "{:<15} {label:<9} FK: single {:6.1} ns, batch 1 thread {:6.1} ns ({:.2}x single), 2 threads {:6.1} ns | FK+J: single {:6.1} ns, batch 1 thread {:6.1} ns ({:.2}x single), 2 threads {:6.1} ns",
                self.name, b[0], b[1], b[1] / b[0], b[2], b[3], b[4], b[4] / b[3], b[5]
            );
            // One machine-readable line per chain and size (the minimum over the rounds).
            println!(
                "RESULT chain={} rows={rows} fk_single_ns={:.2} fk_batch1_ns={:.2} fk_batch2_ns={:.2} fkj_single_ns={:.2} fkj_batch1_ns={:.2} fkj_batch2_ns={:.2}",
                self.name, b[0], b[1], b[2], b[3], b[4], b[5]
            );
        }
    }
}

/// The chains measured in the same rounds (interleaved), so their ratios are of one moment.
fn kernels(cases: &mut [Case]) {
    let pools: Vec<_> = [1usize, 2]
        .iter()
        .map(|&t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
        })
        .collect();
    for _ in 0..9 {
        for case in cases.iter_mut() {
            case.round(&pools);
        }
    }
    for case in cases.iter() {
        case.print();
    }
    // pybullet's Panda (axes written with a rounded π/2) against the bundled one, in cache.
    if let [panda, .., pb] = cases {
        if pb.name == "panda_pybullet" {
            let r = |k: usize| pb.best[0][k] / panda.best[0][k];
            println!(
                "panda_pybullet / panda (in cache): FK single {:.3}, batch {:.3} | FK+J single {:.3}, batch {:.3}",
                r(0),
                r(1),
                r(3),
                r(4)
            );
        }
    }
}

fn ik(name: &str, kin: &Kinematics) {
    let rows = 2000;
    let n = kin.dof();
    let qs = screwkit_solve::sample::configurations(kin, rows, 5);
    let mut targets = vec![0.0; rows * 16];
    fk_batch(kin, &qs, &mut targets).unwrap();
    let opts = IkOptions {
        timeout: None,
        ..IkOptions::default()
    };
    let mut ws = Workspace::new(kin);
    let (mut q, mut status) = (vec![0.0; rows * n], vec![IkStatus::default(); rows]);
    let mid = kin.midpoint();
    let mut best = [f64::INFINITY; 3];
    let per = |t0: Instant| t0.elapsed().as_secs_f64() / rows as f64 * 1e6;
    for _ in 0..5 {
        let t0 = Instant::now();
        for k in 0..rows {
            let t = Se3::from_row_major(&targets[16 * k..16 * (k + 1)], 1e-6).unwrap();
            let o = IkOptions {
                seed: row_seed(opts.seed, k),
                ..opts.clone()
            };
            std::hint::black_box(solve(kin, &mut ws, &t, &mid, &o).unwrap());
        }
        best[0] = best[0].min(per(t0));
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let t0 = Instant::now();
            pool.install(|| {
                ik_batch(kin, &targets, None, &opts, &mut q, &mut status, None).unwrap()
            });
            best[threads] = best[threads].min(per(t0));
        }
    }
    println!(
        "{name:<15} IK: single loop {:6.2} µs, batch 1 thread {:6.2} µs, 2 threads {:6.2} µs ({:.2}x); host: {:.2}x",
        best[0], best[1], best[2], best[1] / best[2], host_scaling()
    );
}

/// What 2 threads give on this host right now: the same fixed arithmetic (no memory traffic,
/// no sharing) on 1 and then 2 threads of one pool, best of 5 rounds, as work per second on 2
/// threads over 1. A shared host whose second core is busy, or whose two vCPUs are one core's
/// two hyperthreads at that moment, shows it here, next to the IK batch's own ratio.
fn host_scaling() -> f64 {
    // Eight independent multiply-add chains: throughput-bound like the kernels, so two threads
    // that share one physical core (SMT siblings) show it.
    let work = |seed: f64| {
        let mut x = [seed; 8];
        for _ in 0..4_000_000 {
            for (k, v) in x.iter_mut().enumerate() {
                *v = v.mul_add(0.999_999_9, 1e-9 * k as f64);
            }
        }
        std::hint::black_box(x)
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let (mut one, mut two) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..5 {
        let t0 = Instant::now();
        pool.install(|| work(1.0));
        one = one.min(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        pool.install(|| rayon::join(|| work(1.0), || work(2.0)));
        two = two.min(t0.elapsed().as_secs_f64());
    }
    2.0 * one / two
}

fn main() {
    println!("host: {}", screwkit_testkit::protocol::host());
    let load = |f: &str, b: Option<&str>, t: Option<&str>| {
        Kinematics::new(&screwkit_model::load_chain(f, b, t).unwrap())
    };
    let mut cases = vec![
        Case::new(
            "panda",
            load(&screwkit_testkit::bundled("panda.urdf"), None, None),
        ),
        Case::new(
            "iiwa14",
            load(&screwkit_testkit::bundled("iiwa14.urdf"), None, None),
        ),
    ];
    // pybullet's Panda from the CI data, when SCREWKIT_SHARED_URDF names it.
    if let Some(pb) = std::env::var_os("SCREWKIT_SHARED_URDF")
        .map(|d| std::path::Path::new(&d).join("panda_pybullet.urdf"))
        .filter(|p| p.exists())
    {
        let pb = pb.to_str().expect("a UTF-8 path");
        cases.push(Case::new(
            "panda_pybullet",
            load(pb, Some("panda_link0"), Some("panda_hand")),
        ));
    }
    kernels(&mut cases);
    ik(
        "panda",
        &load(&screwkit_testkit::bundled("panda.urdf"), None, None),
    );
    ik(
        "ur5",
        &load(&screwkit_testkit::bundled("ur5.urdf"), None, None),
    );
}
