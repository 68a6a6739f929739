//! Singularity analysis of a Jacobian from its SVD ([`crate::linalg::svd`]).
//!
//! Caveat of the field: J mixes units (rad/s and m/s rows), so singular values and the condition
//! number depend on the length unit; the rank and the lost directions do not.

use nalgebra::{Matrix6xX, Vector3, Vector6};

use screwkit_lie::display::fixed_list;
use screwkit_lie::Frame;

use crate::error::SolveError;
use crate::kinematics::Kinematics;
use crate::workspace::Workspace;

/// Above this condition number a full-rank configuration is called near singular in
/// [`Analysis::verdict`].
pub const NEAR_SINGULAR_CONDITION: f64 = 1e3;

/// A manipulability ellipsoid {J q̇ : ‖q̇‖ ≤ 1} projected on 3 rows (angular or linear):
/// principal axes are the eigenvectors of A = J_p J_pᵀ (J_p's left singular vectors), semi-axis
/// lengths √λ_i (J_p's singular values).
#[derive(Debug, Clone, PartialEq)]
pub struct Ellipsoid {
    /// Unit principal axes, longest first.
    pub axes: [Vector3<f64>; 3],
    /// Semi-axis lengths √λ_i, longest first.
    pub lengths: [f64; 3],
}

/// What the SVD J = U Σ Vᵀ says about a configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    /// The number of columns of J (the chain's DoF).
    pub columns: usize,
    /// The min(6, n) singular values σ₁ ≥ σ₂ ≥ … ≥ 0.
    pub singular_values: Vec<f64>,
    /// Number of σ_i above [`Analysis::rank_tolerance`]; at most min(6, n).
    pub rank: usize,
    /// σ_i ≤ max(6, n) · ε · σ₁ counts as zero (the LAPACK/NumPy `matrix_rank` convention).
    pub rank_tolerance: f64,
    /// Yoshikawa's manipulability √det(J Jᵀ) = σ₁ ⋯ σ₆; 0 when n < 6 or the Jacobian is rank
    /// deficient (a σ within the rank tolerance counts as zero, as for the condition number:
    /// the product would be rounding noise).
    pub manipulability: f64,
    /// σ₁ / σ_min(6,n); ∞ when the Jacobian is rank deficient (σ_min within the rank tolerance
    /// is numerically zero: its value is rounding noise, so the ratio would be too).
    pub condition_number: f64,
    /// det J for a square (6 × 6) Jacobian.
    pub determinant: Option<f64>,
    /// The angular-velocity ellipsoid (rows ω).
    pub angular: Ellipsoid,
    /// The linear-velocity ellipsoid (rows v).
    pub linear: Ellipsoid,
    /// Twist directions the chain cannot produce: the left singular vectors u_i with
    /// σ_i ≤ tolerance, plus u_{n+1..6} when n < 6. Ordered (ω, v). Every direction here and
    /// in the ellipsoids has a canonical sign ([`canonical_sign`]).
    pub lost_directions: Vec<Vector6<f64>>,
    /// The twist direction of the smallest singular value (the motion that is hardest to make).
    pub weakest_direction: Vector6<f64>,
}

/// A singular vector or eigenvector is defined up to sign, and which sign an SVD returns depends
/// on rounding (and so on the CPU). This picks one: the first component with |x| > 1e-9 is made
/// positive.
pub fn canonical_sign<const D: usize>(x: nalgebra::SVector<f64, D>) -> nalgebra::SVector<f64, D> {
    match x.iter().find(|c| c.abs() > 1e-9) {
        Some(&c) if c < 0.0 => -x,
        _ => x,
    }
}

/// The ellipsoid of J's three rows from `first` (0: ω, 3: v): its axes are the left singular
/// vectors of J_p, its lengths the singular values (the eigenvectors and √eigenvalues of
/// J_p J_pᵀ), by the crate's one SVD on J_p stacked over three zero rows. The zero rows'
/// columns of Jᵀ take part in no rotation, so U is block diagonal and J_p's three columns are
/// the ones supported on the first three rows.
fn ellipsoid(j: &Matrix6xX<f64>, first: usize) -> Ellipsoid {
    let n = j.ncols();
    let padded = Matrix6xX::from_fn(n, |r, c| if r < 3 { j[(first + r, c)] } else { 0.0 });
    let Ok(svd) = crate::linalg::svd::jacobian_svd(&padded, None) else {
        return Ellipsoid {
            axes: [Vector3::repeat(f64::NAN); 3],
            lengths: [f64::NAN; 3],
        };
    };
    let mut axes = [Vector3::zeros(); 3];
    let mut lengths = [0.0; 3];
    let mut found = 0;
    for c in 0..6 {
        let axis = Vector3::new(svd.u[(0, c)], svd.u[(1, c)], svd.u[(2, c)]);
        if found < 3 && axis.norm() > 0.5 {
            axes[found] = canonical_sign(axis);
            lengths[found] = svd.s.get(c).copied().unwrap_or(0.0);
            found += 1;
        }
    }
    Ellipsoid { axes, lengths }
}

/// Analyses the Jacobian of `kin` at q in `frame` (the directions are in that frame). Checks q.
pub fn analyze(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    frame: Frame,
) -> Result<Analysis, SolveError> {
    analyze_jacobian(crate::jacobian::jacobian(kin, ws, q, frame)?)
}

/// The position-only analysis: how the tip point can move, from the 3 × n Jacobian of its
/// velocity (J_v of the body Jacobian; its singular values are the same in any axes). It has
/// the units the 6 × n analysis mixes kept apart (m per rad or m per m), and it is the one that
/// means something for a chain with fewer than 6 joints.
#[derive(Debug, Clone, PartialEq)]
pub struct PositionAnalysis {
    /// Singular values of J_v, largest first (min(3, n) of them).
    pub singular_values: Vec<f64>,
    /// Numerical rank (singular values above max(3, n) · ε · σ₁).
    pub rank: usize,
    /// √det(J_v J_vᵀ) = σ₁σ₂σ₃ (0 for fewer than 3 joints): the volume of the velocity ellipsoid.
    pub manipulability: f64,
    /// σ_max / σ_min over the 3 position directions (∞ when rank < 3).
    pub condition_number: f64,
}

/// Analyses the tip point's velocity Jacobian of `kin` at q. Checks q.
pub fn analyze_position(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
) -> Result<PositionAnalysis, SolveError> {
    let j = crate::jacobian::jacobian(kin, ws, q, Frame::Body)?;
    let jv = nalgebra::DMatrix::from_fn(3, j.ncols(), |r, c| j[(3 + r, c)]);
    Ok(analyze_position_jacobian(&jv))
}

/// The position-only analysis of a 3 × n tip-point velocity Jacobian (the linear rows of J_b
/// or of the world-aligned Jacobian).
pub fn analyze_position_jacobian(jv: &nalgebra::DMatrix<f64>) -> PositionAnalysis {
    let n = jv.ncols();
    // The crate's one SVD (`svd`, for 6 × n) on Jv stacked over three zero rows: the same
    // singular values, then zeros.
    let mut sv: Vec<f64> = if n == 0 {
        Vec::new()
    } else {
        let padded = nalgebra::Matrix6xX::from_fn(n, |r, c| if r < 3 { jv[(r, c)] } else { 0.0 });
        crate::linalg::svd::jacobian_svd(&padded, None)
            .map_or_else(|_| vec![f64::NAN; n.min(3)], |d| d.s)
    };
    sv.truncate(n.min(3));
    let s1 = sv.first().copied().unwrap_or(0.0);
    let tol = 3.max(n) as f64 * f64::EPSILON * s1;
    let rank = sv.iter().filter(|&&x| x > tol).count();
    PositionAnalysis {
        manipulability: if sv.len() == 3 {
            sv.iter().product()
        } else {
            0.0
        },
        condition_number: if rank == 3 { s1 / sv[2] } else { f64::INFINITY },
        singular_values: sv,
        rank,
    }
}

/// Analyses any 6 × n Jacobian (space or body; the directions are in its frame).
pub fn analyze_jacobian(j: &Matrix6xX<f64>) -> Result<Analysis, SolveError> {
    let n = j.ncols();
    if j.iter().any(|x| !x.is_finite()) {
        return Err(SolveError::InvalidInput(
            "the Jacobian has non-finite entries".into(),
        ));
    }
    let svd = crate::linalg::svd::jacobian_svd(j, None)?;
    let k = n.min(6);
    let singular_values = svd.s;
    let s1 = singular_values.first().copied().unwrap_or(0.0);
    let rank_tolerance = 6.max(n) as f64 * f64::EPSILON * s1;
    let rank = singular_values
        .iter()
        .filter(|&&x| x > rank_tolerance)
        .count();
    let u = svd.u;
    let col = |i: usize| canonical_sign(Vector6::from_fn(|r, _| u[(r, i)]));
    let lost_directions = (0..6)
        .filter(|&i| i >= k || singular_values[i] <= rank_tolerance)
        .map(col)
        .collect();
    let smin = singular_values.last().copied().unwrap_or(0.0);
    Ok(Analysis {
        columns: n,
        manipulability: if n >= 6 && rank == 6 {
            singular_values.iter().product()
        } else {
            0.0
        },
        condition_number: if rank == k && smin > 0.0 {
            s1 / smin
        } else {
            f64::INFINITY
        },
        determinant: (n == 6).then(|| j.fixed_columns::<6>(0).into_owned().determinant()),
        angular: ellipsoid(j, 0),
        linear: ellipsoid(j, 3),
        lost_directions,
        weakest_direction: col(k.saturating_sub(1)),
        singular_values,
        rank,
        rank_tolerance,
    })
}

/// Yoshikawa's manipulability √det(J Jᵀ) of a 6 × n Jacobian given row-major (the layout of
/// [`crate::batch::jacobian_batch`]), without an SVD: the Gram matrix J Jᵀ (6 × 6) and its
/// determinant by LU (for n = 6, |det J| by one LU of J). Equal to the product of the singular values that
/// [`analyze_jacobian`] reports as `manipulability` (tested to 1e-9 relative: the Gram matrix
/// squares the condition number, so the last digits differ); 0 when n < 6
/// or J Jᵀ is singular to rounding. The same for a space and a body Jacobian (they differ by
/// an adjoint, whose determinant is 1). For maps and batches where an SVD per row would cost
/// more than the IK.
pub fn manipulability(j: &[f64], n: usize) -> f64 {
    if n < 6 || j.len() != 6 * n {
        return 0.0;
    }
    if n == 6 {
        // Square: √det(J Jᵀ) = |det J|, one LU of J itself.
        return nalgebra::Matrix6::<f64>::from_row_slice(j)
            .lu()
            .determinant()
            .abs();
    }
    let mut g = nalgebra::Matrix6::<f64>::zeros();
    for r in 0..6 {
        for c in r..6 {
            let (a, b) = (&j[r * n..(r + 1) * n], &j[c * n..(c + 1) * n]);
            let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
            g[(r, c)] = dot;
            g[(c, r)] = dot;
        }
    }
    let det = g.lu().determinant();
    if det > 0.0 {
        det.sqrt()
    } else {
        0.0
    }
}

/// Plain words for a twist direction (ω, v): a rotation, a translation, or the twist itself.
fn describe(u: &Vector6<f64>) -> String {
    let w = u.fixed_rows::<3>(0).into_owned();
    let v = u.fixed_rows::<3>(3).into_owned();
    let tuple = |x: &Vector3<f64>| format!("({})", fixed_list(x.as_slice(), 6));
    if v.norm() < 0.05 {
        format!("rotation about {}", tuple(&w.normalize()))
    } else if w.norm() < 0.05 {
        format!("translation along {}", tuple(&v.normalize()))
    } else {
        format!("the twist (ω | v) = ({} | {})", tuple(&w), tuple(&v))
    }
}

impl Analysis {
    /// The verdict in plain words: no joints, singular (with the lost motions), near singular (condition
    /// number above [`NEAR_SINGULAR_CONDITION`], with the weakest motion), a chain too short to
    /// make every twist, or well-conditioned.
    pub fn verdict(&self) -> String {
        let n = self.columns;
        let k = n.min(6);
        if n == 0 {
            "no joints: the tip cannot move".into()
        } else if self.rank < k {
            let dirs: Vec<String> = self
                .lost_directions
                .iter()
                .take(k - self.rank)
                .map(describe)
                .collect();
            format!(
                "singular (rank {} of {k}): loses motion along {}",
                self.rank,
                dirs.join("; ")
            )
        } else if self.condition_number > NEAR_SINGULAR_CONDITION {
            format!(
                "near singular (condition number {:.3e}): loses motion along {}",
                self.condition_number,
                describe(&self.weakest_direction)
            )
        } else if n < 6 {
            format!(
                "full rank {n}, but a {n}-joint chain can never produce {} of the 6 twist directions",
                6 - n
            )
        } else {
            format!(
                "well-conditioned (condition number {:.3})",
                self.condition_number
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ellipsoids from the one SVD against their definition, A = J_p J_pᵀ: lengths² equal
    /// faer's eigenvalues of A (an independent symmetric eigensolver), A a = length² a for
    /// each axis, axes orthonormal and sign-canonical; on wide, square and narrow Jacobians,
    /// rank-deficient ones (a zero length whose axis is A's null direction) and the zero one.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn ellipsoids_equal_the_eigen_decomposition_of_j_jt() {
        let mut rng = crate::sample::SplitMix64(0xE111_0000_0000_0001);
        for n in 0..=8 {
            for case in 0..6 {
                let mut j = Matrix6xX::from_fn(n, |_, _| rng.uniform() - 0.5);
                if case >= 3 && n >= 2 {
                    // The linear rows of rank 1 at most: each a multiple of the first.
                    let (a, b) = (rng.uniform(), rng.uniform());
                    for c in 0..n {
                        j[(4, c)] = a * j[(3, c)];
                        j[(5, c)] = b * j[(3, c)];
                    }
                }
                for (first, e) in [(0, ellipsoid(&j, 0)), (3, ellipsoid(&j, 3))] {
                    let jp = j.fixed_rows::<3>(first).into_owned();
                    let a = jp.clone() * jp.transpose();
                    let m = faer::Mat::<f64>::from_fn(3, 3, |r, c| a[(r, c)]);
                    let mut theirs = m.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
                    theirs.sort_by(|x, y| y.total_cmp(x));
                    let scale = theirs[0].max(1e-300);
                    for i in 0..3 {
                        let l2 = e.lengths[i] * e.lengths[i];
                        assert!((l2 - theirs[i]).abs() <= 1e-13 * scale, "{n} {case} {i}");
                        let ax = e.axes[i];
                        assert!((ax.norm() - 1.0).abs() < 1e-14);
                        assert!((a * ax - ax * l2).norm() <= 1e-13 * scale.max(1.0));
                        assert_eq!(canonical_sign(ax), ax);
                        for k in i + 1..3 {
                            assert!(ax.dot(&e.axes[k]).abs() < 1e-14);
                        }
                    }
                    assert!(e.lengths[0] >= e.lengths[1] && e.lengths[1] >= e.lengths[2]);
                }
            }
        }
    }
}
