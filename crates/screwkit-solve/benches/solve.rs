//! FK, all-link FK, FK + Jacobian, one IK iteration and batches (1 vs 2 threads) on the bundled
//! UR5-, Panda- and iiwa-class arms.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use screwkit_solve::batch::{fk_batch, ik_batch};
use screwkit_solve::fk::{fk, fk_all_links};
use screwkit_solve::ik::{solve, IkOptions, IkStatus};
use screwkit_solve::jacobian::fk_jacobian;
use screwkit_solve::{Frame, Kinematics, Workspace};

const ROBOTS: &[&str] = &["ur5", "panda", "iiwa14"];

fn kin(name: &str) -> Kinematics {
    let chain = screwkit_model::load_chain(
        screwkit_testkit::bundled(&format!("{name}.urdf")),
        None,
        None,
    )
    .unwrap();
    Kinematics::new(&chain)
}

fn configs(kin: &Kinematics, rows: usize) -> Vec<f64> {
    screwkit_solve::sample::configurations(kin, rows, 0x1234_5678_9ABC_DEF1)
}

fn single(c: &mut Criterion) {
    let mut g = c.benchmark_group("single");
    for name in ROBOTS {
        let k = kin(name);
        let q = configs(&k, 1);
        let mut ws = Workspace::new(&k);
        g.bench_with_input(BenchmarkId::new("fk", name), &q, |b, q| {
            b.iter(|| fk(&k, &mut ws, black_box(q)).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("fk_all_links", name), &q, |b, q| {
            b.iter(|| fk_all_links(&k, &mut ws, black_box(q)).unwrap().len())
        });
        g.bench_with_input(BenchmarkId::new("fk_jacobian_space", name), &q, |b, q| {
            b.iter(|| {
                fk_jacobian(&k, &mut ws, black_box(q), Frame::Space)
                    .unwrap()
                    .pose
            })
        });
        g.bench_with_input(BenchmarkId::new("fk_jacobian_body", name), &q, |b, q| {
            b.iter(|| {
                fk_jacobian(&k, &mut ws, black_box(q), Frame::Body)
                    .unwrap()
                    .pose
            })
        });
        // One IK iteration = one solve that converges in a single step from very close.
        let target = fk(&k, &mut ws, &q).unwrap();
        let mut near = q.clone();
        near[0] += 1e-7;
        let one_step = IkOptions {
            max_iterations: 1,
            timeout: None,
            ..IkOptions::default()
        };
        g.bench_function(BenchmarkId::new("ik_one_iteration_lm", name), |b| {
            b.iter(|| {
                solve(&k, &mut ws, black_box(&target), &near, &one_step)
                    .unwrap()
                    .status
                    .iterations
            })
        });
    }
    g.finish();
}

fn batches(c: &mut Criterion) {
    let mut g = c.benchmark_group("batch");
    let k = kin("panda");
    let rows = 20_000;
    let qs = configs(&k, rows);
    let mut out = vec![0.0; rows * 16];
    fk_batch(&k, &qs, &mut out).unwrap();
    let targets = out[..1000 * 16].to_vec();
    let (mut q_out, mut status) = (vec![0.0; 1000 * k.dof()], vec![IkStatus::default(); 1000]);
    let opts = IkOptions {
        timeout: None,
        ..IkOptions::default()
    };
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        g.throughput(Throughput::Elements(rows as u64));
        g.bench_function(BenchmarkId::new("fk_20k_panda", threads), |b| {
            b.iter(|| pool.install(|| fk_batch(&k, &qs, &mut out).unwrap()))
        });
        g.throughput(Throughput::Elements(1000));
        g.bench_function(BenchmarkId::new("ik_1000_panda", threads), |b| {
            b.iter(|| {
                pool.install(|| {
                    ik_batch(&k, &targets, None, &opts, &mut q_out, &mut status, None).unwrap()
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, single, batches);
criterion_main!(benches);
