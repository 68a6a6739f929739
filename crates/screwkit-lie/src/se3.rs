//! SE(3): rigid transforms T = (R, p), their exponential, logarithm and adjoint.

use std::fmt;
use std::ops::Mul;

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3};

use crate::error::LieError;
use crate::fma::{MulAdd, Plain};
use crate::screw::ScrewAxis;
use crate::so3;
use crate::twist::Twist;
use crate::wrench::Wrench;

/// A rigid transform T = (R, p) ∈ SE(3), stored as a rotation and a translation (not 4x4).
///
/// As a homogeneous matrix T = [[R, p], [0, 1]]. Name values by their frames: `t_sb` is the
/// pose of frame {b} in frame {s}, so `t_sb * t_bc = t_sc` and `t_sb.transform_point(x_b) = x_s`.
///
/// The rotation is trusted to be in SO(3): the checked constructors ([`Se3::from_homogeneous`],
/// [`Se3::from_parts`], …) validate user input; [`Se3::from_parts_unchecked`] is for values
/// computed from rotations.
#[derive(Clone, Copy, PartialEq)]
pub struct Se3 {
    rotation: Matrix3<f64>,
    translation: Vector3<f64>,
}

/// D = (1 − (θ/2) cot(θ/2)) / θ², the [ω]² coefficient of V⁻¹ in the SE(3) logarithm, given
/// θ with its sine s and cosine c.
///
/// Series Σ |B₂ₙ| θ²ⁿ⁻²/(2n)! = 1/12 + θ²/720 + θ⁴/30240 + θ⁶/1209600 + θ⁸/47900160 below
/// θ = 0.25 (truncation < 1e-15); above, cot(θ/2) = s/(1 − c), where 1 − c ≥ 0.03 does not
/// cancel and s → 0 at θ = π is harmless (D(π) = 1/π²). The absolute error of (θ/2)cot(θ/2)
/// is what reaches v, and it stays at a few ulp everywhere.
#[inline]
fn log_coefficient(theta: f64, s: f64, c: f64) -> f64 {
    let t2 = theta * theta;
    if theta < 0.25 {
        1.0 / 12.0
            + t2 * (1.0 / 720.0
                + t2 * (1.0 / 30_240.0 + t2 * (1.0 / 1_209_600.0 + t2 / 47_900_160.0)))
    } else {
        (1.0 - 0.5 * theta * s / (1.0 - c)) / t2
    }
}

/// The translation of the SE(3) exponential, p = (a I + b\[ω\] + c\[ω\]²) v
/// = a v + b (ω × v) + c ω × (ω × v), given ω × v and ω × (ω × v): the one home of this formula.
///
/// [`Se3::exp`] of a twist ξ = (ω, v) passes a = 1, b = (1 − cos θ)/θ², c = (θ − sin θ)/θ³
/// (θ = ‖ω‖). A unit screw S = (ω̂, v) turned by θ (sin θ, cos θ known, ω̂ × v and
/// ω̂ × (ω̂ × v) precomputed, as in the product-of-exponentials kernels) passes a = θ,
/// b = 1 − cos θ, c = θ − sin θ: the textbook p = G(θ) v, G(θ) = Iθ + (1 − cos θ)[ω̂] +
/// (θ − sin θ)[ω̂]² (*Modern Robotics* eq. 3.88). `M` is the multiply-add policy
/// ([`crate::fma`]).
#[inline(always)]
pub fn translation_from_coefficients<M: MulAdd>(
    v: &[f64; 3],
    w_x_v: &[f64; 3],
    w_x_w_x_v: &[f64; 3],
    a: f64,
    b: f64,
    c: f64,
) -> [f64; 3] {
    std::array::from_fn(|i| M::madd(v[i], a, M::madd(w_x_v[i], b, w_x_w_x_v[i] * c)))
}

/// The translation of e^{\[S\]θ} for a unit screw of pitch 0 (a rotation, ω̂ · v = 0), given
/// sin θ, b = 1 − cos θ and ω̂ × v: p = G(θ) v = sin θ v + (1 − cos θ) (ω̂ × v). It is
/// [`translation_from_coefficients`] with a = θ, c = θ − sin θ, where ω̂ × (ω̂ × v) =
/// ω̂ (ω̂ · v) − v = −v cancels the θ terms exactly: two products per component instead of
/// three, and no θ − sin θ, whose rounding grows with |θ| (≈ ulp(θ)·‖v‖ at |θ| = 100).
/// `M` is the multiply-add policy ([`crate::fma`]).
#[inline(always)]
pub fn translation_of_rotation<M: MulAdd>(
    v: &[f64; 3],
    w_x_v: &[f64; 3],
    s: f64,
    b: f64,
) -> [f64; 3] {
    [
        M::madd(w_x_v[0], b, v[0] * s),
        M::madd(w_x_v[1], b, v[1] * s),
        M::madd(w_x_v[2], b, v[2] * s),
    ]
}

/// How far a 4 × 4 matrix is from SE(3): ‖[[RᵀR, 0], [last row]] − I‖_F for its upper-left R
/// when det R > 0 (so a bottom row other than (0, 0, 0, 1) counts), +∞ otherwise — *Modern
/// Robotics*' `DistanceToSE3`, which returns 1e9 there. Non-finite input: NaN.
pub fn distance_to_se3(m: &Matrix4<f64>) -> f64 {
    if !m.iter().all(|x| x.is_finite()) {
        return f64::NAN;
    }
    let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    if r.determinant() <= 0.0 {
        return f64::INFINITY;
    }
    let mut d = Matrix4::zeros();
    d.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(r.transpose() * r));
    d.set_row(3, &m.row(3));
    (d - Matrix4::identity()).norm()
}

/// The transform nearest to a 4 × 4 matrix: its upper-left block replaced by the nearest
/// rotation ([`crate::so3::nearest_rotation`], proper: det = +1 always), its translation kept
/// and the bottom row (0, 0, 0, 1). Non-finite input is an error.
pub fn project_to_se3(m: &Matrix4<f64>) -> Result<Se3, LieError> {
    if !m.iter().all(|x| x.is_finite()) {
        return Err(LieError::NonFinite { what: "matrix" });
    }
    let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    Ok(Se3::from_parts_unchecked(
        so3::nearest_rotation(&r),
        m.fixed_view::<3, 1>(0, 3).into_owned(),
    ))
}

impl Se3 {
    /// The identity transform (R = I, p = 0).
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// T = (R, p) without validation: the caller guarantees R ∈ SO(3).
    #[inline]
    pub fn from_parts_unchecked(rotation: Matrix3<f64>, translation: Vector3<f64>) -> Self {
        Self {
            rotation,
            translation,
        }
    }

    /// T = (R, p), checking that everything is finite and that R is a rotation
    /// (max |RᵀR − I| ≤ [`so3::DEFAULT_ROTATION_TOLERANCE`], det R > 0).
    pub fn from_parts(rotation: Matrix3<f64>, translation: Vector3<f64>) -> Result<Self, LieError> {
        so3::check_rotation(&rotation, so3::DEFAULT_ROTATION_TOLERANCE)?;
        if !translation.iter().all(|x| x.is_finite()) {
            return Err(LieError::NonFinite {
                what: "translation",
            });
        }
        Ok(Self::from_parts_unchecked(rotation, translation))
    }

    /// A pure translation (R = I).
    pub fn from_translation(translation: Vector3<f64>) -> Self {
        Self::from_parts_unchecked(Matrix3::identity(), translation)
    }

    /// URDF `<origin xyz rpy>`: p = xyz, R = R_z(yaw) R_y(pitch) R_x(roll) (fixed axes).
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Result<Self, LieError> {
        if !xyz.iter().chain(rpy.iter()).all(|x| x.is_finite()) {
            return Err(LieError::NonFinite { what: "xyz/rpy" });
        }
        Ok(Self::from_parts_unchecked(
            so3::from_rpy(rpy[0], rpy[1], rpy[2]),
            Vector3::from(xyz),
        ))
    }

    /// p = xyz and R from the quaternion (x, y, z, w), which is normalised first.
    pub fn from_translation_quaternion(xyz: [f64; 3], quat: [f64; 4]) -> Result<Self, LieError> {
        if !xyz.iter().all(|x| x.is_finite()) {
            return Err(LieError::NonFinite {
                what: "translation",
            });
        }
        Ok(Self::from_parts_unchecked(
            so3::from_quaternion(quat)?,
            Vector3::from(xyz),
        ))
    }

    /// From a homogeneous 4x4 matrix [[R, p], [0, 1]], validated: finite, last row
    /// `[0, 0, 0, 1]`, R orthonormal within [`so3::DEFAULT_ROTATION_TOLERANCE`] with det +1.
    pub fn from_homogeneous(m: &Matrix4<f64>) -> Result<Self, LieError> {
        Self::from_homogeneous_with_tolerance(m, so3::DEFAULT_ROTATION_TOLERANCE)
    }

    /// Like [`Se3::from_homogeneous`] with a chosen tolerance on max |RᵀR − I|; when the
    /// check passes, R is replaced by the nearest exact rotation ([`so3::nearest_rotation`]),
    /// so rounded input (e.g. 4 decimals, tolerance 1e-3) becomes a proper transform.
    pub fn from_homogeneous_with_tolerance(
        m: &Matrix4<f64>,
        tolerance: f64,
    ) -> Result<Self, LieError> {
        if !m.iter().all(|x| x.is_finite()) {
            return Err(LieError::NonFinite {
                what: "homogeneous matrix",
            });
        }
        let row = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]];
        let tol_row = tolerance.max(1e-12);
        if row[0].abs() > tol_row
            || row[1].abs() > tol_row
            || row[2].abs() > tol_row
            || (row[3] - 1.0).abs() > tol_row
        {
            return Err(LieError::BadLastRow { row });
        }
        let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
        let r = so3::rotation_from_matrix(&r, tolerance)?;
        Ok(Self::from_parts_unchecked(
            r,
            m.fixed_view::<3, 1>(0, 3).into_owned(),
        ))
    }

    /// From 16 numbers of a homogeneous matrix in row-major order, validated as in
    /// [`Se3::from_homogeneous_with_tolerance`].
    pub fn from_row_major(values: &[f64], tolerance: f64) -> Result<Self, LieError> {
        if values.len() != 16 {
            return Err(LieError::WrongLength {
                what: "a 4x4 matrix",
                expected: 16,
                got: values.len(),
            });
        }
        Self::from_homogeneous_with_tolerance(&Matrix4::from_row_slice(values), tolerance)
    }

    /// Writes T as a row-major 4 × 4 into `out[..16]` (the inverse of [`Se3::from_row_major`];
    /// the layout of every flat pose buffer).
    #[inline]
    pub fn write_row_major(&self, out: &mut [f64]) {
        let (r, p) = (&self.rotation, &self.translation);
        for i in 0..3 {
            out[4 * i] = r[(i, 0)];
            out[4 * i + 1] = r[(i, 1)];
            out[4 * i + 2] = r[(i, 2)];
            out[4 * i + 3] = p[i];
        }
        out[12..16].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    }

    /// The rotation R.
    #[inline]
    pub fn rotation(&self) -> &Matrix3<f64> {
        &self.rotation
    }

    /// The translation p.
    #[inline]
    pub fn translation(&self) -> &Vector3<f64> {
        &self.translation
    }

    /// The homogeneous matrix [[R, p], [0, 1]].
    pub fn to_homogeneous(&self) -> Matrix4<f64> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotation);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        m
    }

    /// The rotation as URDF roll, pitch, yaw ([`so3::to_rpy`]).
    pub fn rpy(&self) -> [f64; 3] {
        so3::to_rpy(&self.rotation)
    }

    /// The rotation as a unit quaternion (x, y, z, w), w ≥ 0.
    pub fn quaternion(&self) -> [f64; 4] {
        so3::to_quaternion(&self.rotation)
    }

    /// Composition T_ac = T_ab T_bc: (R_ab R_bc, R_ab p_bc + p_ab).
    #[inline]
    pub fn compose(&self, other: &Se3) -> Se3 {
        Se3 {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// T⁻¹ = (Rᵀ, −Rᵀp).
    #[inline]
    pub fn inverse(&self) -> Se3 {
        let rt = self.rotation.transpose();
        Se3 {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// T⁻¹ S computed without forming T⁻¹: (Rᵀ R_S, Rᵀ (p_S − p)).
    #[inline]
    pub fn inverse_compose(&self, other: &Se3) -> Se3 {
        let rt = self.rotation.transpose();
        Se3 {
            rotation: rt * other.rotation,
            translation: rt * (other.translation - self.translation),
        }
    }

    /// T x = R x + p for a point x.
    #[inline]
    pub fn transform_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * x + self.translation
    }

    /// R x for a free vector x (directions, velocities: translation does not apply).
    #[inline]
    pub fn transform_vector(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * x
    }

    /// e^\[ξ\] for any twist ξ = (ω, v) (unit or not; for a screw axis S and distance θ, ξ = Sθ):
    ///
    /// - θ = ‖ω‖, R = I + A\[ω\] + B\[ω\]²,
    /// - p = (I + B\[ω\] + C\[ω\]²) v,
    ///
    /// with A = sin θ/θ, B = (1 − cos θ)/θ², C = (θ − sin θ)/θ³ (series near θ = 0). For a unit
    /// axis ω̂ this is the textbook p = G(θ)v, G(θ) = Iθ + (1 − cos θ)[ω̂] + (θ − sin θ)[ω̂]²;
    /// for ω = 0 it is the pure translation p = v.
    #[inline]
    pub fn exp(xi: &Twist) -> Se3 {
        let w = &xi.w;
        let theta = w.norm();
        let (a, b, cc) = so3::exp_coefficients(theta);
        let rotation = so3::rotation_from_coefficients(w, theta, a, b);
        let wxv = w.cross(&xi.v);
        let translation = translation_from_coefficients::<Plain>(
            &xi.v.into(),
            &wxv.into(),
            &w.cross(&wxv).into(),
            1.0,
            b,
            cc,
        );
        Se3 {
            rotation,
            translation: translation.into(),
        }
    }

    /// e^\[S\]θ for a screw axis S and a distance θ along it (radians for a rotating screw,
    /// metres for a pure translation).
    #[inline]
    pub fn exp_screw(screw: &ScrewAxis, theta: f64) -> Se3 {
        Self::exp(&screw.to_twist(theta))
    }

    /// log T = ξ = Sθ, the exponential coordinates of T as a twist (ω, v):
    ///
    /// - ω = log R ([`so3::log`]) with θ = ‖ω‖ ∈ [0, π],
    /// - v = V⁻¹ p with V⁻¹ = I − ½\[ω\] + D\[ω\]², D = (1 − (θ/2) cot(θ/2))/θ²
    ///   (the textbook v_S = G⁻¹(θ) p, G⁻¹(θ) = I/θ − [ω̂]/2 + (1/θ − ½cot(θ/2))[ω̂]², times θ).
    ///
    /// R = I gives the pure translation ξ = (0, p). Accurate near θ = 0 (series) and θ = π.
    pub fn log(&self) -> Twist {
        let (theta, s, c, axis2) = so3::angle(&self.rotation);
        let w = so3::log_from_angle(&self.rotation, theta, s, c, &axis2);
        let d = log_coefficient(theta, s, c);
        let p = &self.translation;
        let wxp = w.cross(p);
        let v = p - wxp * 0.5 + w.cross(&wxp) * d;
        Twist { w, v }
    }

    /// log T as a unit screw axis S and the distance θ along it (T = e^\[S\]θ).
    ///
    /// θ is the rotation angle (in [0, π]) when R ≠ I, otherwise the distance ‖p‖ of a pure
    /// translation. `None` for the identity, which has no axis.
    pub fn log_screw(&self) -> Option<(ScrewAxis, f64)> {
        ScrewAxis::from_twist(&self.log()).ok()
    }

    /// \[Ad_T\] = [[R, 0], [\[p\]R, R]] (6x6, acting on twists ordered (ω, v)).
    pub fn adjoint(&self) -> Matrix6<f64> {
        let r = &self.rotation;
        let pr = so3::hat(&self.translation) * r;
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(r);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&pr);
        m
    }

    /// \[Ad_T\] V without building the 6x6: ω' = Rω, v' = p × (Rω) + Rv.
    ///
    /// With T = T_ab this changes a twist's frame: V_a = \[Ad_{T_ab}\] V_b.
    #[inline]
    pub fn adjoint_apply(&self, twist: &Twist) -> Twist {
        let w = self.rotation * twist.w;
        let v = self.translation.cross(&w) + self.rotation * twist.v;
        Twist { w, v }
    }

    /// \[Ad_T\]⁻¹ V = \[Ad_{T⁻¹}\] V: ω' = Rᵀω, v' = Rᵀ(v − p × ω).
    #[inline]
    pub fn adjoint_inverse_apply(&self, twist: &Twist) -> Twist {
        let rt = self.rotation.transpose();
        Twist {
            w: rt * twist.w,
            v: rt * (twist.v - self.translation.cross(&twist.w)),
        }
    }

    /// \[Ad_T\]ᵀ F without building the 6x6: m' = Rᵀ(m − p × f), f' = Rᵀ f.
    ///
    /// With T = T_ab this changes a wrench's frame from {a} to {b}: F_b = \[Ad_{T_ab}\]ᵀ F_a.
    /// (The transpose, not the adjoint itself: power is frame-invariant,
    /// V_bᵀF_b = V_bᵀ Ad_{T_ab}ᵀ F_a = (Ad_{T_ab} V_b)ᵀ F_a = V_aᵀ F_a.)
    #[inline]
    pub fn adjoint_transpose_apply(&self, wrench: &Wrench) -> Wrench {
        let rt = self.rotation.transpose();
        Wrench {
            m: rt * (wrench.m - self.translation.cross(&wrench.f)),
            f: rt * wrench.f,
        }
    }

    /// Largest absolute difference between the entries of two transforms' (R, p).
    pub fn max_abs_diff(&self, other: &Se3) -> f64 {
        (self.rotation - other.rotation)
            .amax()
            .max((self.translation - other.translation).amax())
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rotation
            .iter()
            .chain(self.translation.iter())
            .all(|x| x.is_finite())
    }
}

impl Default for Se3 {
    fn default() -> Self {
        Self::identity()
    }
}

impl Mul for Se3 {
    type Output = Se3;
    /// T_ab * T_bc = T_ac.
    #[inline]
    fn mul(self, rhs: Se3) -> Se3 {
        self.compose(&rhs)
    }
}

impl Mul<&Se3> for &Se3 {
    type Output = Se3;
    /// T_ab * T_bc = T_ac.
    #[inline]
    fn mul(self, rhs: &Se3) -> Se3 {
        self.compose(rhs)
    }
}

/// Prints the 4x4 homogeneous matrix, one row per line (precision from the formatter, 6 by
/// default).
impl fmt::Display for Se3 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let prec = f.precision().unwrap_or(6);
        let m = self.to_homogeneous();
        for i in 0..4 {
            write!(f, "[")?;
            for j in 0..4 {
                let x = crate::display::fixed(m[(i, j)], prec);
                write!(f, "{}{:>w$}", if j > 0 { " " } else { "" }, x, w = prec + 4)?;
            }
            writeln!(f, "]")?;
        }
        Ok(())
    }
}

impl fmt::Debug for Se3 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.rotation;
        let p = &self.translation;
        write!(
            f,
            "Se3 {{ R: [[{:?}, {:?}, {:?}], [{:?}, {:?}, {:?}], [{:?}, {:?}, {:?}]], p: [{:?}, {:?}, {:?}] }}",
            r[(0, 0)], r[(0, 1)], r[(0, 2)], r[(1, 0)], r[(1, 1)], r[(1, 2)], r[(2, 0)], r[(2, 1)], r[(2, 2)],
            p.x, p.y, p.z
        )
    }
}

/// The four coefficients of the Jacobians of SE(3)'s exponential at θ = ‖ω‖:
/// (1 − cos θ)/θ², (θ − sin θ)/θ³, (θ² + 2 cos θ − 2)/(2θ⁴), (2θ − 3 sin θ + θ cos θ)/(2θ⁵),
/// by their Taylor series below θ = 0.1 (where the last two cancel).
fn jacobian_coefficients(theta: f64) -> [f64; 4] {
    let t2 = theta * theta;
    if theta < 0.1 {
        [
            0.5 - t2 * (1.0 / 24.0 - t2 * (1.0 / 720.0 - t2 / 40_320.0)),
            1.0 / 6.0 - t2 * (1.0 / 120.0 - t2 * (1.0 / 5040.0 - t2 / 362_880.0)),
            1.0 / 24.0 - t2 * (1.0 / 720.0 - t2 * (1.0 / 40_320.0 - t2 / 3_628_800.0)),
            1.0 / 120.0 - t2 * (1.0 / 2520.0 - t2 * (1.0 / 120_960.0 - t2 / 9_979_200.0)),
        ]
    } else {
        let (s, c) = theta.sin_cos();
        [
            (1.0 - c) / t2,
            (theta - s) / (t2 * theta),
            (t2 + 2.0 * c - 2.0) / (2.0 * t2 * t2),
            (2.0 * theta - 3.0 * s + theta * c) / (2.0 * t2 * t2 * theta),
        ]
    }
}

/// The coupling block Q(ω, v) of SE(3)'s left Jacobian (Barfoot, *State Estimation for
/// Robotics*, eq. 7.86b, written for twists ordered (ω, v)):
/// Q = ½[v] + b([ω][v] + [v][ω] + [ω][v][ω]) + c([ω]²[v] + [v][ω]² − 3[ω][v][ω])
///   + d([ω][v][ω]² + [ω]²[v][ω]), with b, c, d the last three [`jacobian_coefficients`].
fn left_jacobian_coupling(xi: &Twist, k: &[f64; 4]) -> Matrix3<f64> {
    let w = so3::hat(&xi.w);
    let v = so3::hat(&xi.v);
    let wv = w * v;
    let vw = v * w;
    let wvw = wv * w;
    let ww = w * w;
    v * 0.5
        + (wv + vw + wvw) * k[1]
        + (ww * v + vw * w - wvw * 3.0) * k[2]
        + (wvw * w + ww * vw) * k[3]
}

/// The left Jacobian of SE(3)'s exponential at ξ = (ω, v): exp(ξ + δ) ≈ exp(J_l(ξ) δ) exp(ξ),
///
/// J_l = [[J, 0], [Q, J]],  J = I + (1 − cos θ)/θ² \[ω\] + (θ − sin θ)/θ³ \[ω\]² (SO(3)'s left
/// Jacobian, the V of [`Se3::exp`]), Q the coupling block of Barfoot's eq. 7.86b; the right
/// Jacobian is J_r(ξ) = J_l(−ξ) (exp(ξ + δ) ≈ exp(ξ) exp(J_r δ)). J_l(ξ) ξ = ξ.
pub fn left_jacobian(xi: &Twist) -> Matrix6<f64> {
    let k = jacobian_coefficients(xi.w.norm());
    let w = so3::hat(&xi.w);
    let j = Matrix3::identity() + w * k[0] + w * w * k[1];
    let q = left_jacobian_coupling(xi, &k);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&j);
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&j);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&q);
    out
}

/// J_l(ξ)⁻¹ = [[J⁻¹, 0], [−J⁻¹ Q J⁻¹, J⁻¹]] with J⁻¹ = I − ½\[ω\] + D\[ω\]² (the V⁻¹ of
/// [`Se3::log`], D = (1 − (θ/2) cot(θ/2))/θ²), defined for θ < 2π (log's θ ≤ π). With
/// ξ = log(T_F⁻¹ T*) it is the derivative of that error: moving T_F by T_F exp(δ) changes ξ by
/// −J_l(ξ)⁻¹ δ (whole-body IK's frame task rows).
pub fn left_jacobian_inverse(xi: &Twist) -> Matrix6<f64> {
    let theta = xi.w.norm();
    let k = jacobian_coefficients(theta);
    let w = so3::hat(&xi.w);
    let (s, c) = theta.sin_cos();
    let jinv = Matrix3::identity() - w * 0.5 + w * w * log_coefficient(theta, s, c);
    let q = left_jacobian_coupling(xi, &k);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&jinv);
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&jinv);
    out.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(-(jinv * q * jinv)));
    out
}

#[cfg(test)]
mod jacobian_tests {
    use super::*;

    fn twists() -> Vec<Twist> {
        let mut out = Vec::new();
        for (i, theta) in [0.0, 1e-9, 1e-4, 0.05, 0.0999, 0.1001, 0.7, 2.0, 3.1]
            .iter()
            .enumerate()
        {
            let axis = Vector3::new(0.3 + i as f64, -0.5, 0.8).normalize();
            out.push(Twist {
                w: axis * *theta,
                v: Vector3::new(0.4, -1.1 + 0.2 * i as f64, 0.6),
            });
        }
        out
    }

    fn vec6(t: &Twist) -> nalgebra::Vector6<f64> {
        nalgebra::Vector6::new(t.w[0], t.w[1], t.w[2], t.v[0], t.v[1], t.v[2])
    }

    fn twist(x: &nalgebra::Vector6<f64>) -> Twist {
        Twist {
            w: Vector3::new(x[0], x[1], x[2]),
            v: Vector3::new(x[3], x[4], x[5]),
        }
    }

    #[test]
    fn left_jacobian_is_the_derivative_of_the_exponential() {
        for xi in twists() {
            let jl = left_jacobian(&xi);
            let t = Se3::exp(&xi);
            let h = 1e-6;
            for k in 0..6 {
                let mut d = nalgebra::Vector6::zeros();
                d[k] = h;
                let p = Se3::exp(&twist(&(vec6(&xi) + d)))
                    .compose(&t.inverse())
                    .log();
                let m = Se3::exp(&twist(&(vec6(&xi) - d)))
                    .compose(&t.inverse())
                    .log();
                let fd = (vec6(&p) - vec6(&m)) / (2.0 * h);
                assert!(
                    (fd - jl.column(k)).norm() < 1e-8,
                    "{xi:?} column {k}: {} vs {fd}",
                    jl.column(k)
                );
            }
            assert!((jl * vec6(&xi) - vec6(&xi)).norm() < 1e-14);
            let inv = left_jacobian_inverse(&xi);
            assert!((inv * jl - Matrix6::identity()).norm() < 1e-12, "{xi:?}");
        }
    }
}

#[cfg(test)]
mod translation_tests {
    use super::*;
    use crate::fma::Plain;
    use crate::ScrewAxis;

    /// The pitch-0 translation equals the general G(θ) v and the exponential's translation, to
    /// rounding, for revolute screws through points at several distances, at angles up to 1e3 —
    /// and at large |θ| it is the more accurate one (no θ − sin θ), measured against a
    /// rotation about the axis point composed directly, R(q) p + (I − R) q with p = 0.
    #[test]
    fn translation_of_rotation_is_the_pitch_zero_exponential() {
        for (k, point) in [
            Vector3::new(0.3, -0.2, 0.7),
            Vector3::new(-2.0, 5.0, 0.01),
            Vector3::zeros(),
        ]
        .into_iter()
        .enumerate()
        {
            let axis = Vector3::new(0.2 + k as f64, -0.6, 0.4).normalize();
            let s = ScrewAxis::from_point_direction_pitch(point, axis, 0.0).unwrap();
            let (w, v) = (s.twist().w, s.twist().v);
            let wv = w.cross(&v);
            let wwv = w.cross(&wv);
            let (va, wva, wwva): ([f64; 3], [f64; 3], [f64; 3]) = (v.into(), wv.into(), wwv.into());
            for theta in [-3.0, -0.4, 0.0, 1e-8, 0.9, 2.5, 40.0, -1e3] {
                let (sn, cs) = f64::sin_cos(theta);
                let lean = translation_of_rotation::<Plain>(&va, &wva, sn, 1.0 - cs);
                let general = translation_from_coefficients::<Plain>(
                    &va,
                    &wva,
                    &wwva,
                    theta,
                    1.0 - cs,
                    theta - sn,
                );
                let direct = point
                    - nalgebra::Rotation3::from_axis_angle(
                        &nalgebra::Unit::new_unchecked(axis),
                        theta,
                    ) * point;
                let scale = 1.0 + point.norm();
                for i in 0..3 {
                    assert!(
                        (lean[i] - direct[i]).abs() <= 4.0 * f64::EPSILON * scale,
                        "{theta}"
                    );
                    assert!(
                        (general[i] - lean[i]).abs()
                            <= 4.0 * f64::EPSILON * scale * (1.0 + theta.abs()),
                        "{theta}"
                    );
                }
                let exp = *Se3::exp(&(*s.twist() * theta)).translation();
                assert!((exp - Vector3::from(lean)).norm() <= 1e-14 * scale * (1.0 + theta.abs()));
            }
        }
    }
}
