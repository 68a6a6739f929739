//! Textbook worked examples of screw motions (exponential coordinates, logarithms, twists in
//! two frames; *Modern Robotics* ch. 3), each stated in full below and checked with exact values.
//!
//! The printed solutions round their intermediate results (θ = 2.23, 1.055, 0.6121, …). The expected
//! values here were computed independently in double precision from the closed forms
//! (Rodrigues, G(θ), G⁻¹(θ) written out by hand in a separate script), not with this crate.

use std::f64::consts::{FRAC_PI_6, PI};

use nalgebra::{Matrix4, Vector3};
use screwkit_lie::{ScrewAxis, Se3, Twist};

fn assert_close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:.15}, want {want:.15} (tol {tol:e})"
    );
}

/// Lesson, "Homogenous Transformation Matrix to Exponential Coordinates of Motion":
/// T_sb = [[0,−1,0,3],[0,0,−1,0],[1,0,0,0]] → θ = 2π/3, S = (ŝ, G⁻¹(θ)p), h, q = (1, 1, 0).
#[test]
fn lesson_transform_to_screw() {
    let t_sb = Se3::from_homogeneous(&Matrix4::new(
        0.0, -1.0, 0.0, 3.0, //
        0.0, 0.0, -1.0, 0.0, //
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    ))
    .unwrap();
    let (s, theta) = t_sb.log_screw().expect("not the identity");
    assert_close(theta, 2.0 * PI / 3.0, 1e-14, "θ");
    let k = 1.0 / 3f64.sqrt();
    let want = [
        k,
        -k,
        k,
        1.054_815_098_465_312,
        -1.054_815_098_465_312,
        -0.677_235_709_103_565_7,
    ];
    let got = s.twist().to_vector();
    for i in 0..6 {
        assert_close(got[i], want[i], 1e-13, &format!("S[{i}]"));
    }
    // The printed 7-decimal figures, as written.
    assert_close(got[3], 1.0548151, 5e-8, "S_v1 (7 decimals)");
    assert_close(got[5], -0.6772357, 5e-8, "S_v3 (7 decimals)");
    assert_close(
        s.pitch().unwrap(),
        0.826_993_343_132_688_2,
        1e-13,
        "pitch h",
    );
    let q = s.point().unwrap();
    assert!(
        (q - Vector3::new(1.0, 1.0, 0.0)).amax() < 1e-13,
        "closest point {q:?}"
    );
    // And back: e^[S]θ reproduces T_sb.
    assert!(Se3::exp_screw(&s, theta).max_abs_diff(&t_sb) < 1e-14);
}

/// Lesson, "Exponential Coordinates of Motion to Homogenous Transformation Matrix":
/// Sθ = (0, 1, 2, 3, 0, 0). The printed solution rounds θ = √5 to 2.23 and gets −0.6121; exactly, the
/// first row of R is (−0.6173, −0.7037, 0.3518) and p = (1.0555, 1.9407, −0.9704).
#[test]
fn lesson_exponential_coordinates_to_transform() {
    let t = Se3::exp(&Twist::new(
        Vector3::new(0.0, 1.0, 2.0),
        Vector3::new(3.0, 0.0, 0.0),
    ));
    let r = t.rotation();
    let want_r = [
        [
            -0.617_272_876_457_166_4,
            -0.703_689_815_751_397_9,
            0.351_844_907_875_698_94,
        ],
        [
            0.703_689_815_751_397_9,
            -0.293_818_301_165_733_15,
            0.646_909_150_582_866_6,
        ],
        [
            -0.351_844_907_875_698_94,
            0.646_909_150_582_866_6,
            0.676_545_424_708_566_7,
        ],
    ];
    for (i, row) in want_r.iter().enumerate() {
        for (j, &w) in row.iter().enumerate() {
            assert_close(r[(i, j)], w, 1e-14, &format!("R[{i}][{j}]"));
        }
    }
    let want_p = [
        1.055_534_723_627_097,
        1.940_727_451_748_599_7,
        -0.970_363_725_874_299_9,
    ];
    for (i, &w) in want_p.iter().enumerate() {
        assert_close(t.translation()[i], w, 1e-14, &format!("p[{i}]"));
    }
    // The printed 4-decimal figures.
    for (got, want) in [
        (r[(0, 0)], -0.6173),
        (r[(0, 1)], -0.7037),
        (r[(0, 2)], 0.3518),
        (t.translation().x, 1.0555),
        (t.translation().y, 1.9407),
        (t.translation().z, -0.9704),
    ] {
        assert_close(got, want, 5e-5, "4-decimal figure");
    }
}

/// Lecture, "Matrix Exponential and Matrix Logarithm": T_sb = Rot(z, 30°) at (1, 2, 0),
/// T_sc = Rot(z, 60°) at (2, 1, 0); the screw displacing {b} to {c} is
/// log(T_sc T_sb⁻¹) = S θ with S = (0, 0, 1, 3.3660254, −3.3660254, 0), θ = π/6.
///
/// Exact oracle: the axis is ẑ through the fixed point q of the planar motion, which solves
/// (I − R) q = p_c − R p_b (2x2 system solved below); then v = q × ẑ.
#[test]
fn lecture_screw_between_two_frames() {
    let t_sb = Se3::from_parts(
        screwkit_lie::so3::rot_z(FRAC_PI_6),
        Vector3::new(1.0, 2.0, 0.0),
    )
    .unwrap();
    let t_sc = Se3::from_parts(
        screwkit_lie::so3::rot_z(2.0 * FRAC_PI_6),
        Vector3::new(2.0, 1.0, 0.0),
    )
    .unwrap();
    let (s, theta) = (t_sc * t_sb.inverse()).log_screw().unwrap();
    assert_close(theta, FRAC_PI_6, 1e-14, "θ");
    // Fixed point q of the planar motion, by 2x2 algebra independent of the crate.
    let (sa, ca) = FRAC_PI_6.sin_cos();
    // p_c − R p_b with R = R_z(30°) applied to the origin displacement of T_sc T_sb⁻¹:
    // T_sc T_sb⁻¹ = (R_z(30°), p_c − R_z(30°) p_b).
    let rpb = Vector3::new(ca * 1.0 - sa * 2.0, sa * 1.0 + ca * 2.0, 0.0);
    let d = Vector3::new(2.0, 1.0, 0.0) - rpb;
    // (I − R) q = d in 2D: [[1 − c, s], [−s, 1 − c]] q = d.
    let (a11, a12, a21, a22) = (1.0 - ca, sa, -sa, 1.0 - ca);
    let det = a11 * a22 - a12 * a21;
    let q = Vector3::new(
        (a22 * d.x - a12 * d.y) / det,
        (a11 * d.y - a21 * d.x) / det,
        0.0,
    );
    let v_exact = q.cross(&Vector3::z());
    let got = s.twist();
    assert!((got.w - Vector3::z()).amax() < 1e-14, "ω = {:?}", got.w);
    assert!(
        (got.v - v_exact).amax() < 1e-13,
        "v = {:?}, want {v_exact:?}",
        got.v
    );
    assert_close(got.v.x, 3.3660254, 5e-8, "v₁ (printed 7 decimals)");
    assert_close(got.v.y, -3.3660254, 5e-8, "v₂ (printed 7 decimals)");
    assert_close(got.v.z, 0.0, 1e-14, "v₃");
    assert_close(s.pitch().unwrap(), 0.0, 1e-14, "zero pitch");
}

/// Lecture, "Twists Example": a car turning at 2 rad/s about a vertical axis through r_s:
/// ω_s = (0, 0, 2), r_s = (2, −1, 0) → v_s = r_s × ω_s = (−2, −4, 0); in the body frame,
/// ω_b = (0, 0, −2), r_b = (2, −1.4, 0) → v_b = (2.8, 4, 0).
#[test]
fn lecture_twist_of_a_turning_car() {
    let s_axis = ScrewAxis::revolute(Vector3::new(2.0, -1.0, 0.0), Vector3::z()).unwrap();
    let v_s = s_axis.to_twist(2.0);
    assert_eq!(v_s.w, Vector3::new(0.0, 0.0, 2.0));
    assert!((v_s.v - Vector3::new(-2.0, -4.0, 0.0)).amax() < 1e-15);
    let b_axis = ScrewAxis::revolute(Vector3::new(2.0, -1.4, 0.0), -Vector3::z()).unwrap();
    let v_b = b_axis.to_twist(2.0);
    assert!((v_b.v - Vector3::new(2.8, 4.0, 0.0)).amax() < 1e-15);
    // Both describe the same motion: V_s = [Ad_{T_sb}] V_b for the body frame implied by
    // r_s and r_b (the car's frame {b}: origin at r_s − R_sb r_b, rotated 180° about x).
    let r_sb = screwkit_lie::so3::rot_x(PI);
    let p_sb = Vector3::new(2.0, -1.0, 0.0) - r_sb * Vector3::new(2.0, -1.4, 0.0);
    let t_sb = Se3::from_parts(r_sb, p_sb).unwrap();
    let v_s_from_b = t_sb.adjoint_apply(&v_b);
    assert!((v_s_from_b.to_vector() - v_s.to_vector()).amax() < 1e-14);
}

/// A force f applied at a point r: m = r × f. Pushing with 10 N along y at (0.5, 0, 0) gives a
/// 5 N·m moment about z; the same force through the origin gives none; and the power on a twist
/// turning about z at 2 rad/s is ω·m = 10 W (the point moves at 1 m/s along y: f·v = 10 W).
#[test]
fn force_at_a_point() {
    use screwkit_lie::Wrench;
    let f = Vector3::new(0.0, 10.0, 0.0);
    let w = Wrench::from_force_at_point(f, Vector3::new(0.5, 0.0, 0.0));
    assert_eq!(w.m, Vector3::new(0.0, 0.0, 5.0));
    assert_eq!(w.f, f);
    assert_eq!(
        Wrench::from_force_at_point(f, Vector3::zeros()).m,
        Vector3::zeros()
    );
    let v = Twist::new(Vector3::new(0.0, 0.0, 2.0), Vector3::zeros());
    assert_close(w.power(&v), 10.0, 1e-15, "power");
}
