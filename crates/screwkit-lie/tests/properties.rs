//! Group identities over random inputs (proptest).

mod common;

use common::{arb_se3, arb_twist, expm_series};
use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;
use screwkit_lie::{so3, Se3, Twist, Wrench};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// exp(log T) = T for arbitrary rigid transforms.
    #[test]
    fn exp_of_log_is_identity(t in arb_se3()) {
        let back = Se3::exp(&t.log());
        prop_assert!(back.max_abs_diff(&t) < 1e-12, "{t:?} -> {back:?}");
    }

    /// log(exp ξ) = ξ while ‖ω‖ < π (the principal branch).
    #[test]
    fn log_of_exp_is_identity(xi in arb_twist(std::f64::consts::PI - 1e-6)) {
        let back = Se3::exp(&xi).log();
        prop_assert!((back.to_vector() - xi.to_vector()).amax() < 1e-9 * (1.0 + xi.v.norm()),
            "{xi:?} -> {back:?}");
    }

    /// The closed form agrees with a Taylor-series matrix exponential of [ξ].
    #[test]
    fn closed_form_exp_matches_series(xi in arb_twist(3.0)) {
        let series = expm_series(&xi.hat());
        let closed = Se3::exp(&xi).to_homogeneous();
        prop_assert!((series - closed).amax() < 1e-12, "{xi:?}");
    }

    /// ... and nalgebra's Padé matrix exponential, for twists of any size.
    #[test]
    fn closed_form_exp_matches_pade(xi in arb_twist(10.0)) {
        let pade = xi.hat().exp();
        let closed = Se3::exp(&xi).to_homogeneous();
        prop_assert!((pade - closed).amax() < 1e-11, "{xi:?}");
    }

    /// Ad_{AB} = Ad_A Ad_B.
    #[test]
    fn adjoint_is_a_homomorphism(a in arb_se3(), b in arb_se3()) {
        let lhs = (a * b).adjoint();
        let rhs = a.adjoint() * b.adjoint();
        prop_assert!((lhs - rhs).amax() < 1e-12);
    }

    /// Ad_{T⁻¹} = (Ad_T)⁻¹, and the matrix-free inverse application agrees.
    #[test]
    fn adjoint_of_inverse(t in arb_se3(), xi in arb_twist(3.0)) {
        let inv = t.inverse().adjoint();
        prop_assert!((inv * t.adjoint() - nalgebra::Matrix6::identity()).amax() < 1e-12);
        let a = t.adjoint_inverse_apply(&xi).to_vector();
        prop_assert!((a - inv * xi.to_vector()).amax() < 1e-12);
    }

    /// exp(Ad_T ξ) = T exp(ξ) T⁻¹.
    #[test]
    fn exp_conjugation(t in arb_se3(), xi in arb_twist(3.0)) {
        let lhs = Se3::exp(&t.adjoint_apply(&xi));
        let rhs = t * Se3::exp(&xi) * t.inverse();
        prop_assert!(lhs.max_abs_diff(&rhs) < 1e-11);
    }

    /// The matrix-free adjoint application equals the 6x6, and [Ad_T][ξ] = T[ξ]T⁻¹.
    #[test]
    fn adjoint_apply_matches_matrix(t in arb_se3(), xi in arb_twist(3.0)) {
        let a = t.adjoint_apply(&xi).to_vector();
        prop_assert!((a - t.adjoint() * xi.to_vector()).amax() < 1e-12);
        let conj = t.to_homogeneous() * xi.hat() * t.inverse().to_homogeneous();
        prop_assert!((Twist::vee(&conj).to_vector() - a).amax() < 1e-12);
    }

    /// Power VᵀF is frame-invariant: with V_a = Ad_{T_ab} V_b and F_b = Ad_{T_ab}ᵀ F_a.
    #[test]
    fn power_is_frame_invariant(t_ab in arb_se3(), v_b in arb_twist(3.0),
                                m in prop::array::uniform3(-5.0f64..5.0),
                                f in prop::array::uniform3(-5.0f64..5.0)) {
        let f_a = Wrench::new(Vector3::from(m), Vector3::from(f));
        let v_a = t_ab.adjoint_apply(&v_b);
        let f_b = t_ab.adjoint_transpose_apply(&f_a);
        prop_assert!((f_a.power(&v_a) - f_b.power(&v_b)).abs() < 1e-10);
        // The matrix-free transpose application equals Ad_Tᵀ F.
        let want = t_ab.adjoint().transpose() * f_a.to_vector();
        prop_assert!((f_b.to_vector() - want).amax() < 1e-12);
    }

    /// The bracket equals the matrix commutator [V1][V2] − [V2][V1] and \[ad_V1\] V2.
    #[test]
    fn bracket_is_commutator(a in arb_twist(3.0), b in arb_twist(3.0)) {
        let comm = a.hat() * b.hat() - b.hat() * a.hat();
        let br = a.bracket(&b);
        prop_assert!((Twist::vee(&comm).to_vector() - br.to_vector()).amax() < 1e-12);
        prop_assert!((a.ad() * b.to_vector() - br.to_vector()).amax() < 1e-12);
    }

    /// Inverse and composition: T T⁻¹ = I, T⁻¹ S = inverse_compose, points map back.
    #[test]
    fn inverse_and_compose(a in arb_se3(), b in arb_se3(), x in prop::array::uniform3(-5.0f64..5.0)) {
        prop_assert!((a * a.inverse()).max_abs_diff(&Se3::identity()) < 1e-12);
        prop_assert!(a.inverse_compose(&b).max_abs_diff(&(a.inverse() * b)) < 1e-12);
        let x = Vector3::from(x);
        let y = a.transform_point(&x);
        prop_assert!((a.inverse().transform_point(&y) - x).amax() < 1e-12);
        let via_matrix = a.to_homogeneous() * b.to_homogeneous();
        prop_assert!(((a * b).to_homogeneous() - via_matrix).amax() < 1e-12);
    }

    /// so(3): exp(log R) = R and the rotation is orthonormal.
    #[test]
    fn so3_exp_log(t in arb_se3()) {
        let r = t.rotation();
        let back = so3::exp(&so3::log(r));
        prop_assert!((back - r).amax() < 1e-12);
        prop_assert!((back.transpose() * back - Matrix3::identity()).amax() < 1e-14);
    }

    /// rpy and quaternion round trips.
    #[test]
    fn rpy_and_quaternion_round_trip(t in arb_se3()) {
        let r = t.rotation();
        let [roll, pitch, yaw] = so3::to_rpy(r);
        prop_assert!((so3::from_rpy(roll, pitch, yaw) - r).amax() < 1e-12);
        let q = so3::to_quaternion(r);
        prop_assert!((so3::from_quaternion(q).unwrap() - r).amax() < 1e-12);
        // URDF's R = Rz(y) Ry(p) Rx(r), built from elementary rotations.
        let direct = so3::rot_z(yaw) * so3::rot_y(pitch) * so3::rot_x(roll);
        prop_assert!((direct - r).amax() < 1e-12);
    }

    /// A screw built from (q, ŝ, h) gives back ŝ, h and the closest point of its line.
    #[test]
    fn screw_axis_round_trip(q in prop::array::uniform3(-5.0f64..5.0),
                             s in prop::array::uniform3(-1.0f64..1.0),
                             h in -2.0f64..2.0) {
        let s = Vector3::from(s);
        prop_assume!(s.norm() > 1e-3);
        let q = Vector3::from(q);
        let axis = screwkit_lie::ScrewAxis::from_point_direction_pitch(q, s, h).unwrap();
        let s_hat = s.normalize();
        prop_assert!((axis.direction() - s_hat).amax() < 1e-14);
        prop_assert!((axis.pitch().unwrap() - h).abs() < 1e-12);
        let closest = axis.point().unwrap();
        // On the line through q along ŝ, and perpendicular to ŝ (so closest to the origin).
        let off_line = (closest - q) - s_hat * s_hat.dot(&(closest - q));
        prop_assert!(off_line.amax() < 1e-12);
        prop_assert!(closest.dot(&s_hat).abs() < 1e-12);
        // A twist at speed 2.5 about it decomposes back into (axis, 2.5).
        let (back, speed) = screwkit_lie::ScrewAxis::from_twist(&axis.to_twist(2.5)).unwrap();
        prop_assert!((speed - 2.5).abs() < 1e-12);
        prop_assert!((back.twist().to_vector() - axis.twist().to_vector()).amax() < 1e-12);
    }
}
