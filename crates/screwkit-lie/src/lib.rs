//! # screwkit-lie
//!
//! The rigid-body groups behind screw theory, with the conventions of Lynch & Park,
//! *Modern Robotics*:
//!
//! - [`so3`]: rotations — hat/vee, Rodrigues' exponential, logarithm (robust at θ → 0 and θ = π),
//!   roll-pitch-yaw and quaternions.
//! - [`Se3`]: rigid transforms T = (R, p) — composition, inverse, exp/log, adjoint.
//! - [`Twist`] V = (ω, v), [`Wrench`] F = (m, f), [`ScrewAxis`] S ↔ (ŝ, q, h).
//! - [`Frame`]: space or body, the frame a twist or Jacobian is expressed in.
//! - [`fma`]: the multiply-add policies, the CPU's kernel path and the run-time dispatch of
//!   the single calls' kernels; [`lanes`]: f64 lanes of the widest vector unit (8 on AVX-512,
//!   4 on AVX2 and portably) and the batch kernels' dispatch;
//!   [`trig`]: the inlined, vectorisable sine/cosine those kernels use.
//!
//! Conventions: twists and screw axes are ordered (ω, v); wrenches (m, f). A twist changes frame
//! with the adjoint, V_a = \[Ad_{T_ab}\] V_b; a wrench with its transpose,
//! F_b = \[Ad_{T_ab}\]ᵀ F_a, so that the power VᵀF is the same in every frame.
//! Units: metres, radians. Everything is `f64`, fixed-size and allocation-free.
//!
//! ```
//! use screwkit_lie::{Se3, Twist};
//! use nalgebra::Vector3;
//!
//! // A screw motion: rotate 90° about z while advancing 0.1 m along it.
//! let xi = Twist::new(Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.0, 0.1 / std::f64::consts::FRAC_PI_2))
//!     * std::f64::consts::FRAC_PI_2;
//! let t = Se3::exp(&xi);
//! assert!((t.translation().z - 0.1).abs() < 1e-15);
//! let back = t.log();
//! assert!((back.to_vector() - xi.to_vector()).norm() < 1e-14);
//! ```

pub mod angle;
pub mod display;
pub mod error;
pub mod fma;
pub mod frame;
pub mod lanes;
pub mod screw;
pub mod se3;
pub mod so3;
pub mod trajectory;
pub mod trig;
pub mod twist;
pub mod wrench;

pub use error::LieError;
pub use frame::Frame;
pub use screw::ScrewAxis;
pub use se3::Se3;
pub use twist::Twist;
pub use wrench::Wrench;

pub use nalgebra;
