//! SE(3) exp, log and composition, next to nalgebra's generic equivalents measured in the same
//! run (nalgebra's Padé `Matrix4::exp` for exp, `Rotation3::scaled_axis` for the SO(3) part of
//! log, `Isometry3` multiplication for composition).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Rotation3, Translation3, UnitQuaternion, Vector3};
use screwkit_lie::{Se3, Twist};

fn inputs() -> (Twist, Se3, Se3) {
    let xi = Twist::new(Vector3::new(0.3, -1.1, 0.7), Vector3::new(0.5, 0.2, -0.4));
    let a = Se3::exp(&xi);
    let b = Se3::exp(&Twist::new(
        Vector3::new(-0.2, 0.4, 1.9),
        Vector3::new(1.0, -2.0, 0.3),
    ));
    (xi, a, b)
}

fn bench(c: &mut Criterion) {
    let (xi, a, b) = inputs();
    let mut g = c.benchmark_group("se3");
    g.bench_function("exp/screwkit", |bn| bn.iter(|| Se3::exp(black_box(&xi))));
    let hat = xi.hat();
    g.bench_function("exp/nalgebra_matrix4_pade", |bn| {
        bn.iter(|| black_box(&hat).exp())
    });
    g.bench_function("log/screwkit", |bn| bn.iter(|| black_box(&a).log()));
    let rot = Rotation3::from_matrix_unchecked(*a.rotation());
    g.bench_function("log_so3_only/nalgebra_scaled_axis", |bn| {
        bn.iter(|| black_box(&rot).scaled_axis())
    });
    g.bench_function("compose/screwkit", |bn| {
        bn.iter(|| black_box(&a).compose(black_box(&b)))
    });
    let ia = Isometry3::from_parts(
        Translation3::from(*a.translation()),
        UnitQuaternion::from_matrix(a.rotation()),
    );
    let ib = Isometry3::from_parts(
        Translation3::from(*b.translation()),
        UnitQuaternion::from_matrix(b.rotation()),
    );
    g.bench_function("compose/nalgebra_isometry3", |bn| {
        bn.iter(|| black_box(&ia) * black_box(&ib))
    });
    g.bench_function("adjoint_apply/screwkit", |bn| {
        bn.iter(|| black_box(&a).adjoint_apply(black_box(&xi)))
    });
    g.bench_function("adjoint_6x6/screwkit", |bn| {
        bn.iter(|| black_box(&a).adjoint())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
