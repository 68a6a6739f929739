//! Batched kernels per configuration, next to a loop of single calls on the same rows, in one
//! run (interleaved rounds, minimum kept): tip FK (`fk_batch`, the structure-of-arrays block
//! kernel), FK + space Jacobian (`jacobian_batch` with poses), on 1 and 2 threads, for the
//! bundled Panda and iiwa14 and, when ../shared/urdf is beside the clone, pybullet's Panda.
//! Run: `cargo bench -p screwkit-solve --bench batch_kernels`.

use std::time::Instant;

use screwkit_solve::batch::{fk_batch, jacobian_batch};
use screwkit_solve::fk::fk;
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
}
