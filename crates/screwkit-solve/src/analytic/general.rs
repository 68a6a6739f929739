//! The general 6R — any six revolute axes, no special geometry: every solution (at most 16) by
//! algebraic elimination in the manner of Raghavan & Roth (1993) and Manocha & Canny (1994),
//! with the coefficients computed numerically from the chain instead of symbolically.
//!
//! Each joint i turns about z of a frame F_i on its line (z = k_i, origin r_i), so
//! e^\[S_i\]θ_i = F_i R_z(θ_i) F_i⁻¹, and g = e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆ closes into a loop
//!
//! ```text
//! R_z(θ₁) D₁ R_z(θ₂) D₂ ⋯ R_z(θ₆) D₆ = I,   D_i = F_i⁻¹ F_{i+1} (i < 6),   D₆ = F₆⁻¹ g⁻¹ F₁.
//! ```
//!
//! Read from joint s + 1 (*roles* 1…6 are joints s+1, …, s+6 mod 6, K_j the link after role
//! j; s is chosen so that roles 1 and 2 are neither parallel nor meeting, [`choose_shift`]):
//!
//! ```text
//! R₃ K₃ R₄ K₄ R₅ K₅ R₆ = K₂⁻¹ R₂⁻¹ K₁⁻¹ R₁⁻¹ K₆⁻¹.
//! ```
//!
//! Both sides applied to the origin and the z axis of role 6's frame (which R₆ leaves alone)
//! give a point p and a direction l. The 14 quantities p, l, p·p, p·l, p × l,
//! (p·p) l − 2 (p·l) p are, on the left, of degree ≤ 1 in (cos, sin) of each of θ₃, θ₄, θ₅
//! and, on the right, of degree ≤ 1 in each of θ₁, θ₂: 14 equations P(θ₃) x₄₅ = Q x₁₂, x₁₂
//! the 8 products of (1, c₁, s₁) ⊗ (1, c₂, s₂) other than 1. Their coefficients are read off
//! samples of each side at 0, 2π/3 and 4π/3 per angle (exact for degree 1; θ₃ enters the left
//! side as its outermost rotation, so its coefficients follow from those of θ₄, θ₅).
//!
//! The 6 combinations of the equations orthogonal to Q's columns (Householder) eliminate θ₁
//! and θ₂: 6 equations in θ₃, θ₄, θ₅. With the half-angle tangents x₄, x₅, each (times
//! (1 + x₄²)(1 + x₅²)) is a sum over the 9 monomials x₄ⁱ x₅ʲ (i, j ≤ 2); with the same 6
//! times x₄ they are 12 equations Σ(θ₃) m = 0 in the 12 monomials x₄ⁱ x₅ʲ (i ≤ 3, j ≤ 2),
//! Σ linear in (1, cos θ₃, sin θ₃). With x = tan((θ₃ − δ)/2), (1 + x²) Σ = A x² + B x + C,
//! and det(A x² + B x + C) = 0 (degree 24: the ≤ 16 solutions and (1 + x²)⁴) is the
//! eigenproblem of the 24 × 24 companion [[0, I], [−A⁻¹C, −A⁻¹B]]; δ is chosen where A is
//! well conditioned. Each real eigenvalue gives θ₃; the null vector of Σ gives θ₄ and θ₅ (as
//! ratios of its monomials); the least-squares x₁₂ gives θ₁ and θ₂; the loop gives θ₆. Newton
//! steps on the chain polish each to machine precision; a posture is exact when its polished
//! residual is below [`EXACT`] (× max(1, L)). Where no real root gives an exact posture (the
//! pose out of reach), the complex roots' real parts seed damped Newton steps: least-squares
//! configurations, as the closed forms give theirs.

// Index loops on purpose: the matrix algorithms read as in their references.
#![allow(clippy::needless_range_loop)]

use nalgebra::SMatrix;

use crate::linalg::newton;

use super::*;

/// Newton steps at most per posture.
const NEWTON_STEPS: usize = 12;
/// An eigenvalue is taken as real when its imaginary part, as an angle (2 |Im x| / (1 + |x|²)),
/// is below this: a near-double root (rounding splits it into a complex pair) is polished, and
/// kept when Newton's steps reach the pose.
const IMAGINARY: f64 = 1e-4;
/// Pairs of consecutive lines whose sine and distance (/ L) are both above this are general.
const GENERAL_PAIR: f64 = 1e-3;
/// Q (14 × 8) counts as of full rank when its R's smallest diagonal entry is above this × the
/// largest.
const RANK: f64 = 1e-9;
/// Σ(θ₃) whose LU pivot ratio stays below this at every offset tried is singular for every θ₃.
const SINGULAR_SIGMA: f64 = 1e-10;
/// Exact candidates closer than this (each joint, mod 2π) are one posture: the better kept.
const SAME_POSTURE: f64 = 1e-6;

type M12 = SMatrix<f64, 12, 12>;

/// A rigid transform x ↦ r x + t.
#[derive(Debug, Clone, Copy)]
struct Rigid {
    r: M3,
    t: V3,
}

impl Rigid {
    #[inline]
    fn inverse(&self) -> Self {
        let r = self.r.transpose();
        Self {
            r,
            t: -(r * self.t),
        }
    }

    #[inline]
    fn compose(&self, o: &Self) -> Self {
        Self {
            r: self.r * o.r,
            t: self.r * o.t + self.t,
        }
    }

    /// A frame with z = k (unit) and origin at `origin`.
    #[inline]
    fn on_line(k: &V3, origin: V3) -> Self {
        let a = if k.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let x = (a - k * k.dot(&a)).normalize();
        let y = k.cross(&x);
        Self {
            r: M3::from_columns(&[x, y, *k]),
            t: origin,
        }
    }

    /// This transform followed on the left by R_z(θ) (cos c, sin s): R_z ∘ self.
    #[inline]
    fn after_rz(&self, c: f64, s: f64) -> Self {
        let mut out = *self;
        for j in 0..3 {
            let (x, y) = (self.r[(0, j)], self.r[(1, j)]);
            out.r[(0, j)] = c * x - s * y;
            out.r[(1, j)] = s * x + c * y;
        }
        out.t = rz(c, s, &self.t);
        out
    }
}

/// R_z(θ) v for cos θ = c, sin θ = s.
#[inline]
fn rz(c: f64, s: f64, v: &V3) -> V3 {
    V3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// (cos, sin) of 0, 2π/3, 4π/3: the samples of each angle.
const SAMPLES: [(f64, f64); 3] = [
    (1.0, 0.0),
    (-0.5, 0.866_025_403_784_438_6),
    (-0.5, -0.866_025_403_784_438_6),
];

/// The coefficients of 1, cos θ, sin θ of a function a + b cos θ + c sin θ from its values at
/// the [`SAMPLES`].
#[inline]
fn coefficients(f: [f64; 3]) -> [f64; 3] {
    [
        (f[0] + f[1] + f[2]) / 3.0,
        (2.0 * f[0] - f[1] - f[2]) / 3.0,
        (f[1] - f[2]) / 3f64.sqrt(),
    ]
}

/// Per quantity, the coefficients (index 3 a + b) of φ_a(α) φ_b(β), φ = (1, cos, sin), of a
/// function of degree ≤ 1 in each of two angles from its values at the [`SAMPLES`] of each
/// (`values[a][b]`).
fn coefficients_2d(values: &[[[f64; 14]; 3]; 3]) -> [[f64; 9]; 14] {
    let mut out = [[0.0; 9]; 14];
    for (e, row) in out.iter_mut().enumerate() {
        let mut half = [[0.0; 3]; 3];
        for a in 0..3 {
            half[a] = coefficients([values[a][0][e], values[a][1][e], values[a][2][e]]);
        }
        for b in 0..3 {
            let c = coefficients([half[0][b], half[1][b], half[2][b]]);
            for a in 0..3 {
                row[a * 3 + b] = c[a];
            }
        }
    }
    out
}

/// The 14 quantities of a point p and a direction l: p, l, p·p, p·l, p × l,
/// (p·p) l − 2 (p·l) p.
#[inline]
fn quantities(p: &V3, l: &V3) -> [f64; 14] {
    let (pp, pl) = (p.dot(p), p.dot(l));
    let c = p.cross(l);
    let w = l * pp - p * (2.0 * pl);
    [
        p.x, p.y, p.z, l.x, l.y, l.z, pp, pl, c.x, c.y, c.z, w.x, w.y, w.z,
    ]
}

/// How far consecutive lines i and i + 1 (mod 6: 5 and 0 are the pair through the target)
/// are from special: min(sine of their angle, distance / L); 0 for line 5 and 0.
fn pair_score(k: &[V3; 6], r: &[V3; 6], scale: f64, i: usize) -> f64 {
    if i == 5 {
        return 0.0;
    }
    let sine = k[i].cross(&k[i + 1]).norm();
    if sine < 1e-12 {
        return 0.0;
    }
    let line = |j: usize| AxisLine {
        direction: k[j],
        point: r[j],
    };
    sine.min(closest_points(&line(i), &line(i + 1)).1 / scale)
}

/// Random configurations per reading tried by [`choose_shift`].
const SHIFT_TRIALS: usize = 4;

/// The reading s (roles 1…6 = joints s+1, …, s+6 mod 6) for six lines in chain order and
/// their home: the elimination needs roles 1 and 2 neither parallel nor meeting (Q then has
/// rank 8) and the equations it leaves well conditioned — roles 4–6 meeting in one point
/// (a spherical shoulder or wrist, or one rounded in the file) make them degenerate, and a
/// near-spherical triple outside roles 2–4 makes pairs of solutions share θ₃ (a double
/// root). Each reading whose roles 1 and 2 are a general pair (and the one through the
/// target, s = 5) is tried on [`SHIFT_TRIALS`] poses of random configurations: the one that
/// finds the configurations most often wins, ties to the best-conditioned Σ(θ₃) at the
/// poses, then to the most general pair.
pub(super) fn choose_shift(lines: &[AxisLine; 6], home: Se3, reversed: bool) -> usize {
    let mut rng = crate::sample::SplitMix64(0x6e6e_7261_6c36);
    let configurations: Vec<[f64; 6]> = (0..SHIFT_TRIALS)
        .map(|_| std::array::from_fn(|_| (rng.uniform() * 2.0 - 1.0) * std::f64::consts::PI))
        .collect();
    let mut best = (0usize, f64::NEG_INFINITY, f64::NEG_INFINITY, 0usize);
    for s in 0..6 {
        let p = Prepared::new(Method::General, lines, home, reversed, s);
        let pair = pair_score(&p.k, &p.r, p.scale, s);
        if s != 5 && pair < GENERAL_PAIR {
            continue;
        }
        let mut found = 0;
        let mut conditioning = f64::INFINITY;
        for q in &configurations {
            let mut g = *q;
            let (pose, _) = poe(&p, &mut g);
            let mut singular = false;
            let mut hit = false;
            general(&p, &pose, &mut singular, &mut |t, exact| {
                hit |= exact && (0..6).all(|i| wrap(t[i] - q[i]).abs() < 1e-8);
            });
            found += usize::from(hit);
            conditioning = conditioning.min(sigma_conditioning(&p, &pose));
        }
        let key = (found, conditioning, pair, s);
        if (key.0, key.1, key.2) > (best.0, best.1, best.2) {
            best = key;
        }
    }
    best.3
}

/// How well conditioned the problem's Σ(θ₃) is away from its roots: the LU pivot ratio at
/// θ₃ = 1 (0 where the elimination fails).
fn sigma_conditioning(p: &Prepared, g: &Se3) -> f64 {
    match eliminate(links(p, g, p.shift)) {
        Some((_, h)) => {
            let m = sigma(&h);
            let (s, c) = 1f64.sin_cos();
            pivot_ratio(&(m[0] + m[1] * c + m[2] * s).lu())
        }
        None => 0.0,
    }
}

/// The length of a problem: the largest distance of a line's point or the home's origin from
/// the base (1 for a chain that has none).
pub(super) fn scale_of(r: &[V3; 6], home: &Se3) -> f64 {
    let s = r
        .iter()
        .map(|x| x.norm())
        .fold(home.translation().norm(), f64::max);
    if s > 1e-9 && s.is_finite() {
        s
    } else {
        1.0
    }
}

/// The loop's links in roles (lengths / L) for the target g, read from joint `shift` + 1
/// (module documentation).
fn links(p: &Prepared, g: &Se3, shift: usize) -> [Rigid; 6] {
    let scale = p.scale;
    let frames: [Rigid; 6] = std::array::from_fn(|i| Rigid::on_line(&p.k[i], p.r[i] / scale));
    let gs = Rigid {
        r: *g.rotation(),
        t: g.translation() / scale,
    };
    let d: [Rigid; 6] = std::array::from_fn(|i| {
        if i < 5 {
            frames[i].inverse().compose(&frames[i + 1])
        } else {
            frames[5]
                .inverse()
                .compose(&gs.inverse())
                .compose(&frames[0])
        }
    });
    std::array::from_fn(|j| d[(shift + j) % 6])
}

/// The eliminated problem of one target: the links in roles (lengths / L), the θ₁ θ₂ side's
/// QR, the left side's coefficients.
struct Eliminated {
    k: [Rigid; 6],
    /// Q's Householder vectors (row k: entries k..14) and factors.
    v: [[f64; 14]; 8],
    beta: [f64; 8],
    /// R of Q = QR (upper 8 × 8).
    r: [[f64; 8]; 8],
    /// The right side's constant term per quantity (moved to the left).
    constant: [f64; 14],
}

impl Eliminated {
    /// Qᵀ y in place.
    #[inline]
    fn apply_qt(&self, y: &mut [f64; 14]) {
        for k in 0..8 {
            let d: f64 = (k..14).map(|i| self.v[k][i] * y[i]).sum();
            let f = self.beta[k] * d;
            for i in k..14 {
                y[i] -= f * self.v[k][i];
            }
        }
    }

    /// The left side without R₃, K₃ R₄ K₄ R₅ K₅ (cos, sin of θ₄ and θ₅), applied to the
    /// origin and z: (p, l).
    #[inline]
    fn inner(&self, c4: f64, s4: f64, c5: f64, s5: f64) -> (V3, V3) {
        let mut p = self.k[4].t;
        let mut l = self.k[4].r.column(2).into_owned();
        p = self.k[3].r * rz(c5, s5, &p) + self.k[3].t;
        l = self.k[3].r * rz(c5, s5, &l);
        p = self.k[2].r * rz(c4, s4, &p) + self.k[2].t;
        l = self.k[2].r * rz(c4, s4, &l);
        (p, l)
    }

    /// The left side's 14 quantities at (θ₃, θ₄, θ₅), minus the right side's constant.
    #[inline]
    fn left(&self, t: [f64; 3]) -> [f64; 14] {
        let (s3, c3) = t[0].sin_cos();
        let (s4, c4) = t[1].sin_cos();
        let (s5, c5) = t[2].sin_cos();
        let (p, l) = self.inner(c4, s4, c5, s5);
        let mut q = quantities(&rz(c3, s3, &p), &rz(c3, s3, &l));
        for (x, c) in q.iter_mut().zip(&self.constant) {
            *x -= c;
        }
        q
    }

    /// θ₁, θ₂ from the left side's value `f` at (θ₃, θ₄, θ₅): the least-squares x₁₂ of
    /// Q x₁₂ = f, read as the rank-one (1, c₁, s₁) ⊗ (1, c₂, s₂).
    #[inline]
    fn first_two(&self, mut f: [f64; 14]) -> (f64, f64) {
        self.apply_qt(&mut f);
        let mut x = [0.0; 8];
        let big = (0..8).map(|i| self.r[i][i].abs()).fold(0.0, f64::max);
        for i in (0..8).rev() {
            let s: f64 = f[i] - (i + 1..8).map(|j| self.r[i][j] * x[j]).sum::<f64>();
            x[i] = if self.r[i][i].abs() > 1e-12 * big {
                s / self.r[i][i]
            } else {
                0.0
            };
        }
        // z[a][b] = φ_a(θ₁) φ_b(θ₂), φ = (1, cos, sin).
        let z = [[1.0, x[0], x[1]], [x[2], x[3], x[4]], [x[5], x[6], x[7]]];
        let t1 = f64::atan2(
            (0..3).map(|b| z[2][b] * z[0][b]).sum(),
            (0..3).map(|b| z[1][b] * z[0][b]).sum(),
        );
        let t2 = f64::atan2(
            (0..3).map(|a| z[a][2] * z[a][0]).sum(),
            (0..3).map(|a| z[a][1] * z[a][0]).sum(),
        );
        (t1, t2)
    }
}

/// Every posture of the general 6R problem g (module documentation): the exact ones first
/// (at most 16 real solutions; [`Postures`] keeps 16); `singular` set where a root was (nearly) double or the Jacobian at a posture
/// (nearly) singular.
pub(super) fn general(
    p: &Prepared,
    g: &Se3,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let scale = p.scale;
    // The solver's reading first; where it fails for this target (roles 1 and 2 parallel or
    // meeting here, no well-conditioned offset, a QR iteration that does not converge), the
    // others in turn.
    let mut solved = None;
    for s in (0..6).map(|i| (p.shift + i) % 6) {
        let Some((e, h)) = eliminate(links(p, g, s)) else {
            continue;
        };
        let m = sigma(&h);
        if let Some(r) = roots(&m) {
            solved = Some((s, e, m, r));
            break;
        }
    }
    let Some((s, e, m, roots)) = solved else {
        return;
    };
    // Candidates in joint order, polished; the exact ones emitted first. The real roots give
    // the solutions; where none is exact (the pose out of reach), the real parts of the
    // complex ones seed damped Newton steps: least-squares configurations.
    let mut found: [([f64; 6], bool, f64); 48] = [([0.0; 6], false, 0.0); 48];
    let mut count = 0;
    for pass in [true, false] {
        if !pass && found[..count].iter().any(|f| f.1) {
            break;
        }
        for &(x3, delta, near_double, real) in roots.iter() {
            if real != pass {
                continue;
            }
            for t in back_substitute(&e, &m, x3, delta).iter() {
                let mut q = [0.0; 6];
                for (j, &v) in t.iter().enumerate() {
                    q[(s + j) % 6] = wrap(v);
                }
                let (residual, conditioned) = newton(p, g, &mut q);
                let exact = residual <= EXACT * scale.max(1.0);
                if exact && (near_double || !conditioned) {
                    *singular = true;
                }
                // One entry per posture: candidates of one solution (the two eigenvalues of a
                // near-double root, two null vectors) merge, the smaller residual kept.
                let same = |f: &([f64; 6], bool, f64)| {
                    (0..6).all(|i| wrap(f.0[i] - q[i]).abs() < SAME_POSTURE)
                };
                let capacity = found.len();
                match found[..count].iter_mut().find(|f| same(f)) {
                    Some(f) if (exact, -residual) > (f.1, -f.2) => *f = (q, exact, residual),
                    Some(_) => {}
                    None if count < capacity => {
                        found[count] = (q, exact, residual);
                        count += 1;
                    }
                    None => {}
                }
            }
        }
    }
    for want in [true, false] {
        for f in found[..count].iter().filter(|f| f.1 == want) {
            emit(f.0, f.1);
        }
    }
}

/// The 14 equations of the roles' links `k`, θ₁ and θ₂ eliminated (module documentation):
/// the right side's QR and the left side's coefficients. None for non-finite data.
fn eliminate(k: [Rigid; 6]) -> Option<(Eliminated, [[f64; 27]; 6])> {
    // The right side K₂⁻¹ R₂⁻¹ K₁⁻¹ R₁⁻¹ K₆⁻¹ at the 3 × 3 samples of (θ₁, θ₂).
    let (k1i, k2i, k6i) = (k[0].inverse(), k[1].inverse(), k[5].inverse());
    let mut right = [[[0.0; 14]; 3]; 3];
    for (a, &(c1, s1)) in SAMPLES.iter().enumerate() {
        let inner = k1i.compose(&k6i.after_rz(c1, -s1));
        for (b, &(c2, s2)) in SAMPLES.iter().enumerate() {
            let m = k2i.compose(&inner.after_rz(c2, -s2));
            right[a][b] = quantities(&m.t, &m.r.column(2).into_owned());
        }
    }
    // g[e][a][b]: coefficients of φ_a(θ₁) φ_b(θ₂).
    let gc = coefficients_2d(&right);
    if !gc.iter().flatten().all(|x| x.is_finite()) {
        return None;
    }
    // Householder QR of Q (14 × 8: the columns of every product but 1).
    let mut q = [[0.0; 8]; 14];
    for i in 0..14 {
        q[i].copy_from_slice(&gc[i][1..9]);
    }
    let mut v = [[0.0; 14]; 8];
    let mut beta = [0.0; 8];
    for c in 0..8 {
        let norm = (c..14).map(|i| q[i][c] * q[i][c]).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        let alpha = if q[c][c] > 0.0 { -norm } else { norm };
        for i in c..14 {
            v[c][i] = q[i][c];
        }
        v[c][c] -= alpha;
        let vv: f64 = (c..14).map(|i| v[c][i] * v[c][i]).sum();
        if vv == 0.0 {
            continue;
        }
        beta[c] = 2.0 / vv;
        for j in c..8 {
            let dot: f64 = (c..14).map(|i| v[c][i] * q[i][j]).sum();
            let f = beta[c] * dot;
            for i in c..14 {
                q[i][j] -= f * v[c][i];
            }
        }
    }
    let mut r = [[0.0; 8]; 8];
    for i in 0..8 {
        r[i][i..8].copy_from_slice(&q[i][i..8]);
    }
    // Roles 1 and 2 parallel or meeting for this target leave Q of rank < 8: θ₁ and θ₂ are
    // then not eliminated (another reading is tried).
    let diagonal = (0..8).map(|i| r[i][i].abs());
    let (lo, hi) = diagonal.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    if lo.is_nan() || lo <= RANK * hi {
        return None;
    }
    let e = Eliminated {
        k,
        v,
        beta,
        r,
        constant: std::array::from_fn(|i| gc[i][0]),
    };
    // The left side without its outer rotation R₃: K₃ R₄ K₄ R₅ K₅ at the samples of (θ₄, θ₅),
    // then its coefficients w[e][b][c] of φ_b(θ₄) φ_c(θ₅).
    let mut samples = [[[0.0; 14]; 3]; 3];
    for (b, &(c4, s4)) in SAMPLES.iter().enumerate() {
        for (c, &(c5, s5)) in SAMPLES.iter().enumerate() {
            let (p, l) = e.inner(c4, s4, c5, s5);
            samples[b][c] = quantities(&p, &l);
        }
    }
    let w = coefficients_2d(&samples);
    // θ₃ is the outer rotation: R_z(θ₃) u = (c u_x − s u_y, s u_x + c u_y, u_z) for the
    // vectors (p, l, p × l, the last), the scalars (p·p, p·l) do not depend on it.
    // f[i][a * 9 + b * 3 + c]: coefficients of φ_a(θ₃) φ_b(θ₄) φ_c(θ₅).
    let mut f = [[0.0; 27]; 14];
    for start in [0, 3, 8, 11] {
        let (x, y, z) = (start, start + 1, start + 2);
        for m in 0..9 {
            f[x][9 + m] = w[x][m];
            f[x][18 + m] = -w[y][m];
            f[y][9 + m] = w[y][m];
            f[y][18 + m] = w[x][m];
            f[z][m] = w[z][m];
        }
    }
    for i in [6, 7] {
        f[i][..9].copy_from_slice(&w[i]);
    }
    for i in 0..14 {
        f[i][0] -= e.constant[i];
    }
    // The 6 combinations orthogonal to Q's columns: rows 8..14 of Qᵀ f.
    let mut h = [[0.0; 27]; 6];
    for col in 0..27 {
        let mut y: [f64; 14] = std::array::from_fn(|i| f[i][col]);
        e.apply_qt(&mut y);
        for k in 0..6 {
            h[k][col] = y[8 + k];
        }
    }
    // Each equation scaled to its largest coefficient.
    for row in h.iter_mut() {
        let big = row.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if !(big > 0.0 && big.is_finite() && row.iter().all(|x| x.is_finite())) {
            return None;
        }
        for x in row.iter_mut() {
            *x /= big;
        }
    }
    Some((e, h))
}

/// (1 + x²) φ(θ) for x = tan(θ/2), φ = (1, cos, sin): coefficients of x⁰, x¹, x².
const HALF_ANGLE: [[f64; 3]; 3] = [[1.0, 0.0, 1.0], [1.0, 0.0, -1.0], [0.0, 2.0, 0.0]];

/// The 12 × 12 matrices Σ = M₀ + cos θ₃ M₁ + sin θ₃ M₂ of the 6 equations `h` and the same
/// times x₄ in the monomials x₄ⁱ x₅ʲ (column 3 i + j).
fn sigma(h: &[[f64; 27]; 6]) -> [M12; 3] {
    let mut m = [M12::zeros(); 3];
    for (k, row) in h.iter().enumerate() {
        for (a, ma) in m.iter_mut().enumerate() {
            for b in 0..3 {
                for c in 0..3 {
                    let coefficient = row[a * 9 + b * 3 + c];
                    if coefficient == 0.0 {
                        continue;
                    }
                    for i in 0..3 {
                        for j in 0..3 {
                            let v = coefficient * HALF_ANGLE[b][i] * HALF_ANGLE[c][j];
                            ma[(k, i * 3 + j)] += v;
                            ma[(6 + k, (i + 1) * 3 + j)] += v;
                        }
                    }
                }
            }
        }
    }
    m
}

/// The quadratic A x² + B x + C = (1 + x²) Σ(δ + 2 atan x) of `m`.
fn quadratic(m: &[M12; 3], delta: f64) -> [M12; 3] {
    let (sd, cd) = delta.sin_cos();
    let mc = m[1] * cd + m[2] * sd;
    let ms = m[2] * cd - m[1] * sd;
    [m[0] - mc, ms * 2.0, m[0] + mc]
}

/// How well conditioned a 12 × 12 matrix is, by the pivots of its LU: min |u_ii| / max |u_ii|.
fn pivot_ratio(lu: &nalgebra::LU<f64, nalgebra::U12, nalgebra::U12>) -> f64 {
    let u = lu.u();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for i in 0..12 {
        let x = u[(i, i)].abs();
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if hi > 0.0 && lo.is_finite() {
        lo / hi
    } else {
        0.0
    }
}

/// Offsets δ of θ₃ tried, in turn, for a well-conditioned leading matrix A = Σ(δ + π).
const OFFSETS: [f64; 6] = [0.7, 2.3, 4.1, 5.5, 1.6, 3.3];

/// The roots of det Σ(θ₃) = 0 as (x, δ, near-double, real) with θ₃ = δ + 2 atan x (for a
/// complex root, its real part), from the companion eigenproblem (module documentation); real:
/// within [`IMAGINARY`] of the real line. None when no offset gives an invertible A or the QR
/// iteration does not converge.
fn roots(m: &[M12; 3]) -> Option<Few<(f64, f64, bool, bool), 24>> {
    // The first offset whose A is well conditioned (else the best), its LU kept.
    let mut best: Option<(f64, f64, nalgebra::LU<f64, nalgebra::U12, nalgebra::U12>)> = None;
    for &delta in &OFFSETS {
        let lu = quadratic(m, delta)[0].lu();
        let ratio = pivot_ratio(&lu);
        let better = best.as_ref().is_none_or(|b| ratio > b.0);
        if better {
            best = Some((ratio, delta, lu));
        }
        if ratio > 1e-3 {
            break;
        }
    }
    let (ratio, delta, lu) = best?;
    // Σ(θ₃) singular at every offset: the reading is degenerate for this target (roles 1
    // and 2 parallel or meeting make the 6 equations dependent).
    if ratio < SINGULAR_SIGMA {
        return None;
    }
    let [_, b, c] = quadratic(m, delta);
    let x = lu.solve(&c)?;
    let y = lu.solve(&b)?;
    let mut companion = [[0.0; 24]; 24];
    for i in 0..12 {
        companion[i][12 + i] = 1.0;
        for j in 0..12 {
            companion[12 + i][j] = -x[(i, j)];
            companion[12 + i][12 + j] = -y[(i, j)];
        }
    }
    let values = crate::linalg::eigen::eigenvalues(&mut companion)?;
    let mut out = Few::default();
    for &(re, im) in values.iter() {
        let angle = 2.0 * im.abs() / (1.0 + re * re);
        if re.is_finite() {
            out.push((re, delta, im != 0.0, angle <= IMAGINARY));
        }
    }
    Some(out)
}

/// The roles' six angles of the root x (θ₃ = δ + 2 atan x): θ₄, θ₅ from the null vector of
/// Σ(θ₃), θ₁, θ₂ from the least-squares x₁₂, θ₆ from the loop. Where Σ(θ₃) has a
/// two-dimensional null space (two solutions share θ₃: the two shoulders of an arm whose
/// first three axes nearly meet), both: the combinations of the two null vectors whose
/// monomials are of rank one ([`double_root`]).
fn back_substitute(el: &Eliminated, m: &[M12; 3], x: f64, delta: f64) -> Few<[f64; 6], 2> {
    let t3 = delta + 2.0 * x.atan();
    let (s3, c3) = t3.sin_cos();
    let mut at = m[0] + m[1] * c3 + m[2] * s3;
    let (n, second) = null_space(&mut at);
    let mut out = Few::default();
    let vectors = match second {
        Some(n2) => double_root(&n, &n2),
        None => Few::one(n),
    };

    for v in vectors.iter() {
        if let Some(t) = angles_of(el, t3, v) {
            out.push(t);
        }
    }
    out
}

/// The six angles from θ₃ and a null vector `n` of Σ(θ₃) (n\[3 i + j\] ∝ x₄ⁱ x₅ʲ).
fn angles_of(el: &Eliminated, t3: f64, n: &[f64; 12]) -> Option<[f64; 6]> {
    // Each tangent as the ratio of the largest neighbouring pair.
    let mut best4 = (-1.0, 0.0, 0.0);
    for i in 0..3 {
        for j in 0..3 {
            let (lo, hi) = (n[3 * i + j], n[3 * (i + 1) + j]);
            let size = lo * lo + hi * hi;
            if size > best4.0 {
                best4 = (size, hi, lo);
            }
        }
    }
    let mut best5 = (-1.0, 0.0, 0.0);
    for i in 0..4 {
        for j in 0..2 {
            let (lo, hi) = (n[3 * i + j], n[3 * i + j + 1]);
            let size = lo * lo + hi * hi;
            if size > best5.0 {
                best5 = (size, hi, lo);
            }
        }
    }
    let (t4, t5) = (2.0 * best4.1.atan2(best4.2), 2.0 * best5.1.atan2(best5.2));
    let (t1, t2) = el.first_two(el.left([t3, t4, t5]));
    // R₆ = (R₁ K₁ R₂ K₂ R₃ K₃ R₄ K₄ R₅ K₅)⁻¹ K₆⁻¹: its angle about z.
    let mut chain = Rigid {
        r: M3::identity(),
        t: V3::zeros(),
    };
    for (j, t) in [t1, t2, t3, t4, t5].into_iter().enumerate() {
        let (s, c) = t.sin_cos();
        chain = chain.compose(&el.k[j].after_rz(c, s));
    }
    let r6 = chain.inverse().compose(&el.k[5].inverse()).r;
    let t6 = r6[(1, 0)].atan2(r6[(0, 0)]);
    let t = [t1, t2, t3, t4, t5, t6];
    t.iter().all(|v| v.is_finite()).then_some(t)
}

/// The vectors α n₁ + β n₂ of a two-dimensional null space whose 4 × 3 grid of monomials
/// x₄ⁱ x₅ʲ has rank one: the 2 × 2 minor of the grid with the largest coefficients, a
/// quadratic form in (α, β), set to 0.
fn double_root(n1: &[f64; 12], n2: &[f64; 12]) -> Few<[f64; 12], 2> {
    let mut best = ([0.0; 3], -1.0);
    for (i, k) in [(0, 1), (1, 2), (2, 3), (0, 2), (1, 3), (0, 3)] {
        for (j, l) in [(0, 1), (1, 2), (0, 2)] {
            // (a + t b)(d + t e) − (c + t f)(g + t h) for entries (i,j)(k,l) − (i,l)(k,j).
            let (a, b) = (n1[3 * i + j], n2[3 * i + j]);
            let (d, e) = (n1[3 * k + l], n2[3 * k + l]);
            let (c, f) = (n1[3 * i + l], n2[3 * i + l]);
            let (g, h) = (n1[3 * k + j], n2[3 * k + j]);
            let q = [a * d - c * g, a * e + b * d - c * h - f * g, b * e - f * h];
            let size = q.iter().map(|x| x * x).sum::<f64>();
            if size > best.1 {
                best = (q, size);
            }
        }
    }
    let [c0, c1, c2] = best.0;
    let mut out = Few::default();
    // c₀ α² + c₁ α β + c₂ β² = 0, solved for the ratio whose leading coefficient is larger.
    let (lead, mid, last, flip) = if c2.abs() >= c0.abs() {
        (c2, c1, c0, false)
    } else {
        (c0, c1, c2, true)
    };
    if lead == 0.0 {
        return out;
    }
    let disc = (mid * mid - 4.0 * lead * last).max(0.0).sqrt();
    let r1 = (-mid - disc.copysign(mid)) / (2.0 * lead);
    let r2 = if r1 != 0.0 { last / (lead * r1) } else { 0.0 };
    for r in [r1, r2] {
        // flip: r = α / β; else r = β / α.
        let (alpha, beta) = if flip { (r, 1.0) } else { (1.0, r) };
        out.push(std::array::from_fn(|i| alpha * n1[i] + beta * n2[i]));
    }
    out
}

/// A second null vector is taken when the second-last pivot is below this (relative to the
/// first).
const DOUBLE: f64 = 1e-5;

/// A null vector of a (nearly) singular 12 × 12 matrix by Gaussian elimination with complete
/// pivoting (the last unknown set to 1), and a second one (the last two set to (0, 1), the
/// first's to (1, 0)) when the second-last pivot is also below [`DOUBLE`] of the first.
fn null_space(a: &mut M12) -> ([f64; 12], Option<[f64; 12]>) {
    let mut cols: [usize; 12] = std::array::from_fn(|i| i);
    for k in 0..11 {
        let (mut pi, mut pj, mut big) = (k, k, -1.0);
        for i in k..12 {
            for j in k..12 {
                let v = a[(i, j)].abs();
                if v > big {
                    (pi, pj, big) = (i, j, v);
                }
            }
        }
        a.swap_rows(k, pi);
        a.swap_columns(k, pj);
        cols.swap(k, pj);
        let pivot = a[(k, k)];
        if pivot == 0.0 {
            continue;
        }
        for i in k + 1..12 {
            let f = a[(i, k)] / pivot;
            if f != 0.0 {
                for j in k..12 {
                    a[(i, j)] -= f * a[(k, j)];
                }
            }
        }
    }
    let solve = |last: usize, tail: &[f64]| {
        let mut z = [0.0; 12];
        z[last..].copy_from_slice(tail);
        for i in (0..last).rev() {
            let s: f64 = (i + 1..12).map(|j| a[(i, j)] * z[j]).sum();
            z[i] = if a[(i, i)] != 0.0 {
                -s / a[(i, i)]
            } else {
                0.0
            };
        }
        let mut out = [0.0; 12];
        for i in 0..12 {
            out[cols[i]] = z[i];
        }
        out
    };
    if a[(10, 10)].abs() <= DOUBLE * a[(0, 0)].abs() {
        (solve(10, &[1.0, 0.0]), Some(solve(10, &[0.0, 1.0])))
    } else {
        (solve(11, &[1.0]), None)
    }
}

/// The pose e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆ of the problem's lines (the kernels' g) and its space
/// Jacobian (columns (ω, v) = (R k_i, p × R k_i) for the moved line through p).
fn poe(p: &Prepared, q: &mut [f64; 6]) -> (Se3, nalgebra::Matrix6<f64>) {
    let mut r = M3::identity();
    let mut t = V3::zeros();
    let mut j = nalgebra::Matrix6::zeros();
    for i in 0..6 {
        let w = r * p.k[i];
        let point = r * p.r[i] + t;
        let v = point.cross(&w);
        j.fixed_view_mut::<3, 1>(0, i).copy_from(&w);
        j.fixed_view_mut::<3, 1>(3, i).copy_from(&v);
        let ri = rotation(&p.k[i], q[i]);
        let ti = p.r[i] - ri * p.r[i];
        t += r * ti;
        r *= ri;
    }
    (Se3::from_parts_unchecked(r, t), j)
}

/// Newton steps on g = e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆ (space Jacobian, θ ← θ + J⁻¹ log(g T(θ)⁻¹))
/// while the residual falls, a damped step when the full one does not ([`newton::polish`]);
/// returns the residual (max |T(θ) − g|) of the best iterate, left in `q`, and whether its
/// Jacobian was well conditioned.
pub(super) fn newton(p: &Prepared, g: &Se3, q: &mut [f64; 6]) -> (f64, bool) {
    let linearise = |q: &[f64; 6]| {
        let (pose, jacobian) = poe(p, &mut q.clone());
        let err = g.compose(&pose.inverse()).log();
        Some(newton::Linear {
            error: nalgebra::Vector6::new(err.w.x, err.w.y, err.w.z, err.v.x, err.v.y, err.v.z),
            jacobian,
            residual: pose.max_abs_diff(g),
        })
    };
    let budget = newton::Newton {
        steps: NEWTON_STEPS,
        floor: 1e-15 * p.scale.max(1.0),
        dampings: &[1e-6, 1e-3, 1e-1],
    };
    let Some(at) = newton::polish(q, budget, wrap, linearise) else {
        return (f64::INFINITY, false);
    };
    let (residual, jac) = (at.residual, at.jacobian);
    // Conditioning by the LU pivots of the (column-scaled) Jacobian.
    let mut scaled = jac;
    for mut c in scaled.column_iter_mut() {
        let n = c.norm();
        if n > 0.0 {
            c /= n;
        }
    }
    let u = scaled.lu().u();
    let (lo, hi) = (0..6).fold((f64::INFINITY, 0.0f64), |(a, b), i| {
        (a.min(u[(i, i)].abs()), b.max(u[(i, i)].abs()))
    });
    (residual, lo > 1e-6 * hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Six lines, axes 1 ∥ 2 (roles 1 and 2 of reading 0: a degenerate reading).
    fn lines() -> [AxisLine; 6] {
        let mut x = 0.37_f64;
        let mut next = || {
            x = (x * 997.0 + 0.131).fract();
            x - 0.5
        };
        let mut out: [AxisLine; 6] = std::array::from_fn(|_| AxisLine {
            direction: V3::new(next(), next(), next()).normalize(),
            point: V3::new(next(), next(), next()) * 0.6,
        });
        out[1].direction = out[0].direction;
        out
    }

    #[test]
    fn a_reading_that_fails_for_a_target_gives_way_to_another() {
        let home = Se3::from_translation(V3::new(0.2, 0.1, 0.4));
        let bad = Prepared::new(Method::General, &lines(), home, false, 0);
        let good = choose_shift(&lines(), home, false);
        assert_ne!(good, 0, "roles 1 and 2 of reading 0 are parallel");
        let q = [0.4, -1.1, 0.7, 2.0, -0.3, 1.3];
        let (g, _) = poe(&bad, &mut q.clone());
        let mut hit = false;
        general(&bad, &g, &mut false, &mut |t, exact| {
            hit |= exact && (0..6).all(|i| wrap(t[i] - q[i]).abs() < 1e-9);
        });
        assert!(hit, "q among the postures through another reading");
        // Reading 0 alone: its Σ(θ₃) is singular at every θ₃ (the 6 equations dependent), so
        // it gives no roots.
        let (_, h) = eliminate(links(&bad, &g, 0)).unwrap();
        assert!(roots(&sigma(&h)).is_none());
    }
}
