//! Screw axes: S ↔ {q, ŝ, h} (point on the axis, direction, pitch).

use std::fmt;

use nalgebra::Vector3;

use crate::display::{fixed, fixed_list};
use crate::error::LieError;
use crate::twist::Twist;

/// A normalised screw axis S = (ω, v): either ‖ω‖ = 1 (a rotating screw of finite pitch),
/// or ω = 0 and ‖v‖ = 1 (a pure translation, infinite pitch).
///
/// For a rotating screw through point q with direction ŝ and pitch h:
/// S = (ŝ, −ŝ × q + hŝ). Back: ŝ = ω, h = ŝᵀv, and the point of the axis closest to the
/// origin is q = ŝ × v. A twist about S at speed θ̇ is V = S θ̇.
#[derive(Clone, Copy, PartialEq)]
pub struct ScrewAxis {
    s: Twist,
}

impl ScrewAxis {
    /// S = (ŝ, −ŝ × q + hŝ) for a screw through `point` q along `direction` ŝ (normalised here)
    /// with pitch h (metres per radian; 0 for a revolute joint).
    pub fn from_point_direction_pitch(
        point: Vector3<f64>,
        direction: Vector3<f64>,
        pitch: f64,
    ) -> Result<Self, LieError> {
        if !point.iter().chain(direction.iter()).all(|x| x.is_finite()) || !pitch.is_finite() {
            return Err(LieError::NonFinite { what: "screw axis" });
        }
        let n = direction.norm();
        if n == 0.0 {
            return Err(LieError::ZeroVector {
                what: "screw direction",
            });
        }
        let s = direction / n;
        Ok(Self {
            s: Twist::new(s, point.cross(&s) + s * pitch),
        })
    }

    /// A zero-pitch (revolute) screw through `point` along `direction`: S = (ŝ, −ŝ × q).
    pub fn revolute(point: Vector3<f64>, direction: Vector3<f64>) -> Result<Self, LieError> {
        Self::from_point_direction_pitch(point, direction, 0.0)
    }

    /// A pure translation (prismatic, infinite pitch) along `direction`: S = (0, v̂).
    pub fn prismatic(direction: Vector3<f64>) -> Result<Self, LieError> {
        if !direction.iter().all(|x| x.is_finite()) {
            return Err(LieError::NonFinite { what: "screw axis" });
        }
        let n = direction.norm();
        if n == 0.0 {
            return Err(LieError::ZeroVector {
                what: "translation direction",
            });
        }
        Ok(Self {
            s: Twist::new(Vector3::zeros(), direction / n),
        })
    }

    /// The screw axis and speed of a twist: V = S θ̇.
    ///
    /// If ω ≠ 0: θ̇ = ‖ω‖, S = V/‖ω‖. If ω = 0 (exactly): θ̇ = ‖v‖, S = (0, v/‖v‖), a pure
    /// translation. A zero or non-finite twist is an error.
    pub fn from_twist(twist: &Twist) -> Result<(Self, f64), LieError> {
        if !twist.is_finite() {
            return Err(LieError::NonFinite { what: "twist" });
        }
        let wn = twist.w.norm();
        if wn > 0.0 {
            return Ok((
                Self {
                    s: *twist * (1.0 / wn),
                },
                wn,
            ));
        }
        let vn = twist.v.norm();
        if vn > 0.0 {
            return Ok((
                Self {
                    s: Twist::new(Vector3::zeros(), twist.v / vn),
                },
                vn,
            ));
        }
        Err(LieError::ZeroVector { what: "twist" })
    }

    /// Wraps a twist that the caller guarantees to be normalised (‖ω‖ = 1, or ω = 0 and
    /// ‖v‖ = 1).
    #[inline]
    pub fn from_unit_twist_unchecked(s: Twist) -> Self {
        Self { s }
    }

    /// The unit twist S = (ω, v).
    #[inline]
    pub fn twist(&self) -> &Twist {
        &self.s
    }

    /// The twist V = S θ̇ about this axis at speed θ̇ (or the exponential coordinates Sθ).
    #[inline]
    pub fn to_twist(&self, theta_dot: f64) -> Twist {
        self.s * theta_dot
    }

    /// True for a pure translation (ω = 0, infinite pitch).
    #[inline]
    pub fn is_pure_translation(&self) -> bool {
        self.s.w == Vector3::zeros()
    }

    /// The unit direction ŝ of the axis: ω, or v for a pure translation.
    pub fn direction(&self) -> Vector3<f64> {
        if self.is_pure_translation() {
            self.s.v
        } else {
            self.s.w
        }
    }

    /// The pitch h = ŝᵀv (translation per radian); `None` for a pure translation
    /// (infinite pitch).
    pub fn pitch(&self) -> Option<f64> {
        (!self.is_pure_translation()).then(|| self.s.w.dot(&self.s.v))
    }

    /// The point of the axis closest to the origin, q = ŝ × v; `None` for a pure translation
    /// (its direction is all that is defined).
    pub fn point(&self) -> Option<Vector3<f64>> {
        (!self.is_pure_translation()).then(|| self.s.w.cross(&self.s.v))
    }
}

impl fmt::Display for ScrewAxis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = f.precision().unwrap_or(6);
        let d = self.direction();
        match (self.point(), self.pitch()) {
            (Some(q), Some(h)) => write!(
                f,
                "screw along ({}) through ({}), pitch {}",
                fixed_list(d.as_slice(), p),
                fixed_list(q.as_slice(), p),
                fixed(h, p)
            ),
            _ => write!(
                f,
                "pure translation along ({})",
                fixed_list(d.as_slice(), p)
            ),
        }
    }
}

impl fmt::Debug for ScrewAxis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ScrewAxis {{ s: {:?} }}", self.s)
    }
}
