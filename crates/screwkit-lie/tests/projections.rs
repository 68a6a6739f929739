//! Distances to SO(3) and SE(3) and the projection onto them, against closed forms and a
//! brute-force search over random rotations.

use nalgebra::{Matrix3, Matrix4, Vector3};
use screwkit_lie::se3::{distance_to_se3, project_to_se3};
use screwkit_lie::so3::{distance_to_so3, exp, nearest_rotation};

/// A small deterministic generator (xorshift) of numbers in [−1, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn rotation(&mut self) -> Matrix3<f64> {
        exp(&(Vector3::new(self.next(), self.next(), self.next()) * 3.0))
    }
}

#[test]
fn distance_to_so3_closed_forms() {
    let mut rng = Rng(0x1234_5678);
    for _ in 0..100 {
        let r = rng.rotation();
        assert!(distance_to_so3(&r) < 1e-14);
        // (1 + a) R: MᵀM − I = ((1 + a)² − 1) I, Frobenius norm √3 ((1 + a)² − 1).
        let a = 0.01 * rng.next();
        let want = 3f64.sqrt() * ((1.0 + a) * (1.0 + a) - 1.0).abs();
        assert!((distance_to_so3(&(r * (1.0 + a))) - want).abs() < 1e-14);
        // A reflection is as orthogonal as a rotation and no rotation at all.
        assert_eq!(distance_to_so3(&(-r)), f64::INFINITY);
    }
    assert_eq!(distance_to_so3(&Matrix3::zeros()), f64::INFINITY);
    assert!(distance_to_so3(&Matrix3::from_element(f64::NAN)).is_nan());
    // Modern Robotics' documented example: mat = [[1, 0, 0], [0, 0.1, -0.95], [0, 1, 0.1]]
    // gives 0.08835.
    let m = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.1, -0.95, 0.0, 1.0, 0.1);
    assert!((distance_to_so3(&m) - 0.08835).abs() < 1e-5);
}

#[test]
fn distance_to_se3_closed_forms() {
    let mut rng = Rng(0x9abc_def0);
    for _ in 0..100 {
        let mut t = Matrix4::identity();
        t.fixed_view_mut::<3, 3>(0, 0).copy_from(&rng.rotation());
        t[(0, 3)] = 5.0 * rng.next();
        assert!(distance_to_se3(&t) < 1e-14);
        // A bottom row off (0, 0, 0, 1) counts, the translation does not.
        let mut off = t;
        off[(3, 0)] = 0.2;
        assert!((distance_to_se3(&off) - 0.2).abs() < 1e-14);
        let mut improper = t;
        improper.fixed_view_mut::<3, 1>(0, 2).neg_mut();
        assert_eq!(distance_to_se3(&improper), f64::INFINITY);
    }
    // Modern Robotics' documented example gives 0.134931.
    let m = Matrix4::new(
        1.0, 0.0, 0.0, 1.2, 0.0, 0.1, -0.95, 1.5, 0.0, 1.0, 0.1, -0.9, 0.0, 0.0, 0.1, 0.98,
    );
    assert!((distance_to_se3(&m) - 0.134931).abs() < 1e-6);
}

/// The projection is a proper rotation, the identity on rotations, and no random rotation is
/// nearer to M in the Frobenius norm — also for improper and singular M, where the nearest
/// proper rotation is what a caller asking for SO(3) needs (Modern Robotics' ProjectToSO3 negates
/// a column of U Vᵀ instead, which is a rotation but not the nearest one).
#[test]
fn projection_is_the_nearest_proper_rotation() {
    let mut rng = Rng(0x0bad_cafe);
    let mut cases: Vec<Matrix3<f64>> = (0..60)
        .map(|_| Matrix3::from_fn(|_, _| rng.next()))
        .collect();
    cases.push(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, -3.0)));
    cases.push(Matrix3::zeros());
    for m in &cases {
        let r = nearest_rotation(m);
        assert!(distance_to_so3(&r) < 1e-14, "{m}");
        let best = (m - r).norm();
        for _ in 0..2000 {
            let other = rng.rotation();
            assert!(
                (m - other).norm() >= best - 1e-12,
                "{m}: {r} beaten by {other}"
            );
        }
    }
    let r = rng.rotation();
    assert!((nearest_rotation(&r) - r).norm() < 1e-14);
    let mut t = Matrix4::identity();
    t.fixed_view_mut::<3, 3>(0, 0).copy_from(&(r * 1.01));
    t[(1, 3)] = 0.7;
    t[(3, 2)] = 0.3;
    let p = project_to_se3(&t).unwrap();
    assert!((p.rotation() - r).norm() < 1e-14);
    assert_eq!(p.translation()[1], 0.7);
    assert_eq!(p.to_homogeneous().row(3), Matrix4::<f64>::identity().row(3));
    assert!(project_to_se3(&Matrix4::from_element(f64::INFINITY)).is_err());
}

/// Issue 44, item 14: the projection does not depend on the matrix's scale; entries of 1e154
/// and more (whose squares overflow inside the SVD) gave NaN, and tiny ones are as good.
#[test]
fn nearest_rotation_of_huge_and_tiny_matrices() {
    let r = exp(&Vector3::new(0.3, -1.1, 0.7));
    let e = Matrix3::new(0.01, -0.02, 0.0, 0.03, 0.0, 0.01, -0.02, 0.01, 0.02);
    let want = nearest_rotation(&(r + e));
    for scale in [1e154, 1e200, 1e300, 1e-300] {
        let got = nearest_rotation(&((r + e) * scale));
        assert!((got - want).amax() < 1e-14, "{scale}: {got}");
        let t = project_to_se3(&{
            let mut m = Matrix4::identity();
            m.fixed_view_mut::<3, 3>(0, 0).copy_from(&((r + e) * scale));
            m
        })
        .unwrap();
        assert!((t.rotation() - want).amax() < 1e-14, "{scale}");
    }
}
