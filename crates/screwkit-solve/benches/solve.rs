//! FK, all-link FK, FK + Jacobian, one IK iteration and batches (1 vs 2 threads) on the bundled
//! UR5-, Panda- and iiwa-class arms.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use screwkit_lie::Se3;
use screwkit_solve::batch::{fk_batch, ik_batch};
use screwkit_solve::fk::{fk_all_links, fk_unchecked};
use screwkit_solve::ik::{solve, IkOptions};
use screwkit_solve::jacobian::{fk_jacobian_body, fk_jacobian_space};
use screwkit_solve::{Kinematics, Workspace};

const ROBOTS: &[&str] = &["ur5", "panda", "iiwa14"];

fn kin(name: &str) -> Kinematics {
    let chain = screwkit_model::load_chain(
        format!(
            "{}/../../assets/urdf/{name}.urdf",
            env!("CARGO_MANIFEST_DIR")
        ),
        None,
        None,
    )
    .unwrap();
    Kinematics::new(&chain)
}

fn configs(kin: &Kinematics, rows: usize) -> Vec<f64> {
    screwkit_solve::protocol::sample_configurations(kin, rows, 0x1234_5678_9ABC_DEF1)
}

fn single(c: &mut Criterion) {
    let mut g = c.benchmark_group("single");
    for name in ROBOTS {
        let k = kin(name);
        let q = configs(&k, 1);
        let mut ws = Workspace::new(&k);
        g.bench_with_input(BenchmarkId::new("fk", name), &q, |b, q| {
            b.iter(|| fk_unchecked(&k, black_box(q)))
        });
        g.bench_with_input(BenchmarkId::new("fk_all_links", name), &q, |b, q| {
            b.iter(|| fk_all_links(&k, &mut ws, black_box(q)).unwrap().len())
        });
        g.bench_with_input(BenchmarkId::new("fk_jacobian_space", name), &q, |b, q| {
            b.iter(|| fk_jacobian_space(&k, &mut ws, black_box(q)).unwrap().0)
        });
        g.bench_with_input(BenchmarkId::new("fk_jacobian_body", name), &q, |b, q| {
            b.iter(|| fk_jacobian_body(&k, &mut ws, black_box(q)).unwrap().0)
        });
        // One IK iteration = one solve that converges in a single step from very close.
        let target = fk_unchecked(&k, &q);
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
    let mut out = vec![Se3::identity(); rows];
    let targets: Vec<Se3> = qs
        .chunks(k.dof())
        .take(1000)
        .map(|q| fk_unchecked(&k, q))
        .collect();
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
        g.throughput(Throughput::Elements(targets.len() as u64));
        g.bench_function(BenchmarkId::new("ik_1000_panda", threads), |b| {
            b.iter(|| pool.install(|| ik_batch(&k, &targets, None, &opts).unwrap().len()))
        });
    }
    g.finish();
}

criterion_group!(benches, single, batches);
criterion_main!(benches);
