//! Twists V = (ω, v): spatial velocities and elements of se(3).

use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

use nalgebra::{Matrix4, Matrix6, Vector3, Vector6};

use crate::error::LieError;
use crate::so3;

/// A twist V = (ω, v) ∈ se(3), ordered angular then linear as in *Modern Robotics*.
///
/// As a velocity expressed in frame {a}: ω is the angular velocity and v the linear velocity
/// of the point of the body at the origin of {a}. As exponential coordinates ξ = Sθ it
/// describes a rigid displacement (see [`crate::Se3::exp`]). Change frames with the adjoint,
/// `t_ab.adjoint_apply(&v_b) == v_a`.
#[derive(Clone, Copy, PartialEq, Default)]
pub struct Twist {
    /// Angular part ω.
    pub w: Vector3<f64>,
    /// Linear part v.
    pub v: Vector3<f64>,
}

impl Twist {
    /// V = (ω, v).
    #[inline]
    pub fn new(w: Vector3<f64>, v: Vector3<f64>) -> Self {
        Self { w, v }
    }

    /// The zero twist.
    pub fn zero() -> Self {
        Self::default()
    }

    /// From a 6-vector (ω₁, ω₂, ω₃, v₁, v₂, v₃).
    #[inline]
    pub fn from_vector(x: &Vector6<f64>) -> Self {
        Self {
            w: x.fixed_rows::<3>(0).into_owned(),
            v: x.fixed_rows::<3>(3).into_owned(),
        }
    }

    /// From six numbers (ω, v), checking the length and that all are finite.
    pub fn try_from_slice(x: &[f64]) -> Result<Self, LieError> {
        if x.len() != 6 {
            return Err(LieError::WrongLength {
                what: "a twist (ω, v)",
                expected: 6,
                got: x.len(),
            });
        }
        if !x.iter().all(|a| a.is_finite()) {
            return Err(LieError::NonFinite { what: "twist" });
        }
        Ok(Self::from_vector(&Vector6::from_column_slice(x)))
    }

    /// The 6-vector (ω, v).
    #[inline]
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(self.w.x, self.w.y, self.w.z, self.v.x, self.v.y, self.v.z)
    }

    /// \[V\] = [[\[ω\], v], [0, 0]] ∈ se(3), the 4x4 matrix form.
    pub fn hat(&self) -> Matrix4<f64> {
        let mut m = Matrix4::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&so3::hat(&self.w));
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.v);
        m
    }

    /// The inverse of [`Twist::hat`]: (vee of the skew 3x3 block, last column).
    pub fn vee(m: &Matrix4<f64>) -> Self {
        let w3 = m.fixed_view::<3, 3>(0, 0).into_owned();
        Self {
            w: so3::vee(&w3),
            v: m.fixed_view::<3, 1>(0, 3).into_owned(),
        }
    }

    /// \[ad_V\] = [[\[ω\], 0], [\[v\], \[ω\]]]: the Lie bracket as a 6x6 matrix, \[ad_V1\] V2 = [V1, V2].
    pub fn ad(&self) -> Matrix6<f64> {
        let w = so3::hat(&self.w);
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&so3::hat(&self.v));
        m
    }

    /// The Lie bracket [V1, V2] = \[ad_V1\] V2 = (ω₁ × ω₂, v₁ × ω₂ + ω₁ × v₂),
    /// equal to vee(\[V1\]\[V2\] − \[V2\]\[V1\]).
    #[inline]
    pub fn bracket(&self, other: &Twist) -> Twist {
        Twist {
            w: self.w.cross(&other.w),
            v: self.v.cross(&other.w) + self.w.cross(&other.v),
        }
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.w.iter().chain(self.v.iter()).all(|x| x.is_finite())
    }
}

impl Add for Twist {
    type Output = Twist;
    fn add(self, rhs: Twist) -> Twist {
        Twist::new(self.w + rhs.w, self.v + rhs.v)
    }
}

impl Sub for Twist {
    type Output = Twist;
    fn sub(self, rhs: Twist) -> Twist {
        Twist::new(self.w - rhs.w, self.v - rhs.v)
    }
}

impl Neg for Twist {
    type Output = Twist;
    fn neg(self) -> Twist {
        Twist::new(-self.w, -self.v)
    }
}

impl Mul<f64> for Twist {
    type Output = Twist;
    /// Vθ: scales both parts.
    #[inline]
    fn mul(self, k: f64) -> Twist {
        Twist::new(self.w * k, self.v * k)
    }
}

/// Prints `(ω₁, ω₂, ω₃ | v₁, v₂, v₃)` (precision from the formatter, 6 by default).
impl fmt::Display for Twist {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = f.precision().unwrap_or(6);
        let (w, v) = (&self.w, &self.v);
        write!(
            f,
            "({} | {})",
            crate::display::fixed_list(&[w.x, w.y, w.z], p),
            crate::display::fixed_list(&[v.x, v.y, v.z], p)
        )
    }
}

impl fmt::Debug for Twist {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "Twist {{ w: [{:?}, {:?}, {:?}], v: [{:?}, {:?}, {:?}] }}",
            self.w.x, self.w.y, self.w.z, self.v.x, self.v.y, self.v.z
        )
    }
}
