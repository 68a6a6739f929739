//! SO(3): the rotation group and its Lie algebra so(3).
//!
//! A rotation is a plain `Matrix3<f64>` `R` with RᵀR = I and det R = +1. Exponential
//! coordinates are the 3-vector φ = ω̂θ (unit axis ω̂, angle θ ∈ [0, π]).

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

use crate::error::LieError;

/// Default tolerance on max |RᵀR − I| when a rotation is read from user input.
pub const DEFAULT_ROTATION_TOLERANCE: f64 = 1e-6;

/// Tolerance on max |RᵀR − I| of an IK target's rotation, the same in every front end (the
/// CLI's typed matrices, JSON lines, .npy batches, Python arrays): a rotation rounded to
/// four or more decimals is accepted and re-orthonormalised, anything further off refused.
pub const TARGET_ROTATION_TOLERANCE: f64 = 1e-3;

/// \[ω\]: the skew-symmetric matrix with \[ω\] x = ω × x.
///
/// ```text
///        ⎡  0  −ω₃  ω₂ ⎤
/// [ω] =  ⎢  ω₃  0  −ω₁ ⎥
///        ⎣ −ω₂  ω₁  0  ⎦
/// ```
#[inline]
pub fn hat(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// vee(\[ω\]) = ω: the inverse of [`hat`], reading (m₃₂, m₁₃, m₂₁).
///
/// For a matrix that is not exactly skew-symmetric this returns the vee of its skew part,
/// ½ vee(M − Mᵀ), which is the nearest skew-symmetric matrix in the Frobenius norm.
#[inline]
pub fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (m[(2, 1)] - m[(1, 2)]),
        0.5 * (m[(0, 2)] - m[(2, 0)]),
        0.5 * (m[(1, 0)] - m[(0, 1)]),
    )
}

/// The coefficients of the SO(3)/SE(3) exponential for an angle θ = ‖ω‖ ≥ 0:
///
/// - A = sin θ / θ
/// - B = (1 − cos θ) / θ²
/// - C = (θ − sin θ) / θ³
///
/// Below θ = 0.5 (where 1 − cos θ and θ − sin θ cancel) their Taylor series to θ¹² are used,
/// with no trigonometry (truncation < 5e-17); above, one sine/cosine and one reciprocal.
#[inline]
pub(crate) fn exp_coefficients(theta: f64) -> (f64, f64, f64) {
    if theta < 0.5 {
        let t2 = theta * theta;
        // A = Σ (−1)ᵏ θ²ᵏ/(2k+1)!, B = Σ (−1)ᵏ θ²ᵏ/(2k+2)!, C = Σ (−1)ᵏ θ²ᵏ/(2k+3)!
        let a = 1.0
            - t2 * (1.0 / 6.0
                - t2 * (1.0 / 120.0
                    - t2 * (1.0 / 5040.0
                        - t2 * (1.0 / 362_880.0
                            - t2 * (1.0 / 39_916_800.0 - t2 / 6_227_020_800.0)))));
        let b = 0.5
            - t2 * (1.0 / 24.0
                - t2 * (1.0 / 720.0
                    - t2 * (1.0 / 40_320.0
                        - t2 * (1.0 / 3_628_800.0
                            - t2 * (1.0 / 479_001_600.0 - t2 / 87_178_291_200.0)))));
        let c = 1.0 / 6.0
            - t2 * (1.0 / 120.0
                - t2 * (1.0 / 5040.0
                    - t2 * (1.0 / 362_880.0
                        - t2 * (1.0 / 39_916_800.0
                            - t2 * (1.0 / 6_227_020_800.0 - t2 / 1_307_674_368_000.0)))));
        (a, b, c)
    } else {
        let (s, c) = theta.sin_cos();
        let inv = 1.0 / theta;
        let inv2 = inv * inv;
        (s * inv, (1.0 - c) * inv2, (theta - s) * inv2 * inv)
    }
}

/// e^\[φ\]: Rodrigues' formula R = I + A \[φ\] + B \[φ\]² with θ = ‖φ‖, A = sin θ/θ,
/// B = (1 − cos θ)/θ² (for unit ω̂ and φ = ω̂θ: R = I + sin θ [ω̂] + (1 − cos θ)[ω̂]²).
///
/// Exact for every φ, including ‖φ‖ → 0 (series coefficients) and ‖φ‖ ≥ π.
#[inline]
pub fn exp(phi: &Vector3<f64>) -> Matrix3<f64> {
    let theta = phi.norm();
    let (a, b, _) = exp_coefficients(theta);
    rotation_from_coefficients(phi, theta, a, b)
}

/// The rotation of the SO(3)/SE(3) exponential, R = I + A\[φ\] + B\[φ\]² with θ = ‖φ‖, written
/// with \[φ\]² = φφᵀ − θ² I: the one home of Rodrigues' formula.
///
/// [`exp`] and [`crate::Se3::exp`] pass A = sin θ/θ and B = (1 − cos θ)/θ² (series near 0).
/// A unit axis ω̂ turned by a known angle (sin θ, cos θ already computed, as in the
/// product-of-exponentials kernels) passes φ = ω̂, θ = 1, A = sin θ, B = 1 − cos θ, which is the
/// textbook R = I + sin θ [ω̂] + (1 − cos θ)[ω̂]².
#[inline(always)]
pub fn rotation_from_coefficients(phi: &Vector3<f64>, theta: f64, a: f64, b: f64) -> Matrix3<f64> {
    let (x, y, z) = (phi.x, phi.y, phi.z);
    let d = 1.0 - b * theta * theta;
    let (bxy, bxz, byz) = (b * x * y, b * x * z, b * y * z);
    let (ax, ay, az) = (a * x, a * y, a * z);
    Matrix3::new(
        d + b * x * x,
        bxy - az,
        bxz + ay,
        bxy + az,
        d + b * y * y,
        byz - ax,
        bxz - ay,
        byz + ax,
        d + b * z * z,
    )
}

/// Angle, sine and cosine of a rotation, and vee(R − Rᵀ) = 2 sin θ ω̂:
/// θ = atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2) ∈ [0, π].
///
/// The atan2 form keeps θ accurate both near 0 (where acos loses half the digits) and near π;
/// the returned sine and cosine are read off R, not recomputed from θ.
#[inline]
pub(crate) fn angle(r: &Matrix3<f64>) -> (f64, f64, f64, Vector3<f64>) {
    let axis2 = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    );
    let s = 0.5 * axis2.norm();
    let c = 0.5 * (r.trace() - 1.0);
    (s.atan2(c), s, c, axis2)
}

/// log R = φ = ω̂θ with θ ∈ [0, π]: the exponential coordinates of a rotation.
///
/// - θ = atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2).
/// - cos θ > 0: φ = vee(R − Rᵀ) θ / (2 sin θ), with sin θ = ‖vee(R − Rᵀ)‖/2 (so θ/sin θ → 1
///   smoothly as θ → 0, and φ = 0 at R = I).
/// - cos θ ≤ 0 (θ ≥ π/2, including θ = π): the axis comes from the symmetric part,
///   ω̂ω̂ᵀ = ((R + Rᵀ)/2 − cos θ I)/(1 − cos θ); the column with the largest diagonal entry
///   (≥ 1/3) is normalised, so nothing is divided by a small number; its sign is chosen so
///   that ω̂ · vee(R − Rᵀ) ≥ 0. At θ = π exactly, ω̂ and −ω̂ are both valid.
#[inline]
pub fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    let (theta, s, c, axis2) = angle(r);
    log_from_angle(r, theta, s, c, &axis2)
}

/// [`log`] given the output of [`angle`].
#[inline]
pub(crate) fn log_from_angle(
    r: &Matrix3<f64>,
    theta: f64,
    s: f64,
    c: f64,
    axis2: &Vector3<f64>,
) -> Vector3<f64> {
    if c > 0.0 {
        if s == 0.0 {
            return Vector3::zeros();
        }
        return axis2 * (0.5 * theta / s);
    }
    let inv = 1.0 / (1.0 - c);
    let sym = |i: usize, j: usize| 0.5 * (r[(i, j)] + r[(j, i)]) * inv;
    let diag = [
        (r[(0, 0)] - c) * inv,
        (r[(1, 1)] - c) * inv,
        (r[(2, 2)] - c) * inv,
    ];
    let k = if diag[0] >= diag[1] && diag[0] >= diag[2] {
        0
    } else if diag[1] >= diag[2] {
        1
    } else {
        2
    };
    let mut u = Vector3::zeros();
    for i in 0..3 {
        u[i] = if i == k { diag[k] } else { sym(i, k) };
    }
    let n = u.norm();
    if n > 0.0 {
        u /= n;
    }
    if u.dot(axis2) < 0.0 {
        u = -u;
    }
    u * theta
}

/// Checks that R is a rotation: finite, max |RᵀR − I| ≤ `tolerance`, det R > 0.
pub fn check_rotation(r: &Matrix3<f64>, tolerance: f64) -> Result<(), LieError> {
    if !r.iter().all(|x| x.is_finite()) {
        return Err(LieError::NonFinite {
            what: "rotation matrix",
        });
    }
    let err = (r.transpose() * r - Matrix3::identity()).amax();
    let det = r.determinant();
    if err > tolerance || det <= 0.0 {
        return Err(LieError::NotARotation {
            orthogonality_error: err,
            det,
            tolerance,
        });
    }
    Ok(())
}

/// A rotation read from user input: [`check_rotation`] within `tolerance`, then replaced by
/// [`nearest_rotation`] when it is more than 1e-14 from orthonormal (so rounded input becomes
/// an exact rotation, and an exact one is kept bit for bit).
pub fn rotation_from_matrix(r: &Matrix3<f64>, tolerance: f64) -> Result<Matrix3<f64>, LieError> {
    check_rotation(r, tolerance)?;
    Ok(
        if (r.transpose() * r - Matrix3::identity()).amax() > 1e-14 {
            nearest_rotation(r)
        } else {
            *r
        },
    )
}

/// The rotation nearest to M in the Frobenius norm: U Vᵀ from the SVD M = U Σ Vᵀ
/// (with the sign of the last singular direction flipped if det(UVᵀ) < 0).
///
/// Use after [`check_rotation`] with a loose tolerance to turn user-typed, rounded matrices into
/// exact rotations.
pub fn nearest_rotation(m: &Matrix3<f64>) -> Matrix3<f64> {
    // A non-finite M comes back unchanged (nalgebra's SVD could iterate without end or panic
    // on it); the iterations are bounded besides.
    if !m.iter().all(|x| x.is_finite()) {
        return *m;
    }
    // U Vᵀ does not change with a positive scale of M: scaled by its largest entry, entries of
    // 1e154 and more (whose squares overflow inside the SVD: NaN) or of 1e-300 are as good as
    // any other.
    let largest = m.amax();
    let scaled = if largest > 0.0 { m / largest } else { *m };
    let Some(svd) = nalgebra::SVD::try_new(scaled, true, true, f64::EPSILON, 1000) else {
        return *m;
    };
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return *m;
    };
    let mut u = u;
    if (u * v_t).determinant() < 0.0 {
        u.column_mut(2).neg_mut();
    }
    u * v_t
}

/// How far M is from SO(3): ‖MᵀM − I‖_F when det M > 0, +∞ otherwise (an improper or singular
/// matrix is no rotation however orthogonal; *Modern Robotics*' `DistanceToSO3` returns 1e9
/// there). 0 exactly for the identity; about 2‖E‖ for R + E with E small. Non-finite M: NaN.
pub fn distance_to_so3(m: &Matrix3<f64>) -> f64 {
    if !m.iter().all(|x| x.is_finite()) {
        return f64::NAN;
    }
    if m.determinant() > 0.0 {
        (m.transpose() * m - Matrix3::identity()).norm()
    } else {
        f64::INFINITY
    }
}

/// R_x(a): rotation by angle a about x.
pub fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

/// R_y(a): rotation by angle a about y.
pub fn rot_y(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// R_z(a): rotation by angle a about z.
pub fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// URDF roll-pitch-yaw (fixed axes x, y, z): R = R_z(yaw) R_y(pitch) R_x(roll).
pub fn from_rpy(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

/// The inverse of [`from_rpy`]: (roll, pitch, yaw) with pitch ∈ [−π/2, π/2], exact to
/// rounding for every rotation, the gimbal lock and its neighbourhood included.
///
/// yaw = atan2(r₂₁, r₁₁); then R' = R_z(−yaw) R = R_y(pitch) R_x(roll) (its first column has
/// no y component by the choice of yaw), so pitch = atan2(−r'₃₁, r'₁₁) and
/// roll = atan2(−r'₂₃, r'₂₂), each from entries of full magnitude. (The textbook
/// roll = atan2(r₃₂, r₃₃) divides rounding by cos pitch: near the lock its error grew to
/// 3e-5 measured.) At the lock itself yaw is 0 and roll carries the rotation about the vertical.
pub fn to_rpy(r: &Matrix3<f64>) -> [f64; 3] {
    let yaw = r[(1, 0)].atan2(r[(0, 0)]);
    let (sy, cy) = yaw.sin_cos();
    // R' = R_z(−yaw) R: rows 1 and 2 mixed, row 3 unchanged.
    let p11 = cy * r[(0, 0)] + sy * r[(1, 0)];
    let p22 = -sy * r[(0, 1)] + cy * r[(1, 1)];
    let p23 = -sy * r[(0, 2)] + cy * r[(1, 2)];
    let pitch = (-r[(2, 0)]).atan2(p11);
    let roll = (-p23).atan2(p22);
    [roll, pitch, yaw]
}

/// The rotation of a quaternion (x, y, z, w), normalised first; error if zero or non-finite.
pub fn from_quaternion(q: [f64; 4]) -> Result<Matrix3<f64>, LieError> {
    if !q.iter().all(|x| x.is_finite()) {
        return Err(LieError::NonFinite { what: "quaternion" });
    }
    let quat = Quaternion::new(q[3], q[0], q[1], q[2]);
    if quat.norm() < 1e-12 {
        return Err(LieError::ZeroVector { what: "quaternion" });
    }
    Ok(*UnitQuaternion::from_quaternion(quat)
        .to_rotation_matrix()
        .matrix())
}

/// The unit quaternion (x, y, z, w) of a rotation, with w ≥ 0.
pub fn to_quaternion(r: &Matrix3<f64>) -> [f64; 4] {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [s * q.i, s * q.j, s * q.k, s * q.w]
}
