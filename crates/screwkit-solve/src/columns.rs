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

/// `a − b`, lane by lane.
#[inline(always)]
pub(crate) fn sub(a: Lane, b: Lane) -> Lane {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
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

/// Configurations per [`Block`]: the lanes of the vectorised sine and cosine
/// ([`screwkit_lie::trig::LANES`]).
pub(crate) const W: usize = screwkit_lie::trig::LANES;

/// One value per configuration of a [`Block`].
pub(crate) type Lanes = [f64; W];

/// A value aligned to 64 bytes, as the rows of a [`Block`] are: the block kernels' scratch
/// arrays, so that they are stored and loaded as whole aligned vectors.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Align64<T>(pub(crate) T);

/// Lanes g..g + 4 of `x`.
#[inline(always)]
pub(crate) fn quad(x: &Lanes, g: usize) -> [f64; 4] {
    [x[g], x[g + 1], x[g + 2], x[g + 3]]
}

/// The 4 × 4 transpose: row m of the result is (a[m], b[m], c[m], d[m]). Written as whole
/// arrays so that it compiles to shuffles (never gathers).
#[inline(always)]
pub(crate) fn transpose4(a: &[f64; 4], b: &[f64; 4], c: &[f64; 4], d: &[f64; 4]) -> [[f64; 4]; 4] {
    [
        [a[0], b[0], c[0], d[0]],
        [a[1], b[1], c[1], d[1]],
        [a[2], b[2], c[2], d[2]],
        [a[3], b[3], c[3], d[3]],
    ]
}

/// W poses at once, structure of arrays: `c[k][i][l]` is row i of column k (k = 3: p) of
/// configuration l. Every operation is the [`Columns`] operation of the same name applied lane
/// by lane with the same multiply-adds in the same order, so configuration l's result is
/// bit for bit the single-pose one; the loops over lanes vectorise across configurations.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Block {
    pub(crate) c: [[Lanes; 3]; 4],
}

// Index loops on purpose in the block code: iterator adaptors and `array::from_fn` may stay
// out of line, and then their `mul_add` is compiled without FMA (a library call) outside the
// dispatched AVX2 + FMA clone (measured: 4× slower).
#[allow(clippy::needless_range_loop)]
impl Block {
    /// W identities.
    #[inline(always)]
    pub(crate) fn identity() -> Self {
        let mut c = [[[0.0; W]; 3]; 4];
        for (k, col) in c.iter_mut().enumerate().take(3) {
            col[k] = [1.0; W];
        }
        Self { c }
    }

    /// [`Columns::translate`] per lane: p ← R t + p.
    #[inline(always)]
    pub(crate) fn translate<A: MulAdd>(&mut self, t: &[Lanes; 3]) {
        for i in 0..3 {
            let (a, b, c, p) = (self.c[0][i], self.c[1][i], self.c[2][i], self.c[3][i]);
            let mut out = [0.0; W];
            for l in 0..W {
                out[l] = A::madd(
                    a[l],
                    t[0][l],
                    A::madd(b[l], t[1][l], A::madd(c[l], t[2][l], p[l])),
                );
            }
            self.c[3][i] = out;
        }
    }

    /// [`Columns::translate_pair`] per lane: p ← R_I t_I + R_J t_J + p.
    #[inline(always)]
    pub(crate) fn translate_pair<A: MulAdd, const I: usize, const J: usize>(
        &mut self,
        t: &[Lanes; 3],
    ) {
        // Whole rows into locals, then back (as `compose`): indexing the block in place let
        // the AVX-512 build read rows at shifted offsets (stalled store forwarding).
        for i in 0..3 {
            let (a, b, p) = (self.c[I][i], self.c[J][i], self.c[3][i]);
            let mut out = [0.0; W];
            for l in 0..W {
                out[l] = A::madd(a[l], t[I][l], A::madd(b[l], t[J][l], p[l]));
            }
            self.c[3][i] = out;
        }
    }

    /// [`Columns::rotate_pair`] per lane: x_I R e_I + x_J R e_J.
    #[inline(always)]
    pub(crate) fn rotate_pair<A: MulAdd, const I: usize, const J: usize>(
        &self,
        x: &[f64; 3],
    ) -> [Lanes; 3] {
        let mut out = [[0.0; W]; 3];
        for i in 0..3 {
            for l in 0..W {
                out[i][l] = A::madd(self.c[I][i][l], x[I], self.c[J][i][l] * x[J]);
            }
        }
        out
    }

    /// [`Columns::column_scaled`] per lane: g R e_k.
    #[inline(always)]
    pub(crate) fn column_scaled(&self, k: usize, g: f64) -> [Lanes; 3] {
        let mut out = [[0.0; W]; 3];
        for i in 0..3 {
            for l in 0..W {
                out[i][l] = self.c[k][i][l] * g;
            }
        }
        out
    }

    /// [`Columns::compose`] per lane with a per-lane E (`e[row][col][lane]`) and t.
    #[inline(always)]
    pub(crate) fn compose<A: MulAdd>(&mut self, e: &[[Lanes; 3]; 3], t: &[Lanes; 3]) {
        self.translate::<A>(t);
        // Row i of the new columns needs row i of the old ones only.
        for i in 0..3 {
            let (a, b, c) = (self.c[0][i], self.c[1][i], self.c[2][i]);
            for k in 0..3 {
                let mut out = [0.0; W];
                for l in 0..W {
                    out[l] = A::madd(
                        a[l],
                        e[0][k][l],
                        A::madd(b[l], e[1][k][l], c[l] * e[2][k][l]),
                    );
                }
                self.c[k][i] = out;
            }
        }
    }

    /// [`Columns::compose`] with one E and t for every lane (M at the end of the chain).
    #[inline(always)]
    pub(crate) fn compose_fixed<A: MulAdd>(&mut self, e: &Matrix3<f64>, t: &[f64; 3]) {
        // The same multiply-adds as `compose` with every lane of E and t equal, written with
        // the scalars (splat arrays built on the stack cost a store and reload each).
        for i in 0..3 {
            let (a, b, c) = (self.c[0][i], self.c[1][i], self.c[2][i]);
            for l in 0..W {
                self.c[3][i][l] = A::madd(
                    a[l],
                    t[0],
                    A::madd(b[l], t[1], A::madd(c[l], t[2], self.c[3][i][l])),
                );
            }
            for k in 0..3 {
                let mut out = [0.0; W];
                for l in 0..W {
                    out[l] = A::madd(a[l], e[(0, k)], A::madd(b[l], e[(1, k)], c[l] * e[(2, k)]));
                }
                self.c[k][i] = out;
            }
        }
    }

    /// [`Columns::rotate_axis`] per lane: col_I ← c col_I + s col_J, col_J ← c col_J − s col_I.
    #[inline(always)]
    pub(crate) fn rotate_axis<A: MulAdd, const I: usize, const J: usize>(
        &mut self,
        s: &Lanes,
        c: &Lanes,
    ) {
        for i in 0..3 {
            let (u, w) = (self.c[I][i], self.c[J][i]);
            let (mut ou, mut ow) = ([0.0; W], [0.0; W]);
            for l in 0..W {
                ou[l] = A::madd(w[l], s[l], u[l] * c[l]);
                ow[l] = A::madd(u[l], -s[l], w[l] * c[l]);
            }
            self.c[I][i] = ou;
            self.c[J][i] = ow;
        }
    }

    /// [`Columns::rotate_near_axis`] per lane, the same multiply-adds in the same order.
    #[inline(always)]
    pub(crate) fn rotate_near_axis<A: MulAdd, const I: usize, const J: usize, const K: usize>(
        &mut self,
        s: &Lanes,
        c: &Lanes,
        u: &[f64; 2],
    ) {
        let [ui, uj] = *u;
        let (mut ki, mut kj, mut ii, mut ij) = ([0.0; W], [0.0; W], [0.0; W], [0.0; W]);
        for l in 0..W {
            let b = 1.0 - c[l];
            ki[l] = A::madd(b, ui, -(s[l] * uj));
            kj[l] = A::madd(b, uj, s[l] * ui);
            ii[l] = A::madd(b, ui, s[l] * uj);
            ij[l] = A::madd(b, uj, -(s[l] * ui));
        }
        for i in 0..3 {
            let (ri, rj, rk) = (self.c[I][i], self.c[J][i], self.c[K][i]);
            let (mut oi, mut oj, mut ok) = ([0.0; W], [0.0; W], [0.0; W]);
            for l in 0..W {
                oi[l] = A::madd(rk[l], ki[l], A::madd(rj[l], s[l], ri[l] * c[l]));
                oj[l] = A::madd(rk[l], kj[l], A::madd(ri[l], -s[l], rj[l] * c[l]));
                ok[l] = A::madd(ri[l], ii[l], A::madd(rj[l], ij[l], rk[l]));
            }
            (self.c[I][i], self.c[J][i], self.c[K][i]) = (oi, oj, ok);
        }
    }

    /// [`Columns::rotate`] per lane: R x = x₁ R e₁ + x₂ R e₂ + x₃ R e₃.
    #[inline(always)]
    pub(crate) fn rotate<A: MulAdd>(&self, x: &[f64; 3]) -> [Lanes; 3] {
        let mut out = [[0.0; W]; 3];
        for i in 0..3 {
            for l in 0..W {
                out[i][l] = A::madd(
                    self.c[0][i][l],
                    x[0],
                    A::madd(self.c[1][i][l], x[1], self.c[2][i][l] * x[2]),
                );
            }
        }
        out
    }

    /// Every configuration as a row-major 4 × 4 ([`Se3::write_row_major`]'s layout), lane l
    /// at `out[16 l..16 l + 16]`. Row i of lane l is (R_i0, R_i1, R_i2, p_i)[l]: four columns'
    /// entries, so four lanes at a time go through a 4 × 4 transpose and are stored as whole
    /// rows (a loop over lanes storing entry by entry became AVX-512 scatters in native builds,
    /// slow on this class of CPU, and 12 extract-and-store pairs per pose elsewhere).
    #[inline(always)]
    pub(crate) fn write_all_row_major(&self, out: &mut [f64]) {
        for g in (0..W).step_by(4) {
            for i in 0..3 {
                let rows = transpose4(
                    &quad(&self.c[0][i], g),
                    &quad(&self.c[1][i], g),
                    &quad(&self.c[2][i], g),
                    &quad(&self.c[3][i], g),
                );
                for m in 0..4 {
                    let at = 16 * (g + m) + 4 * i;
                    out[at..at + 4].copy_from_slice(&rows[m]);
                }
            }
            for m in 0..4 {
                let at = 16 * (g + m) + 12;
                out[at..at + 4].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
            }
        }
    }
}
