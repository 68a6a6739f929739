//! Immutable per-chain data prepared for speed ([`Kinematics`]) and reusable scratch
//! ([`Workspace`]) — the model/data split of Pinocchio.

use nalgebra::{Matrix3, Matrix6xX, Vector3};
use screwkit_lie::fma::MulAdd;
use screwkit_lie::{so3, Se3, Twist};

use crate::columns::{add, cross, Columns, Lane};
use screwkit_model::{Chain, ChainJoint, JointKind};

use crate::error::SolveError;

/// A revolute axis ω that is a coordinate axis (to within 1e-15 per component), with its sign:
/// then T e^{[S]θ} only mixes two columns of R.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Aligned {
    /// Not a coordinate axis.
    General,
    /// ±x (sign).
    X(f64),
    /// ±y (sign).
    Y(f64),
    /// ±z (sign).
    Z(f64),
}

impl Aligned {
    fn of(w: &Vector3<f64>) -> Aligned {
        let tiny = |x: f64| x.abs() < 1e-15;
        let unit = |x: f64| (x.abs() - 1.0).abs() < 1e-15;
        if unit(w.x) && tiny(w.y) && tiny(w.z) {
            Aligned::X(w.x.signum())
        } else if tiny(w.x) && unit(w.y) && tiny(w.z) {
            Aligned::Y(w.y.signum())
        } else if tiny(w.x) && tiny(w.y) && unit(w.z) {
            Aligned::Z(w.z.signum())
        } else {
            Aligned::General
        }
    }
}

/// Per-joint constants of the closed-form exponential of a unit screw S = (ω, v).
#[derive(Debug, Clone)]
pub(crate) struct JointConst {
    pub(crate) prismatic: bool,
    aligned: Aligned,
    /// ω and v of S as plain arrays, for the column kernels.
    w: [f64; 3],
    v: [f64; 3],
    wv: [f64; 3],
    wwv: [f64; 3],
    w_hat: Matrix3<f64>,
    w_hat2: Matrix3<f64>,
    pub(crate) variable: usize,
    pub(crate) multiplier: f64,
    pub(crate) offset: f64,
}

impl JointConst {
    fn new(s: Twist, prismatic: bool, variable: usize, multiplier: f64, offset: f64) -> Self {
        let wv = s.w.cross(&s.v);
        let wwv = s.w.cross(&wv);
        Self {
            prismatic,
            aligned: if prismatic {
                Aligned::General
            } else {
                Aligned::of(&s.w)
            },
            w: s.w.into(),
            v: s.v.into(),
            wv: wv.into(),
            wwv: wwv.into(),
            w_hat: so3::hat(&s.w),
            w_hat2: so3::hat(&s.w) * so3::hat(&s.w),
            variable,
            multiplier,
            offset,
        }
    }

    /// The translation of e^[S]θ of a revolute joint or screw, given (sin θ, cos θ):
    /// θ v + (1 − cos θ) ω×v + (θ − sin θ) ω×(ω×v).
    #[inline(always)]
    fn p_local<A: MulAdd>(&self, theta: f64, s: f64, c: f64) -> [f64; 3] {
        let (omc, tms) = (1.0 - c, theta - s);
        std::array::from_fn(|i| {
            A::madd(
                self.v[i],
                theta,
                A::madd(self.wv[i], omc, self.wwv[i] * tms),
            )
        })
    }

    /// T ← T e^{[S]θ}, given (sin θ, cos θ), without forming e^{[S]θ} where the joint allows it:
    /// prismatic p ← p + θ R v (R unchanged); revolute or screw p ← p + R p_local (see
    /// [`JointConst::p_local`]), then R ← R e^{[ω]θ}, which for ω = ±(a coordinate axis) mixes two
    /// columns of R ([`Columns::rotate_axis`], 4 column multiply-adds) and otherwise is
    /// R (I + sin θ [ω] + (1 − cos θ)[ω]²) (Rodrigues).
    #[inline(always)]
    pub(crate) fn apply<A: MulAdd>(&self, t: &mut Columns, theta: f64, s: f64, c: f64) {
        if self.prismatic {
            t.translate::<A>(&self.v.map(|x| x * theta));
            return;
        }
        let p_local = self.p_local::<A>(theta, s, c);
        match self.aligned {
            Aligned::General => {
                let e = Matrix3::identity() + self.w_hat * s + self.w_hat2 * (1.0 - c);
                *t = t.compose::<A>(&e, &p_local);
            }
            Aligned::X(g) => {
                t.translate::<A>(&p_local);
                t.rotate_axis::<A, 1, 2>(g * s, c);
            }
            Aligned::Y(g) => {
                t.translate::<A>(&p_local);
                t.rotate_axis::<A, 2, 0>(g * s, c);
            }
            Aligned::Z(g) => {
                t.translate::<A>(&p_local);
                t.rotate_axis::<A, 0, 1>(g * s, c);
            }
        }
    }

    /// The space-Jacobian column of this joint when the joints before it make T:
    /// \[Ad_T\] S = (R ω, R v + p × R ω) as two lanes (w = 0).
    #[inline(always)]
    pub(crate) fn adjoint_column<A: MulAdd>(&self, t: &Columns) -> (Lane, Lane) {
        let w = t.rotate::<A>(&self.w);
        let v = add(t.rotate::<A>(&self.v), cross(t.p(), w));
        (w, v)
    }
}

/// The immutable kinematic model of a chain, prepared for the solvers: per-joint constants,
/// M, limits, names. Build once with [`Kinematics::new`], share freely (it is `Sync`).
#[derive(Debug, Clone)]
pub struct Kinematics {
    pub(crate) joints: Vec<JointConst>,
    pub(crate) body: Vec<Twist>,
    /// The same constants for the body screws B_j (used right to left by the body Jacobian).
    pub(crate) body_joints: Vec<JointConst>,
    /// M as columns.
    pub(crate) home_columns: Columns,
    pub(crate) home: Se3,
    pub(crate) links: Vec<(String, Se3, usize)>,
    pub(crate) lower: Vec<f64>,
    pub(crate) upper: Vec<f64>,
    pub(crate) continuous: Vec<bool>,
    pub(crate) names: Vec<String>,
    pub(crate) identity_map: bool,
}

impl Kinematics {
    /// Prepares a chain for solving.
    pub fn new(chain: &Chain) -> Self {
        // Closed-form constants of every joint, for the space screws S_j or the body screws B_j.
        let table = |screw: fn(&ChainJoint) -> Twist| -> Vec<JointConst> {
            chain
                .joints
                .iter()
                .map(|j| {
                    JointConst::new(
                        screw(j),
                        j.kind == JointKind::Prismatic,
                        j.variable,
                        j.multiplier,
                        j.offset,
                    )
                })
                .collect()
        };
        Self {
            joints: table(|j| *j.s_space.twist()),
            body: chain.joints.iter().map(|j| *j.b_body.twist()).collect(),
            body_joints: table(|j| *j.b_body.twist()),
            home_columns: Columns::from_se3(&chain.home),
            home: chain.home,
            links: chain
                .links
                .iter()
                .map(|l| (l.name.clone(), l.home, l.joints_before))
                .collect(),
            lower: chain.variables.iter().map(|v| v.lower).collect(),
            upper: chain.variables.iter().map(|v| v.upper).collect(),
            continuous: chain
                .variables
                .iter()
                .map(|v| v.kind == JointKind::Continuous)
                .collect(),
            names: chain.variables.iter().map(|v| v.name.clone()).collect(),
            identity_map: !chain.has_mimic(),
        }
    }

    /// Number of independent variables (the length of q).
    pub fn dof(&self) -> usize {
        self.names.len()
    }

    /// Number of movable joints on the chain (≥ dof with mimic joints).
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Variable names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Lower limits (−∞ for continuous joints).
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper limits (+∞ for continuous joints).
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// True for continuous (unbounded revolute) variables.
    pub fn continuous(&self) -> &[bool] {
        &self.continuous
    }

    /// M: the tip pose at home.
    pub fn home(&self) -> &Se3 {
        &self.home
    }

    /// The names of the chain's links, base first.
    pub fn link_names(&self) -> impl Iterator<Item = &str> {
        self.links.iter().map(|l| l.0.as_str())
    }

    /// The midpoint of the limits (0 for unbounded variables): the default IK seed.
    pub fn midpoint(&self) -> Vec<f64> {
        self.lower
            .iter()
            .zip(&self.upper)
            .map(|(&l, &u)| {
                if l.is_finite() && u.is_finite() {
                    0.5 * (l + u)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// True when every variable is within its limits (inclusive, with `tol`).
    pub fn within_limits(&self, q: &[f64], tol: f64) -> bool {
        q.iter()
            .zip(self.lower.iter().zip(&self.upper))
            .all(|(&x, (&l, &u))| x >= l - tol && x <= u + tol)
    }

    /// Checks a joint vector: right length, all finite.
    pub fn check_q(&self, q: &[f64]) -> Result<(), SolveError> {
        if q.len() != self.dof() {
            return Err(SolveError::WrongLength {
                what: "joint values",
                expected: self.dof(),
                got: q.len(),
                names: self.names.join(", "),
            });
        }
        if let Some((i, &x)) = q.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(SolveError::NonFinite {
                what: "joint value",
                index: i,
                name: self.names[i].clone(),
                value: x,
            });
        }
        Ok(())
    }

    /// θ_j of joint j for variables q.
    #[inline(always)]
    pub(crate) fn theta(&self, j: usize, q: &[f64]) -> f64 {
        let jc = &self.joints[j];
        if self.identity_map {
            q[j]
        } else {
            jc.multiplier * q[jc.variable] + jc.offset
        }
    }
}

impl Kinematics {
    /// Walks the chain base → tip calling `f(j, joint, θ_j, sin θ_j, cos θ_j)`; the sines and
    /// cosines are computed [`screwkit_lie::trig::LANES`] joints at a time, vectorised.
    #[inline(always)]
    pub(crate) fn walk<A: MulAdd>(
        &self,
        q: &[f64],
        mut f: impl FnMut(usize, &JointConst, f64, f64, f64),
    ) {
        const L: usize = screwkit_lie::trig::LANES;
        for (b, block) in self.joints.chunks(L).enumerate() {
            let mut theta = [0.0; L];
            for (i, th) in theta.iter_mut().enumerate().take(block.len()) {
                *th = self.theta(b * L + i, q);
            }
            let (mut s, mut c) = ([0.0; L], [0.0; L]);
            screwkit_lie::trig::sin_cos_lanes_with::<A>(&theta, &mut s, &mut c);
            for (i, jc) in block.iter().enumerate() {
                f(b * L + i, jc, theta[i], s[i], c[i]);
            }
        }
    }
}

impl Kinematics {
    /// Walks the chain tip → base calling `f(j, body joint j, θ_j, sin θ_j, cos θ_j)` with the
    /// constants of the body screws B_j; sines and cosines computed as in [`Kinematics::walk`].
    #[inline(always)]
    pub(crate) fn walk_rev<A: MulAdd>(
        &self,
        q: &[f64],
        mut f: impl FnMut(usize, &JointConst, f64, f64, f64),
    ) {
        const L: usize = screwkit_lie::trig::LANES;
        let n = self.body_joints.len();
        let mut end = n;
        while end > 0 {
            let start = end.saturating_sub(L);
            let mut theta = [0.0; L];
            for (i, th) in theta.iter_mut().enumerate().take(end - start) {
                *th = self.theta(start + i, q);
            }
            let (mut s, mut c) = ([0.0; L], [0.0; L]);
            screwkit_lie::trig::sin_cos_lanes_with::<A>(&theta, &mut s, &mut c);
            for i in (0..end - start).rev() {
                f(
                    start + i,
                    &self.body_joints[start + i],
                    theta[i],
                    s[i],
                    c[i],
                );
            }
            end = start;
        }
    }
}

/// Reusable scratch for one thread: the hot paths write here and allocate nothing.
#[derive(Debug, Clone)]
pub struct Workspace {
    pub(crate) jacobian: Matrix6xX<f64>,
    pub(crate) links: Vec<Se3>,
    /// IK scratch: current q, step, best q, active-set flags (dof each).
    pub(crate) ik: IkScratch,
}

/// The per-solve buffers of the IK loop, kept in the workspace so a solve allocates only the
/// q it returns.
#[derive(Debug, Clone, Default)]
pub(crate) struct IkScratch {
    pub(crate) q: Vec<f64>,
    pub(crate) dq: Vec<f64>,
    pub(crate) best_q: Vec<f64>,
    pub(crate) locked: Vec<bool>,
}

impl Workspace {
    /// Scratch sized for `kin`.
    pub fn new(kin: &Kinematics) -> Self {
        Self {
            jacobian: Matrix6xX::zeros(kin.dof()),
            links: vec![Se3::identity(); kin.links.len()],
            ik: IkScratch {
                q: vec![0.0; kin.dof()],
                dq: vec![0.0; kin.dof()],
                best_q: vec![0.0; kin.dof()],
                locked: vec![false; kin.dof()],
            },
        }
    }

    /// The last Jacobian computed (6 × dof, rows ω then v).
    pub fn jacobian(&self) -> &Matrix6xX<f64> {
        &self.jacobian
    }

    /// The last all-link poses computed, base first.
    pub fn link_poses(&self) -> &[Se3] {
        &self.links
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use screwkit_lie::ScrewAxis;

    /// Every arm of `apply` (aligned axes with either sign, pitch 0 and ≠ 0, a general axis,
    /// prismatic) equals T · e^{[S]θ} with the exponential of screwkit-lie.
    #[test]
    fn apply_equals_compose_with_the_exponential() {
        let t = Se3::exp(&Twist::new(
            Vector3::new(0.3, -0.8, 0.5),
            Vector3::new(0.2, 0.1, -0.4),
        ));
        let point = Vector3::new(0.3, -0.2, 0.7);
        let mut cases = vec![];
        for axis in [
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
            Vector3::new(1.0, 1.0, 0.0).normalize(),
        ] {
            for pitch in [0.0, 0.35] {
                let s = ScrewAxis::from_point_direction_pitch(point, axis, pitch).unwrap();
                let jc = JointConst::new(*s.twist(), false, 0, 1.0, 0.0);
                assert_eq!(
                    jc.aligned == Aligned::General,
                    axis.x.abs() > 0.5 && axis.y.abs() > 0.5
                );
                cases.push((*s.twist(), jc));
            }
        }
        let slide = ScrewAxis::prismatic(Vector3::new(0.2, -0.4, 0.8).normalize()).unwrap();
        cases.push((
            *slide.twist(),
            JointConst::new(*slide.twist(), true, 0, 1.0, 0.0),
        ));
        for (twist, jc) in &cases {
            for theta in [-2.5f64, -0.3, 0.0, 1e-9, 0.7, 3.0] {
                let (sn, cs) = theta.sin_cos();
                let mut cols = Columns::identity();
                cols.0 = std::array::from_fn(|k| {
                    let h = t.to_homogeneous();
                    [h[(0, k)], h[(1, k)], h[(2, k)], h[(3, k)]]
                });
                let mut fused = cols;
                jc.apply::<screwkit_lie::fma::Plain>(&mut cols, theta, sn, cs);
                // Fused outside an fma function is a library call: slow, but the same values.
                jc.apply::<screwkit_lie::fma::Fused>(&mut fused, theta, sn, cs);
                let oracle = t.compose(&Se3::exp(&(*twist * theta)));
                for got in [cols.to_se3(), fused.to_se3()] {
                    assert!(got.max_abs_diff(&oracle) < 1e-14, "{twist:?} {theta}");
                }
            }
        }
    }
}
