//! The 1D search of the families without a closed form: one angle sampled over (−π, π]
//! ([`SEARCH_SAMPLES`]), the closed-form rest solved at each sample, the roots of the residual
//! bracketed and refined, then polished by Newton steps on the chain ([`search_1d`]). The guard
//! refuses arrangements where the search would miss solutions ([`search_guard`]).

use super::*;

/// The roots of a 1D search: `at(θ)` gives up to 4 branches (a state whose first 3 entries
/// identify the branch, and an error e); the roots are the θ where a branch's e = 0. θ is
/// sampled at [`SEARCH_SAMPLES`] points over a turn; consecutive branches are matched by
/// nearness of their states; a sign change along a branch — or before a branch ends or after
/// it begins inside an interval (two roots of a quartic merging: a fold, located by bisection
/// on existence) — is bisected to machine precision. A root where e only touches zero (a
/// double root) is missed, as by any sampled search; a sign change across a branch jump is
/// rejected (|e| must vanish). Returns the states at the roots.
#[inline]
pub(super) fn search_1d(at: impl Fn(f64) -> Few<([f64; 4], f64), 4>) -> Vec<[f64; 4]> {
    use std::f64::consts::{PI, TAU};
    let theta = |i: usize| -PI + TAU * i as f64 / SEARCH_SAMPLES as f64;
    let samples: Vec<Few<([f64; 4], f64), 4>> = (0..SEARCH_SAMPLES).map(|i| at(theta(i))).collect();
    let dist = |a: &[f64; 4], b: &[f64; 4]| (0..3).map(|i| wrap(a[i] - b[i]).abs()).sum::<f64>();
    // The branch at θ nearest to a reference state.
    let nearest = |t: f64, reference: &[f64; 4]| -> Option<([f64; 4], f64)> {
        at(t)
            .iter()
            .copied()
            .min_by(|a, b| dist(&a.0, reference).total_cmp(&dist(&b.0, reference)))
            .filter(|c| dist(&c.0, reference) < 0.5)
    };
    // The branch's sign change between `a` (triple ta, error ea) and `b`, bisected along it.
    let bisect = |mut a: f64, mut b: f64, ea: f64, ta: [f64; 4]| -> Option<[f64; 4]> {
        let (mut ea, mut ta) = (ea, ta);
        for _ in 0..60 {
            let mid = 0.5 * (a + b);
            let (tm, em) = nearest(mid, &ta)?;
            if em.signum() == ea.signum() && em != 0.0 {
                (a, ea, ta) = (mid, em, tm);
            } else {
                b = mid;
            }
            if (b - a).abs() < 1e-15 {
                break;
            }
        }
        nearest(0.5 * (a + b), &ta)
            .filter(|c| c.1.abs() <= 1e-9)
            .map(|c| c.0)
    };
    // Where the branch through `t` at `from` ends on the way to `to` (roots of the quartic
    // merging: a fold): the last point it exists, its triple and error.
    let fold = |from: f64, to: f64, t: [f64; 4], e: f64| -> (f64, [f64; 4], f64) {
        let (mut a, mut b, mut last) = (from, to, (t, e));
        for _ in 0..50 {
            let mid = 0.5 * (a + b);
            match nearest(mid, &last.0) {
                Some(c) => {
                    a = mid;
                    last = c;
                }
                None => b = mid,
            }
        }
        (a, last.0, last.1)
    };
    let matched = |t: &[f64; 4], set: &Few<([f64; 4], f64), 4>| {
        set.iter()
            .copied()
            .min_by(|x, y| dist(&x.0, t).total_cmp(&dist(&y.0, t)))
            .filter(|c| dist(&c.0, t) < 0.5)
    };
    let mut roots: Vec<[f64; 4]> = Vec::new();
    for i in 0..SEARCH_SAMPLES {
        let j = (i + 1) % SEARCH_SAMPLES;
        let (a0, b0) = (theta(i), theta(i) + TAU / SEARCH_SAMPLES as f64);
        for &(ta, ea) in samples[i].iter() {
            match matched(&ta, &samples[j]) {
                Some((_, eb)) => {
                    if ea.signum() != eb.signum() || ea == 0.0 {
                        roots.extend(bisect(a0, b0, ea, ta));
                    }
                }
                None => {
                    // The branch ends inside the interval: a sign change before its end.
                    let (end, te, ee) = fold(a0, b0, ta, ea);
                    if ea.signum() != ee.signum() {
                        roots.extend(bisect(a0, end, ea, ta));
                    } else if ee.abs() <= 1e-9 {
                        roots.push(te);
                    }
                }
            }
        }
        // Branches born inside the interval.
        for &(tb, eb) in samples[j].iter() {
            if matched(&tb, &samples[i]).is_some() {
                continue;
            }
            let (start, ts, es) = fold(b0, a0, tb, eb);
            if es.signum() != eb.signum() {
                roots.extend(bisect(start, b0, es, ts));
            } else if es.abs() <= 1e-9 {
                roots.push(ts);
            }
        }
    }
    roots
}

/// For the 1D search: the first three axes (in the order solved) must not nearly meet in one
/// point. When they do — a spherical shoulder written with rounded angles, as the xArm7's
/// 1.5708 for π/2 misses by 1e-6 m — the 3R position problem inside the search has solutions
/// only in θ₄ windows narrower than any sampling, so the search would silently find nothing:
/// an error naming the miss instead.
#[inline]
pub(super) fn search_guard(
    lines: &[AxisLine],
    reversed: bool,
    length: f64,
) -> Result<(), SolveError> {
    let mut l = lines.to_vec();
    if reversed {
        l.reverse();
    }
    let pair = |i: usize| {
        if l[i].direction.cross(&l[i + 1].direction).norm() < 1e-6 {
            None
        } else {
            Some(closest_points(&l[i], &l[i + 1]))
        }
    };
    if let (Some((p, d1)), Some((q, d2))) = (pair(0), pair(1)) {
        let miss = d1.max(d2).max((p - q).norm());
        if miss <= 1e-4 * length {
            return Err(SolveError::InvalidInput(format!(
                "axes {} nearly meet in one point (within {miss:.1e}, the file's rounding?): \
                 too close to a spherical shoulder for the 1D search; numerical IK only",
                if reversed { "4-6" } else { "1-3" }
            )));
        }
    }
    Ok(())
}
