//! Numerical corners (θ → 0, θ → π, pure translation, pitch ≠ 0) and malformed input.

mod common;

use std::f64::consts::PI;

use common::expm_series;
use nalgebra::{Matrix3, Matrix4, Vector3};
use screwkit_lie::{so3, LieError, ScrewAxis, Se3, Twist};

fn axes() -> Vec<Vector3<f64>> {
    vec![
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        -Vector3::z(),
        Vector3::new(1.0, -1.0, 1.0).normalize(),
        Vector3::new(0.3, 0.2, -0.9).normalize(),
        Vector3::new(1e-9, 1.0, 0.0).normalize(),
    ]
}

/// exp at tiny angles agrees with the series matrix exponential to full precision, and log
/// gives the twist back (small θ is where 1 − cos θ and θ − sin θ cancel).
#[test]
fn small_angles() {
    let v = Vector3::new(0.7, -1.3, 2.1);
    for axis in axes() {
        for theta in [
            0.0, 1e-300, 1e-15, 1e-9, 1e-6, 1e-4, 1e-3, 0.1, 0.2499, 0.25, 0.4999, 0.5,
        ] {
            let xi = Twist::new(axis * theta, v);
            let t = Se3::exp(&xi);
            let oracle = expm_series(&xi.hat());
            assert!(
                (t.to_homogeneous() - oracle).amax() < 1e-15 * 4.0,
                "θ = {theta:e}: {:e}",
                (t.to_homogeneous() - oracle).amax()
            );
            let back = t.log();
            let err = (back.to_vector() - xi.to_vector()).amax();
            assert!(err < 1e-14, "θ = {theta:e}: log error {err:e}");
        }
    }
}

/// Near and at θ = π, where vee(R − Rᵀ) vanishes: log must still recover the axis to ~1e-12.
#[test]
fn angles_near_pi() {
    let v = Vector3::new(0.4, 0.5, -0.6);
    for axis in axes() {
        for theta in [PI - 1e-6, PI - 1e-9, PI - 1e-12, PI, PI + 1e-9, PI + 1e-6] {
            let xi = Twist::new(axis * theta, v);
            let t = Se3::exp(&xi);
            // exp(log T) = T always.
            let back = Se3::exp(&t.log());
            assert!(
                back.max_abs_diff(&t) < 1e-12,
                "θ = π{:+e}: {:e}",
                theta - PI,
                back.max_abs_diff(&t)
            );
            let w = t.log().w;
            let angle = w.norm();
            // The principal angle is in [0, π] ...
            let want_angle = if theta <= PI { theta } else { 2.0 * PI - theta };
            assert!(
                (angle - want_angle).abs() < 1e-12,
                "θ = π{:+e}: angle {angle}",
                theta - PI
            );
            // ... about ±axis (the sign flips past π, and is free at π).
            let align = (w / angle).dot(&axis).abs();
            assert!(
                (align - 1.0).abs() < 1e-12,
                "θ = π{:+e}: axis {:?}",
                theta - PI,
                w / angle
            );
            if theta < PI - 1e-10 {
                assert!(
                    (w - axis * theta).amax() < 1e-12,
                    "θ = π{:+e}: {w:?}",
                    theta - PI
                );
            }
        }
    }
}

/// Rotation by exactly π about the coordinate axes (R diagonal: the textbook special case).
#[test]
fn exact_half_turns() {
    for (r, axis) in [
        (
            Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0)),
            Vector3::x(),
        ),
        (
            Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, -1.0)),
            Vector3::y(),
        ),
        (
            Matrix3::from_diagonal(&Vector3::new(-1.0, -1.0, 1.0)),
            Vector3::z(),
        ),
    ] {
        let w = so3::log(&r);
        assert!((w.norm() - PI).abs() < 1e-15);
        assert!((w.normalize().dot(&axis).abs() - 1.0).abs() < 1e-15);
        assert!((so3::exp(&w) - r).amax() < 1e-15);
    }
}

/// Pure translations: R = I gives ω = 0, v = p; the screw is a pure translation with θ = ‖p‖.
#[test]
fn pure_translation() {
    let p = Vector3::new(3.0, -4.0, 0.0);
    let t = Se3::from_translation(p);
    let xi = t.log();
    assert_eq!(xi.w, Vector3::zeros());
    assert_eq!(xi.v, p);
    let (s, theta) = t.log_screw().unwrap();
    assert!(s.is_pure_translation());
    assert_eq!(theta, 5.0);
    assert!((s.direction() - Vector3::new(0.6, -0.8, 0.0)).amax() < 1e-16);
    assert_eq!(s.pitch(), None);
    assert_eq!(s.point(), None);
    assert_eq!(Se3::identity().log_screw(), None);
    // exp of a prismatic screw moves along it without rotating.
    let prism = ScrewAxis::prismatic(Vector3::new(0.0, 0.0, 2.0)).unwrap();
    let t = Se3::exp_screw(&prism, 0.25);
    assert_eq!(*t.rotation(), Matrix3::identity());
    assert_eq!(*t.translation(), Vector3::new(0.0, 0.0, 0.25));
}

/// A screw with pitch h advances h·θ along its axis while turning θ about it.
#[test]
fn nonzero_pitch() {
    let q = Vector3::new(1.0, 2.0, 0.0);
    let h = 0.3;
    let s = ScrewAxis::from_point_direction_pitch(q, Vector3::z(), h).unwrap();
    let theta = 2.0;
    let t = Se3::exp_screw(&s, theta);
    // The axis point moves only along the axis.
    let moved = t.transform_point(&q);
    assert!((moved - (q + Vector3::z() * (h * theta))).amax() < 1e-14);
    // The origin rotates about the axis through q and rises by hθ.
    let o = t.transform_point(&Vector3::zeros());
    let expected = q + so3::rot_z(theta) * (-q) + Vector3::z() * (h * theta);
    assert!((o - expected).amax() < 1e-14);
    let (back, th) = t.log_screw().unwrap();
    assert!((th - theta).abs() < 1e-14);
    assert!((back.pitch().unwrap() - h).abs() < 1e-14);
    assert!((back.point().unwrap() - q).amax() < 1e-14);
}

/// A non-rotation 3x3 block, a bad last row, NaN: errors, never a panic.
#[test]
fn malformed_matrices_are_errors() {
    let mut m = Matrix4::identity();
    m[(0, 0)] = 2.0;
    assert!(matches!(
        Se3::from_homogeneous(&m),
        Err(LieError::NotARotation { .. })
    ));

    // A reflection: orthonormal, det −1.
    let mut refl = Matrix4::identity();
    refl[(2, 2)] = -1.0;
    let err = Se3::from_homogeneous(&refl).unwrap_err();
    assert!(
        matches!(err, LieError::NotARotation { det, .. } if det < 0.0),
        "{err}"
    );

    let mut shear = Matrix4::identity();
    shear[(0, 1)] = 0.1;
    assert!(Se3::from_homogeneous(&shear).is_err());

    let mut row = Matrix4::identity();
    row[(3, 0)] = 1.0;
    assert!(matches!(
        Se3::from_homogeneous(&row),
        Err(LieError::BadLastRow { .. })
    ));

    let mut nan = Matrix4::identity();
    nan[(1, 3)] = f64::NAN;
    assert!(matches!(
        Se3::from_homogeneous(&nan),
        Err(LieError::NonFinite { .. })
    ));
    let mut inf = Matrix4::identity();
    inf[(0, 0)] = f64::INFINITY;
    assert!(Se3::from_homogeneous(&inf).is_err());

    assert!(matches!(
        Se3::from_row_major(&[1.0; 15], 1e-6),
        Err(LieError::WrongLength { got: 15, .. })
    ));
    assert!(Se3::from_parts(Matrix3::zeros(), Vector3::zeros()).is_err());
    assert!(Se3::from_parts(Matrix3::identity(), Vector3::new(f64::NAN, 0.0, 0.0)).is_err());
    assert!(Se3::from_xyz_rpy([0.0; 3], [f64::NAN, 0.0, 0.0]).is_err());
    assert!(matches!(
        Se3::from_translation_quaternion([0.0; 3], [0.0; 4]),
        Err(LieError::ZeroVector { .. })
    ));
    assert!(Twist::try_from_slice(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0]).is_err());
    assert!(Twist::try_from_slice(&[0.0; 5]).is_err());
    assert!(ScrewAxis::revolute(Vector3::zeros(), Vector3::zeros()).is_err());
    assert!(ScrewAxis::prismatic(Vector3::new(f64::NAN, 1.0, 0.0)).is_err());
    assert!(ScrewAxis::from_twist(&Twist::zero()).is_err());

    // The error messages say what is wrong.
    let msg = Se3::from_homogeneous(&m).unwrap_err().to_string();
    assert!(msg.contains("not a rotation matrix"), "{msg}");
}

/// Rounded, user-typed matrices pass with a looser tolerance and are made exact.
#[test]
fn rounded_rotation_is_projected() {
    let c = 0.8660; // cos 30° to 4 decimals
    let m = [
        c, -0.5, 0.0, 1.0, 0.5, c, 0.0, 2.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    assert!(Se3::from_row_major(&m, 1e-6).is_err());
    let t = Se3::from_row_major(&m, 1e-3).unwrap();
    let r = t.rotation();
    assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-15);
    assert!((r[(0, 0)] - (PI / 6.0).cos()).abs() < 1e-4);
}

/// `write_row_major` writes the homogeneous matrix row by row: the inverse of `from_row_major`.
#[test]
fn row_major_round_trip() {
    let t = Se3::exp(&Twist::new(
        Vector3::new(0.3, -0.2, 0.9),
        Vector3::new(1.0, 2.0, -3.0),
    ));
    let mut out = [f64::NAN; 16];
    t.write_row_major(&mut out);
    let h = t.to_homogeneous();
    for r in 0..4 {
        for c in 0..4 {
            assert_eq!(out[4 * r + c], h[(r, c)]);
        }
    }
    assert_eq!(Se3::from_row_major(&out, 1e-12).unwrap(), t);
}

/// Non-finite input to the hot-path functions gives non-finite output, not a panic.
#[test]
fn nan_through_hot_path_does_not_panic() {
    let xi = Twist::new(Vector3::new(f64::NAN, 0.0, 0.0), Vector3::zeros());
    assert!(!Se3::exp(&xi).is_finite());
    let t = Se3::from_parts_unchecked(Matrix3::from_element(f64::NAN), Vector3::zeros());
    assert!(!t.log().is_finite());
    let _ = so3::log(&Matrix3::from_element(f64::INFINITY));
}

/// Display prints the 4x4 readably; Debug prints rows of R and p.
#[test]
fn display_formats() {
    let t = Se3::from_xyz_rpy([1.0, 2.0, 3.0], [0.0, 0.0, PI / 2.0]).unwrap();
    let text = format!("{t:.3}");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4);
    assert_eq!(lines[0], "[  0.000  -1.000   0.000   1.000]");
    assert_eq!(lines[3], "[  0.000   0.000   0.000   1.000]");
    let dbg = format!("{:?}", Se3::identity());
    assert_eq!(
        dbg,
        "Se3 { R: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], p: [0.0, 0.0, 0.0] }"
    );
    let s = ScrewAxis::revolute(Vector3::new(1.0, 1.0, 0.0), Vector3::z()).unwrap();
    assert_eq!(
        format!("{s:.2}"),
        "screw along (0.00, 0.00, 1.00) through (1.00, 1.00, 0.00), pitch 0.00"
    );
    assert_eq!(
        format!("{:.1}", Twist::new(Vector3::x(), Vector3::y())),
        "(1.0, 0.0, 0.0 | 0.0, 1.0, 0.0)"
    );
}

/// rpy at and near the gimbal lock (pitch = ±π/2 − 10⁻ᵏ, k = 1 … 16, and exactly ±π/2,
/// with rotations built from quaternions, as MJCF gives them): from_rpy(to_rpy(R)) equals R to
/// rounding. The textbook roll = atan2(r₃₂, r₃₃) was 2.8e-5 off here (measured).
#[test]
fn rpy_is_exact_at_and_near_the_gimbal_lock() {
    use nalgebra::{UnitQuaternion, Vector3};
    use screwkit_lie::so3;
    let mut worst = 0.0_f64;
    for sign in [1.0, -1.0] {
        for k in 0..=16 {
            let pitch =
                sign * (std::f64::consts::FRAC_PI_2 - if k == 0 { 0.0 } else { 10f64.powi(-k) });
            for (roll, yaw) in [(0.3, -1.2), (0.0, 0.0), (2.9, 3.1), (-0.7, 0.4)] {
                let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw)
                    * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), pitch)
                    * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), roll);
                let r = *q.to_rotation_matrix().matrix();
                let [a, b, c] = so3::to_rpy(&r);
                worst = worst.max((so3::from_rpy(a, b, c) - r).amax());
            }
        }
    }
    // A half turn about y from a quaternion (0.7071…, 0, 0.7071…, 0): the lock, rounded.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let r = *UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(h, 0.0, h, 0.0))
        .to_rotation_matrix()
        .matrix();
    let [a, b, c] = so3::to_rpy(&r);
    worst = worst.max((so3::from_rpy(a, b, c) - r).amax());
    assert!(worst < 1e-15, "{worst:e}");
}

#[test]
fn nearest_rotation_of_non_finite_input_returns_never_hangs() {
    // nalgebra's SVD iterates without bound on NaN: the projection bounds it and gives the
    // matrix back.
    let mut m = nalgebra::Matrix3::identity();
    m[(1, 2)] = f64::NAN;
    let r = screwkit_lie::so3::nearest_rotation(&m);
    assert!(r[(1, 2)].is_nan());
    let r = screwkit_lie::so3::nearest_rotation(&nalgebra::Matrix3::repeat(f64::INFINITY));
    assert!(!r.iter().all(|x| x.is_finite()));
}
