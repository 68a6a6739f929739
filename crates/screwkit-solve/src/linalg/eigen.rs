//! Eigenvalues of a small dense real matrix, without its eigenvectors and without allocating
//! ([`eigenvalues`]): balancing (Parlett & Reinsch, powers of 2), reduction to upper
//! Hessenberg form by stabilised elementary transforms (Wilkinson's `elmhes`), then the Francis
//! double-shift QR iteration with deflation on small subdiagonal entries (EISPACK's `hqr`;
//! Golub & Van Loan, *Matrix Computations*, §7.5; Wilkinson's exceptional shifts after 10 and 20
//! stalled iterations). Every loop is bounded: a matrix whose iteration does not converge, or
//! whose sums overflow, gives None, never a hang.
//!
//! It serves the general 6R's 24 × 24 companion matrix, where it is several times faster than
//! a Schur decomposition that also accumulates the Schur vectors.

// Index loops on purpose: the matrix algorithms read as in their references.
#![allow(clippy::needless_range_loop)]

/// Iterations per eigenvalue (or pair) at most before giving up.
const ITERATIONS: usize = 60;

/// The eigenvalues of the N × N matrix `a` (row-major, destroyed) as (real, imaginary) parts,
/// complex ones in conjugate pairs (positive imaginary part first), in no particular order.
/// None for a non-finite matrix or when the QR iteration does not converge.
pub fn eigenvalues<const N: usize>(a: &mut [[f64; N]; N]) -> Option<[(f64, f64); N]> {
    if N == 0 || !a.iter().flatten().all(|x| x.is_finite()) {
        return None;
    }
    balance(a);
    hessenberg(a);
    if !a.iter().flatten().all(|x| x.is_finite()) {
        return None;
    }
    let out = hqr(a)?;
    out.iter()
        .all(|(re, im)| re.is_finite() && im.is_finite())
        .then_some(out)
}

/// Scales rows and columns by powers of 2 (exact) so that each row and column have similar
/// norms: the same eigenvalues, computed more accurately.
fn balance<const N: usize>(a: &mut [[f64; N]; N]) {
    for _ in 0..64 {
        let mut done = true;
        for i in 0..N {
            let (mut c, mut r) = (0.0, 0.0);
            for j in 0..N {
                if j != i {
                    c += a[j][i].abs();
                    r += a[i][j].abs();
                }
            }
            // (Sums that overflow, or scales out of range, leave the row as it is.)
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let s = c + r;
            let mut f = 1.0f64;
            let mut g = r / 2.0;
            let mut steps = 0;
            while c < g && steps < 64 {
                f *= 2.0;
                c *= 4.0;
                steps += 1;
            }
            g = r * 2.0;
            while c > g && steps < 128 {
                f /= 2.0;
                c /= 4.0;
                steps += 1;
            }
            if !(f.is_finite() && f > 0.0) {
                continue;
            }
            if (c + r) / f < 0.95 * s {
                done = false;
                let g = 1.0 / f;
                for x in a[i].iter_mut() {
                    *x *= g;
                }
                for row in a.iter_mut() {
                    row[i] *= f;
                }
            }
        }
        if done {
            break;
        }
    }
}

/// Reduces `a` to upper Hessenberg form by stabilised elementary similarity transforms
/// (Gaussian elimination with row and column interchanges, Wilkinson's `elmhes`: half the
/// work of Householder reflections, stable in practice with the pivoting); entries below the
/// subdiagonal set to 0.
fn hessenberg<const N: usize>(a: &mut [[f64; N]; N]) {
    for m in 1..N.saturating_sub(1) {
        // The pivot: the largest entry of column m − 1 below the diagonal.
        let mut i = m;
        let mut x = 0.0f64;
        for j in m..N {
            if a[j][m - 1].abs() > x.abs() {
                x = a[j][m - 1];
                i = j;
            }
        }
        if i != m {
            a.swap(i, m);
            for row in a.iter_mut() {
                row.swap(i, m);
            }
        }
        if x == 0.0 {
            continue;
        }
        for i in m + 1..N {
            let y = a[i][m - 1] / x;
            if y == 0.0 {
                continue;
            }
            a[i][m - 1] = 0.0;
            // Row i −= y row m; column m += y column i.
            let (head, tail) = a.split_at_mut(i);
            for (xi, xm) in tail[0][m..].iter_mut().zip(&head[m][m..]) {
                *xi -= y * xm;
            }
            for row in a.iter_mut() {
                row[m] += y * row[i];
            }
        }
    }
}

/// The eigenvalues of an upper Hessenberg matrix by the Francis double-shift QR iteration
/// (the matrix is destroyed).
fn hqr<const N: usize>(a: &mut [[f64; N]; N]) -> Option<[(f64, f64); N]> {
    let mut out = [(0.0, 0.0); N];
    let mut norm = 0.0;
    for (i, row) in a.iter().enumerate() {
        for x in &row[i.saturating_sub(1)..] {
            norm += x.abs();
        }
    }
    if norm == 0.0 {
        return Some(out);
    }
    // `nn`: the last row of the active block (as an index + 1, so that 0 means done).
    let mut nn = N;
    let mut shift = 0.0;
    while nn > 0 {
        let last = nn - 1;
        let mut its = 0;
        loop {
            // The start l of the active block: the last small subdiagonal entry.
            let mut l = last;
            while l >= 1 {
                let mut s = a[l - 1][l - 1].abs() + a[l][l].abs();
                if s == 0.0 {
                    s = norm;
                }
                if a[l][l - 1].abs() <= f64::EPSILON * s {
                    a[l][l - 1] = 0.0;
                    break;
                }
                l -= 1;
            }
            let mut x = a[last][last];
            if l == last {
                // One real eigenvalue.
                out[last] = (x + shift, 0.0);
                nn -= 1;
                break;
            }
            let mut y = a[last - 1][last - 1];
            let mut w = a[last][last - 1] * a[last - 1][last];
            if l + 1 == last {
                // A 2 × 2 block: two real eigenvalues or a complex pair.
                let p = 0.5 * (y - x);
                let q = p * p + w;
                let z = q.abs().sqrt();
                x += shift;
                if q >= 0.0 {
                    let z = p + z.copysign(p);
                    let second = if z != 0.0 { x - w / z } else { x + z };
                    out[last - 1] = (x + z, 0.0);
                    out[last] = (second, 0.0);
                } else {
                    out[last - 1] = (x + p, z);
                    out[last] = (x + p, -z);
                }
                nn -= 2;
                break;
            }
            if its == ITERATIONS {
                return None;
            }
            if its == 10 || its == 20 {
                // An exceptional shift.
                shift += x;
                for (i, row) in a.iter_mut().enumerate().take(last + 1) {
                    row[i] -= x;
                }
                let s = a[last][last - 1].abs() + a[last - 1][last - 2].abs();
                x = 0.75 * s;
                y = x;
                w = -0.4375 * s * s;
            }
            its += 1;
            // The double shift's first column, and where two small consecutive subdiagonal
            // entries let the sweep start (m).
            let mut m = last - 2;
            let (mut p, mut q, mut r);
            loop {
                let z = a[m][m];
                let rr = x - z;
                let ss = y - z;
                p = (rr * ss - w) / a[m + 1][m] + a[m][m + 1];
                q = a[m + 1][m + 1] - z - rr - ss;
                r = a[m + 2][m + 1];
                let s = p.abs() + q.abs() + r.abs();
                p /= s;
                q /= s;
                r /= s;
                if m == l {
                    break;
                }
                let u = a[m][m - 1].abs() * (q.abs() + r.abs());
                let v = p.abs() * (a[m - 1][m - 1].abs() + z.abs() + a[m + 1][m + 1].abs());
                if u <= f64::EPSILON * v {
                    break;
                }
                m -= 1;
            }
            for i in m + 2..=last {
                a[i][i - 2] = 0.0;
                if i != m + 2 {
                    a[i][i - 3] = 0.0;
                }
            }
            // The double-shift QR sweep over rows and columns m..=last by 3 × 3 reflectors.
            let mut k = m;
            while k < last {
                let mut scale = 1.0;
                if k != m {
                    p = a[k][k - 1];
                    q = a[k + 1][k - 1];
                    r = if k + 1 != last { a[k + 2][k - 1] } else { 0.0 };
                    scale = p.abs() + q.abs() + r.abs();
                    if scale != 0.0 {
                        p /= scale;
                        q /= scale;
                        r /= scale;
                    }
                }
                let s = (p * p + q * q + r * r).sqrt().copysign(p);
                if s != 0.0 && scale != 0.0 {
                    if k == m {
                        if l != m {
                            a[k][k - 1] = -a[k][k - 1];
                        }
                    } else {
                        a[k][k - 1] = -s * scale;
                    }
                    p += s;
                    let (xx, yy, zz) = (p / s, q / s, r / s);
                    q /= p;
                    r /= p;
                    if k + 1 != last {
                        let (head, tail) = a.split_at_mut(k + 1);
                        let (r1, rest) = tail.split_at_mut(1);
                        let (r0, r1, r2) = (&mut head[k], &mut r1[0], &mut rest[0]);
                        for ((x0, x1), x2) in r0[k..=last]
                            .iter_mut()
                            .zip(&mut r1[k..=last])
                            .zip(&mut r2[k..=last])
                        {
                            let pp = *x0 + q * *x1 + r * *x2;
                            *x2 -= pp * zz;
                            *x1 -= pp * yy;
                            *x0 -= pp * xx;
                        }
                        let top = last.min(k + 3);
                        for row in &mut a[l..=top] {
                            let c = &mut row[k..k + 3];
                            let pp = xx * c[0] + yy * c[1] + zz * c[2];
                            c[2] -= pp * r;
                            c[1] -= pp * q;
                            c[0] -= pp;
                        }
                    } else {
                        let (head, tail) = a.split_at_mut(k + 1);
                        let (r0, r1) = (&mut head[k], &mut tail[0]);
                        for (x0, x1) in r0[k..=last].iter_mut().zip(&mut r1[k..=last]) {
                            let pp = *x0 + q * *x1;
                            *x1 -= pp * yy;
                            *x0 -= pp * xx;
                        }
                        for row in &mut a[l..=last] {
                            let c = &mut row[k..k + 2];
                            let pp = xx * c[0] + yy * c[1];
                            c[1] -= pp * q;
                            c[0] -= pp;
                        }
                    }
                }
                k += 1;
            }
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eigenvalues of random 24 × 24 matrices and of companion matrices of the general 6R's
    /// shape ([[0, I], [−C, −B]]) equal faer's (an independent eigensolver), as multisets.
    #[test]
    fn equal_to_faer() {
        let mut rng = crate::sample::SplitMix64(0x0FAE_0000_0000_0002);
        for trial in 0..60 {
            let mut a = [[0.0; 24]; 24];
            for row in a.iter_mut() {
                for v in row.iter_mut() {
                    *v = rng.uniform() - 0.5;
                }
            }
            if trial % 2 == 1 {
                for i in 0..12 {
                    for j in 0..12 {
                        a[i][j] = 0.0;
                        a[i][12 + j] = f64::from(u8::from(i == j));
                    }
                }
            }
            let m = faer::Mat::<f64>::from_fn(24, 24, |i, j| a[i][j]);
            let scale = m.norm_l2().max(1.0);
            let theirs = m.eigenvalues().unwrap();
            let ours = eigenvalues(&mut a).expect("converges");
            // Each of faer's eigenvalues is one of ours, and each of ours one of faer's.
            let near = |x: (f64, f64), set: &mut dyn Iterator<Item = (f64, f64)>| {
                set.map(|y| ((x.0 - y.0).powi(2) + (x.1 - y.1).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min)
            };
            for t in &theirs {
                let d = near((t.re, t.im), &mut ours.iter().copied());
                assert!(
                    d < 1e-9 * scale,
                    "trial {trial}: faer's {t:?} missing ({d:e})"
                );
            }
            for o in &ours {
                let d = near(*o, &mut theirs.iter().map(|t| (t.re, t.im)));
                assert!(d < 1e-9 * scale, "trial {trial}: {o:?} not faer's ({d:e})");
            }
        }
    }

    /// The eigenvalues of random matrices (and of matrices with repeated, complex and zero
    /// eigenvalues) equal nalgebra's Schur decomposition's, as multisets.
    #[test]
    fn equal_to_a_schur_decomposition() {
        let mut x = 0.123_f64;
        let mut next = || {
            x = (x * 997.0 + 0.137).fract();
            x - 0.5
        };
        for trial in 0..200 {
            let mut a = [[0.0; 12]; 12];
            for row in a.iter_mut() {
                for v in row.iter_mut() {
                    *v = next() * if trial % 3 == 0 { 1e3 } else { 1.0 };
                }
            }
            if trial % 5 == 1 {
                // Structured: a companion-like block matrix with zeros and an identity.
                for i in 0..6 {
                    for j in 0..6 {
                        a[i][j] = 0.0;
                        a[i][6 + j] = f64::from(u8::from(i == j));
                    }
                }
            }
            let m = nalgebra::SMatrix::<f64, 12, 12>::from_fn(|i, j| a[i][j]);
            let want = m.complex_eigenvalues();
            let got = eigenvalues(&mut a).expect("converges");
            let scale = m.norm().max(1.0);
            for w in want.iter() {
                let best = got
                    .iter()
                    .map(|g| ((g.0 - w.re).powi(2) + (g.1 - w.im).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min);
                assert!(best < 1e-9 * scale, "trial {trial}: {w} missing ({best:e})");
            }
        }
        // Known spectra: a rotation block, a Jordan-like block, all zeros.
        let mut r = [[0.0, -2.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 3.0]];
        let mut e = eigenvalues(&mut r).unwrap();
        e.sort_by(|a, b| a.1.total_cmp(&b.1));
        assert!(
            (e[0].0).abs() < 1e-15 && (e[0].1 + 2.0).abs() < 1e-15,
            "{e:?}"
        );
        assert!((e[1].0 - 3.0).abs() < 1e-15 && e[1].1 == 0.0, "{e:?}");
        let mut z = [[0.0; 4]; 4];
        assert_eq!(eigenvalues(&mut z), Some([(0.0, 0.0); 4]));
        let mut bad = [[1.0, f64::NAN], [0.0, 1.0]];
        assert_eq!(eigenvalues(&mut bad), None);
        // Finite entries whose sums overflow: no hang, no NaN passed on.
        let mut huge = [[0.0, 1.0, 0.0], [1e308, 0.0, 0.0], [1e308, 0.0, 0.0]];
        if let Some(e) = eigenvalues(&mut huge) {
            assert!(e.iter().all(|(re, im)| re.is_finite() && im.is_finite()));
        }
        let mut wide = [[1e-300, 1e300], [1e300, 1e-300]];
        if let Some(e) = eigenvalues(&mut wide) {
            assert!(e.iter().all(|(re, im)| re.is_finite() && im.is_finite()));
        }
    }
}
