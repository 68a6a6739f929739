//! A pose held as the four columns of its homogeneous matrix T = [[R, p], [0, 1]]: each column
//! is a 4-lane array (x, y, z, w), w = 0 for the columns of R and 1 for p. Every operation below
//! is a few lane-wise multiply-adds of whole columns, which the compiler turns into one 4-wide
//! vector instruction each under AVX2 (two 2-wide ones on baseline SSE2): R stays in four
//! registers along the chain instead of nine scalars.
//!
//! The multiply-add policy `A` ([`screwkit_lie::fma`]) is a type parameter so the same code is
//! compiled portable and, behind run-time detection, with fused multiply-adds.

use nalgebra::{Matrix3, Vector3};
use screwkit_lie::fma::MulAdd;
use screwkit_lie::Se3;

/// One column: (x, y, z, w).
pub(crate) type Lane = [f64; 4];

/// `a·x + acc`, lane by lane.
#[inline(always)]
fn madd<A: MulAdd>(a: Lane, x: f64, acc: Lane) -> Lane {
    [
        A::madd(a[0], x, acc[0]),
        A::madd(a[1], x, acc[1]),
        A::madd(a[2], x, acc[2]),
        A::madd(a[3], x, acc[3]),
    ]
}

/// `a·x`, lane by lane.
#[inline(always)]
fn scale(a: Lane, x: f64) -> Lane {
    [a[0] * x, a[1] * x, a[2] * x, a[3] * x]
}

/// a × b on the first three lanes (w = 0).
#[inline(always)]
pub(crate) fn cross(a: Lane, b: Lane) -> Lane {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
        0.0,
    ]
}

/// `a + b`, lane by lane.
#[inline(always)]
pub(crate) fn add(a: Lane, b: Lane) -> Lane {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

/// T as columns (R e₁, R e₂, R e₃, p).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Columns(pub(crate) [Lane; 4]);

impl Columns {
    /// The identity.
    #[inline(always)]
    pub(crate) fn identity() -> Self {
        Self([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ])
    }

    /// From an [`Se3`] (R, p).
    pub(crate) fn from_se3(t: &Se3) -> Self {
        let (r, p) = (t.rotation(), t.translation());
        Self(std::array::from_fn(|k| {
            if k < 3 {
                [r[(0, k)], r[(1, k)], r[(2, k)], 0.0]
            } else {
                [p.x, p.y, p.z, 1.0]
            }
        }))
    }

    /// T⁻¹ = [[Rᵀ, −Rᵀp], [0, 1]]: the columns of Rᵀ are the rows of R.
    #[inline(always)]
    pub(crate) fn inverse<A: MulAdd>(&self) -> Self {
        let [a, b, c, p] = self.0;
        let mut out = Self([
            [a[0], b[0], c[0], 0.0],
            [a[1], b[1], c[1], 0.0],
            [a[2], b[2], c[2], 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]);
        let rtp = out.rotate::<A>(&[p[0], p[1], p[2]]);
        out.0[3] = [-rtp[0], -rtp[1], -rtp[2], 1.0];
        out
    }

    /// T · U, both as columns: column k of R_T R_U is R_T (column k of R_U); p = R_T p_U + p_T.
    #[inline(always)]
    pub(crate) fn then<A: MulAdd>(&self, u: &Columns) -> Self {
        let col = |k: usize| {
            let x = u.0[k];
            self.rotate::<A>(&[x[0], x[1], x[2]])
        };
        let p = add(col(3), self.0[3]);
        Self([col(0), col(1), col(2), [p[0], p[1], p[2], 1.0]])
    }

    /// Back to an [`Se3`] (R, p).
    #[inline(always)]
    pub(crate) fn to_se3(self) -> Se3 {
        let [a, b, c, p] = self.0;
        Se3::from_parts_unchecked(
            Matrix3::new(a[0], b[0], c[0], a[1], b[1], c[1], a[2], b[2], c[2]),
            Vector3::new(p[0], p[1], p[2]),
        )
    }

    /// (R, p) as nalgebra values.
    #[inline(always)]
    pub(crate) fn rotation_translation(&self) -> (Matrix3<f64>, Vector3<f64>) {
        let [a, b, c, p] = self.0;
        (
            Matrix3::new(a[0], b[0], c[0], a[1], b[1], c[1], a[2], b[2], c[2]),
            Vector3::new(p[0], p[1], p[2]),
        )
    }

    /// The translation column p (w = 1).
    #[inline(always)]
    pub(crate) fn p(&self) -> Lane {
        self.0[3]
    }

    /// R x = x₁ R e₁ + x₂ R e₂ + x₃ R e₃ (w = 0).
    #[inline(always)]
    pub(crate) fn rotate<A: MulAdd>(&self, x: &[f64; 3]) -> Lane {
        let [a, b, c, _] = self.0;
        madd::<A>(a, x[0], madd::<A>(b, x[1], scale(c, x[2])))
    }

    /// T · [[I, t], [0, 1]]: p ← R t + p.
    #[inline(always)]
    pub(crate) fn translate<A: MulAdd>(&mut self, t: &[f64; 3]) {
        let [a, b, c, p] = self.0;
        self.0[3] = madd::<A>(a, t[0], madd::<A>(b, t[1], madd::<A>(c, t[2], p)));
    }

    /// [`Columns::translate`] for t in the plane of e_I and e_J (t_K = 0): p ← R_I t_I + R_J t_J + p.
    #[inline(always)]
    pub(crate) fn translate_pair<A: MulAdd, const I: usize, const J: usize>(
        &mut self,
        t: &[f64; 3],
    ) {
        let [ri, rj, p] = [self.0[I], self.0[J], self.0[3]];
        self.0[3] = madd::<A>(ri, t[I], madd::<A>(rj, t[J], p));
    }

    /// R x for x in the plane of e_I and e_J (x_K = 0): x_I R e_I + x_J R e_J.
    #[inline(always)]
    pub(crate) fn rotate_pair<A: MulAdd, const I: usize, const J: usize>(
        &self,
        x: &[f64; 3],
    ) -> Lane {
        madd::<A>(self.0[I], x[I], scale(self.0[J], x[J]))
    }

    /// Column k of R scaled by g.
    #[inline(always)]
    pub(crate) fn column_scaled(&self, k: usize, g: f64) -> Lane {
        scale(self.0[k], g)
    }

    /// T · [[E, t], [0, 1]] for any 3x3 E: column k of R E is Σᵢ E_ik R eᵢ; p ← R t + p.
    #[inline(always)]
    pub(crate) fn compose<A: MulAdd>(&self, e: &Matrix3<f64>, t: &[f64; 3]) -> Self {
        let [a, b, c, _] = self.0;
        let col = |k: usize| madd::<A>(a, e[(0, k)], madd::<A>(b, e[(1, k)], scale(c, e[(2, k)])));
        let mut out = *self;
        out.translate::<A>(t);
        out.0[..3].copy_from_slice(&[col(0), col(1), col(2)]);
        out
    }

    /// T · [[R_axis(φ), 0], [0, 1]] for the coordinate axis whose rotation mixes columns I and J
    /// (x: 1, 2; y: 2, 0; z: 0, 1), given (sin φ, cos φ):
    /// col_I ← c col_I + s col_J, col_J ← c col_J − s col_I.
    #[inline(always)]
    pub(crate) fn rotate_axis<A: MulAdd, const I: usize, const J: usize>(
        &mut self,
        s: f64,
        c: f64,
    ) {
        let (u, w) = (self.0[I], self.0[J]);
        self.0[I] = madd::<A>(w, s, scale(u, c));
        self.0[J] = madd::<A>(u, -s, scale(w, c));
    }

    /// T · [[e^{[ω]φ}, 0], [0, 1]] for ω = g e_K + δ near a coordinate axis (δ ⊥ e_K, |δ| ≤
    /// [`crate::poe::NEAR_AXIS`]), given s = g sin φ, c = cos φ and u = g (δ_I, δ_J), where
    /// e_I × e_J = e_K. Rodrigues, e^{[ω]φ} = c I + sin φ [ω] + b ωωᵀ with b = 1 − c, splits into
    /// the axis rotation of [`Columns::rotate_axis`] plus sin φ [δ] + b g (e_K δᵀ + δ e_Kᵀ) + b δδᵀ;
    /// dropping the last term (≤ 2|δ|² ≤ 2e-18) leaves, with R_m the old columns,
    /// col_I ← c R_I + s R_J + (b u_I − s u_J) R_K,
    /// col_J ← c R_J − s R_I + (b u_J + s u_I) R_K,
    /// col_K ← R_K + (b u_I + s u_J) R_I + (b u_J − s u_I) R_J.
    #[inline(always)]
    pub(crate) fn rotate_near_axis<A: MulAdd, const I: usize, const J: usize, const K: usize>(
        &mut self,
        s: f64,
        c: f64,
        u: &[f64; 2],
    ) {
        let (ri, rj, rk) = (self.0[I], self.0[J], self.0[K]);
        let b = 1.0 - c;
        let [ui, uj] = *u;
        self.0[I] = madd::<A>(
            rk,
            A::madd(b, ui, -(s * uj)),
            madd::<A>(rj, s, scale(ri, c)),
        );
        self.0[J] = madd::<A>(rk, A::madd(b, uj, s * ui), madd::<A>(ri, -s, scale(rj, c)));
        self.0[K] = madd::<A>(
            ri,
            A::madd(b, ui, s * uj),
            madd::<A>(rj, A::madd(b, uj, -(s * ui)), rk),
        );
    }
}
