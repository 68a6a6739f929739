//! Wrenches F = (m, f): moments and forces, dual to twists.

use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

use nalgebra::{Vector3, Vector6};

use crate::error::LieError;
use crate::twist::Twist;

/// A wrench F = (m, f): moment m about the frame's origin, then force f, both expressed in
/// the same frame.
///
/// Wrenches change frame with the *transpose* of the adjoint: F_b = \[Ad_{T_ab}\]ᵀ F_a
/// ([`crate::Se3::adjoint_transpose_apply`]), so that the power VᵀF ([`Wrench::power`]) is the
/// same in every frame.
#[derive(Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    /// Moment m.
    pub m: Vector3<f64>,
    /// Force f.
    pub f: Vector3<f64>,
}

impl Wrench {
    /// F = (m, f).
    #[inline]
    pub fn new(m: Vector3<f64>, f: Vector3<f64>) -> Self {
        Self { m, f }
    }

    /// The wrench of a force f applied at point r (both in the same frame): m = r × f.
    pub fn from_force_at_point(f: Vector3<f64>, r: Vector3<f64>) -> Self {
        Self { m: r.cross(&f), f }
    }

    /// From a 6-vector (m₁, m₂, m₃, f₁, f₂, f₃).
    #[inline]
    pub fn from_vector(x: &Vector6<f64>) -> Self {
        Self {
            m: x.fixed_rows::<3>(0).into_owned(),
            f: x.fixed_rows::<3>(3).into_owned(),
        }
    }

    /// From six numbers (m, f), checking the length and that all are finite.
    pub fn try_from_slice(x: &[f64]) -> Result<Self, LieError> {
        if x.len() != 6 {
            return Err(LieError::WrongLength {
                what: "a wrench (m, f)",
                expected: 6,
                got: x.len(),
            });
        }
        if !x.iter().all(|a| a.is_finite()) {
            return Err(LieError::NonFinite { what: "wrench" });
        }
        Ok(Self::from_vector(&Vector6::from_column_slice(x)))
    }

    /// The 6-vector (m, f).
    #[inline]
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(self.m.x, self.m.y, self.m.z, self.f.x, self.f.y, self.f.z)
    }

    /// Power P = VᵀF = ω·m + v·f delivered to a twist (both in the same frame).
    #[inline]
    pub fn power(&self, twist: &Twist) -> f64 {
        twist.w.dot(&self.m) + twist.v.dot(&self.f)
    }
}

impl Add for Wrench {
    type Output = Wrench;
    fn add(self, rhs: Wrench) -> Wrench {
        Wrench::new(self.m + rhs.m, self.f + rhs.f)
    }
}

impl Sub for Wrench {
    type Output = Wrench;
    fn sub(self, rhs: Wrench) -> Wrench {
        Wrench::new(self.m - rhs.m, self.f - rhs.f)
    }
}

impl Neg for Wrench {
    type Output = Wrench;
    fn neg(self) -> Wrench {
        Wrench::new(-self.m, -self.f)
    }
}

impl Mul<f64> for Wrench {
    type Output = Wrench;
    fn mul(self, k: f64) -> Wrench {
        Wrench::new(self.m * k, self.f * k)
    }
}

/// Prints `(m₁, m₂, m₃ | f₁, f₂, f₃)` (precision from the formatter, 6 by default).
impl fmt::Display for Wrench {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = f.precision().unwrap_or(6);
        let (m, g) = (&self.m, &self.f);
        write!(
            f,
            "({} | {})",
            crate::display::fixed_list(&[m.x, m.y, m.z], p),
            crate::display::fixed_list(&[g.x, g.y, g.z], p)
        )
    }
}

impl fmt::Debug for Wrench {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "Wrench {{ m: [{:?}, {:?}, {:?}], f: [{:?}, {:?}, {:?}] }}",
            self.m.x, self.m.y, self.m.z, self.f.x, self.f.y, self.f.z
        )
    }
}
