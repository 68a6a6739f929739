//! Batched kernels per configuration, next to a loop of single calls on the same rows, in one
//! run (interleaved rounds, minimum kept): tip FK (`fk_batch`, the structure-of-arrays block
//! kernel), FK + space Jacobian (`jacobian_batch` with poses), on 1 and 2 threads, for the
//! bundled Panda and iiwa14 and, when ../shared/urdf is beside the clone, pybullet's Panda;
//! then IK (`ik_batch`, 2000 targets, no clock) against a loop of single solves.
//! Run: `cargo bench -p screwkit-solve --bench batch_kernels`.

use std::time::Instant;

use screwkit_lie::Se3;
use screwkit_solve::batch::{fk_batch, ik_batch, jacobian_batch, row_seed};
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve, IkOptions, IkStatus};
use screwkit_solve::jacobian::fk_jacobian;
use screwkit_solve::{Frame, Kinematics, Workspace};

fn bench(name: &str, kin: &Kinematics) {
    let rows = 100_000;
    let n = kin.dof();
    let qs = screwkit_solve::sample::configurations(kin, rows, 3);
    let mut poses = vec![0.0; rows * 16];
    let mut jac = vec![0.0; rows * 6 * n];
    let mut ws = Workspace::new(kin);
    let pools: Vec<_> = [1usize, 2]
        .iter()
        .map(|&t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
        })
        .collect();
    let mut best = [f64::INFINITY; 6];
    let per = |t0: Instant| t0.elapsed().as_secs_f64() / rows as f64 * 1e9;
    for _ in 0..7 {
        let t0 = Instant::now();
        for k in 0..rows {
            std::hint::black_box(fk(kin, &mut ws, &qs[k * n..(k + 1) * n]).unwrap());
        }
        best[0] = best[0].min(per(t0));
        for (i, pool) in pools.iter().enumerate() {
            let t0 = Instant::now();
            pool.install(|| fk_batch(kin, &qs, &mut poses).unwrap());
            best[1 + i] = best[1 + i].min(per(t0));
        }
        let t0 = Instant::now();
        for k in 0..rows {
            std::hint::black_box(
                fk_jacobian(kin, &mut ws, &qs[k * n..(k + 1) * n], Frame::Space)
                    .unwrap()
                    .pose,
            );
        }
        best[3] = best[3].min(per(t0));
        for (i, pool) in pools.iter().enumerate() {
            let t0 = Instant::now();
            pool.install(|| {
                jacobian_batch(kin, &qs, Frame::Space, &mut jac, Some(&mut poses)).unwrap()
            });
            best[4 + i] = best[4 + i].min(per(t0));
        }
    }
    println!(
        "{name:<15} FK: single {:6.1} ns, batch 1 thread {:6.1} ns, 2 threads {:6.1} ns ({:.2}x) | FK+J: single {:6.1} ns, batch 1 thread {:6.1} ns, 2 threads {:6.1} ns ({:.2}x)",
        best[0], best[1], best[2], best[1] / best[2], best[3], best[4], best[5], best[4] / best[5]
    );
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
        "{name:<15} IK: single loop {:6.2} µs, batch 1 thread {:6.2} µs, 2 threads {:6.2} µs ({:.2}x)",
        best[0], best[1], best[2], best[1] / best[2]
    );
}

fn main() {
    let load = |f: &str, b: Option<&str>, t: Option<&str>| {
        Kinematics::new(&screwkit_model::load_chain(f, b, t).unwrap())
    };
    bench(
        "panda",
        &load(&screwkit_testkit::bundled("panda.urdf"), None, None),
    );
    bench(
        "iiwa14",
        &load(&screwkit_testkit::bundled("iiwa14.urdf"), None, None),
    );
    let pb = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/urdf/panda_pybullet.urdf"
    );
    if std::path::Path::new(pb).exists() {
        bench(
            "panda_pybullet",
            &load(pb, Some("panda_link0"), Some("panda_hand")),
        );
    }
    ik(
        "panda",
        &load(&screwkit_testkit::bundled("panda.urdf"), None, None),
    );
    ik(
        "ur5",
        &load(&screwkit_testkit::bundled("ur5.urdf"), None, None),
    );
}
