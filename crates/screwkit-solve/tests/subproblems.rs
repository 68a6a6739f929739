//! Subproblems 1–4 on thousands of random instances built from known angles (recovered), on
//! instances with no exact solution (the least-squares answer checked against a dense scan),
//! and on degenerate ones (point on the axis, parallel axes, tangency). The rotation of the
//! oracle is the library's `so3::exp`, not the subproblems' own `rotate`.

mod common;

use common::Sampler;
use nalgebra::Vector3;
use screwkit_solve::subproblem::{sp1, sp2, sp3, sp4, wrap, AnglePairs, Angles};

fn rot(k: &Vector3<f64>, t: f64, p: &Vector3<f64>) -> Vector3<f64> {
    screwkit_lie::so3::exp(&(k * t)) * p
}

fn unit(r: &mut Sampler) -> Vector3<f64> {
    loop {
        let v = Vector3::new(
            r.uniform() * 2.0 - 1.0,
            r.uniform() * 2.0 - 1.0,
            r.uniform() * 2.0 - 1.0,
        );
        if v.norm() > 0.1 && v.norm() < 1.0 {
            return v.normalize();
        }
    }
}

fn point(r: &mut Sampler) -> Vector3<f64> {
    Vector3::new(
        r.uniform() * 4.0 - 2.0,
        r.uniform() * 4.0 - 2.0,
        r.uniform() * 4.0 - 2.0,
    )
}

fn angle(r: &mut Sampler) -> f64 {
    (r.uniform() * 2.0 - 1.0) * std::f64::consts::PI
}

fn close(a: f64, b: f64) -> bool {
    wrap(a - b).abs() < 1e-9
}

fn exact(a: Angles) -> Vec<f64> {
    match a {
        Angles::Exact(v) => v.to_vec(),
        other => panic!("expected exact solutions, got {other:?}"),
    }
}

#[test]
fn sp1_recovers_angles_and_least_squares() {
    let mut r = Sampler::new(1);
    for _ in 0..5000 {
        let (k, p1, t) = (unit(&mut r), point(&mut r), angle(&mut r));
        let p2 = rot(&k, t, &p1);
        let got = exact(sp1(&p1, &p2, &k));
        assert!(close(got[0], t), "{got:?} vs {t}");
    }
    // No exact solution: the answer minimises the distance (checked by a dense scan).
    for _ in 0..200 {
        let (k, p1, p2) = (unit(&mut r), point(&mut r), point(&mut r));
        let Angles::LeastSquares(t) = sp1(&p1, &p2, &k) else {
            panic!("not least-squares")
        };
        let best = (0..20000)
            .map(|i| f64::from(i) * std::f64::consts::TAU / 20000.0)
            .map(|a| (rot(&k, a, &p1) - p2).norm())
            .fold(f64::INFINITY, f64::min);
        assert!((rot(&k, t, &p1) - p2).norm() <= best + 1e-9);
    }
    // A point on the axis: any angle.
    let k = Vector3::z();
    assert_eq!(
        sp1(
            &Vector3::new(0.0, 0.0, 2.0),
            &Vector3::new(0.0, 0.0, 2.0),
            &k
        ),
        Angles::Any
    );
}

#[test]
fn sp3_and_sp4_contain_the_angle() {
    let mut r = Sampler::new(2);
    for _ in 0..5000 {
        let (k, p1, p2, t) = (unit(&mut r), point(&mut r), point(&mut r), angle(&mut r));
        let d = (rot(&k, t, &p1) - p2).norm();
        let sols = exact(sp3(&p1, &p2, &k, d));
        assert!(sols.iter().any(|&s| close(s, t)), "sp3 {sols:?} lacks {t}");
        for &s in &sols {
            assert!(((rot(&k, s, &p1) - p2).norm() - d).abs() < 1e-9);
        }
        let h = unit(&mut r);
        let d4 = h.dot(&rot(&k, t, &p1));
        let sols = exact(sp4(&h, &p1, &k, d4));
        assert!(sols.iter().any(|&s| close(s, t)), "sp4 {sols:?} lacks {t}");
        for &s in &sols {
            assert!((h.dot(&rot(&k, s, &p1)) - d4).abs() < 1e-9);
        }
    }
    // Out of reach: least squares, the closest distance.
    let (k, p1, p2) = (
        Vector3::z(),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(3.0, 0.0, 0.0),
    );
    assert_eq!(sp3(&p1, &p2, &k, 0.5), Angles::LeastSquares(0.0));
    let Angles::LeastSquares(t) = sp3(&p1, &p2, &k, 10.0) else {
        panic!()
    };
    assert!(close(t, std::f64::consts::PI));
    // Tangent: one solution. The distance 2 from (3,0,0) to the unit circle is reached at θ = 0.
    assert_eq!(exact(sp3(&p1, &p2, &k, 2.0)).len(), 1);
    // sp4 with h along the axis: hᵀRp does not depend on θ.
    assert_eq!(sp4(&k, &p1, &k, 0.0), Angles::Any);
}

#[test]
fn sp2_recovers_angle_pairs() {
    let mut r = Sampler::new(3);
    for _ in 0..5000 {
        let (k1, k2, p1) = (unit(&mut r), unit(&mut r), point(&mut r));
        if k1.cross(&k2).norm() < 0.05 {
            continue;
        }
        let (t1, t2) = (angle(&mut r), angle(&mut r));
        // R(k1, t1) p1 = R(k2, t2) p2.
        let p2 = rot(&k2, -t2, &rot(&k1, t1, &p1));
        let AnglePairs::Exact(pairs) = sp2(&p1, &p2, &k1, &k2) else {
            panic!("not exact")
        };
        assert!(
            pairs.iter().any(|&(a, b)| close(a, t1) && close(b, t2)),
            "{pairs:?} lacks ({t1}, {t2})"
        );
        for &(a, b) in pairs.iter() {
            assert!((rot(&k1, a, &p1) - rot(&k2, b, &p2)).norm() < 1e-8);
        }
    }
    assert_eq!(
        sp2(&Vector3::x(), &Vector3::y(), &Vector3::z(), &Vector3::z()),
        AnglePairs::Degenerate
    );
    // Circles that do not meet (c would need z = 1 and x = 1, so |c|² ≥ 2 > 1.01): least squares.
    let r2 = sp2(
        &Vector3::new(0.1, 0.0, 1.0),
        &Vector3::new(1.0, 0.1, 0.0),
        &Vector3::z(),
        &Vector3::x(),
    );
    assert!(matches!(r2, AnglePairs::LeastSquares(..)), "{r2:?}");
}

#[test]
fn sp4_unit_agrees_with_sp4_and_keeps_precision_near_tangency() {
    use screwkit_solve::subproblem::sp4_unit;
    let mut r = Sampler::new(9);
    for i in 0..5000 {
        let k = unit(&mut r);
        // h, p ⊥ k, unit.
        let h = k.cross(&unit(&mut r)).normalize();
        let p = k.cross(&unit(&mut r)).normalize();
        // Near the tangency for a fifth of the cases: t within 1e-9 of the root of h = R p.
        let t0 = p.cross(&h).dot(&k).atan2(p.dot(&h));
        let t = if i % 5 == 0 {
            t0 + (r.uniform() - 0.5) * 2e-9
        } else {
            angle(&mut r)
        };
        let v = rot(&k, t, &p);
        let got = exact(sp4_unit(&h, &p, &k, &v).unwrap());
        assert!(
            got.iter().any(|&g| close(g, t)),
            "{got:?} lacks {t} (tangency at {t0})"
        );
        for &g in &got {
            assert!((h.dot(&rot(&k, g, &p)) - h.dot(&v)).abs() < 1e-12);
        }
        if i % 5 != 0 {
            let mut want = exact(sp4(&h, &p, &k, h.dot(&v)));
            let mut got = got.clone();
            want.sort_by(f64::total_cmp);
            got.sort_by(f64::total_cmp);
            assert!(
                want.iter().zip(&got).all(|(a, b)| close(*a, *b)),
                "{want:?} {got:?}"
            );
        }
    }
    // Not perpendicular to the axis: not this subproblem's case.
    assert!(sp4_unit(&Vector3::z(), &Vector3::x(), &Vector3::z(), &Vector3::z()).is_none());
}

#[test]
fn real_roots_of_quartics() {
    use screwkit_solve::subproblem::real_roots;
    let mut r = Sampler::new(21);
    for _ in 0..2000 {
        // (x − a)(x − b)(x − c)(x − d) with known roots, or two of them complex.
        let roots: Vec<f64> = (0..4).map(|_| r.uniform() * 6.0 - 3.0).collect();
        let complex = r.uniform() < 0.3;
        let mut poly = vec![1.0];
        let mut times = |lin: &[f64]| {
            let mut out = vec![0.0; poly.len() + lin.len() - 1];
            for (i, a) in poly.iter().enumerate() {
                for (j, b) in lin.iter().enumerate() {
                    out[i + j] += a * b;
                }
            }
            poly = out;
        };
        times(&[-roots[0], 1.0]);
        times(&[-roots[1], 1.0]);
        if complex {
            times(&[roots[2] * roots[2] + 1.0, -2.0 * roots[2], 1.0]);
        } else {
            times(&[-roots[2], 1.0]);
            times(&[-roots[3], 1.0]);
        }
        let got = real_roots(&poly);
        let want = if complex { &roots[..2] } else { &roots[..] };
        for w in want {
            // Close double roots split by √ε: 1e-6.
            assert!(
                got.iter().any(|g| (g - w).abs() < 1e-6),
                "{got:?} lacks {w}"
            );
        }
        assert!(got.len() <= want.len(), "{got:?} vs {want:?}");
    }
    // Degree drops: 2x − 4.
    assert_eq!(&*real_roots(&[-4.0, 2.0, 0.0, 0.0, 0.0]), &[2.0]);
    assert!(real_roots(&[1.0, 0.0, 1.0]).is_empty());
    // Non-finite coefficients give no roots, never a hang (a NaN reached the companion
    // matrix, whose unbounded QR iteration then never ended: the IRB 140 with an offset
    // wrist hung `ik --all`).
    for bad in [
        [f64::NAN, 1.0, 2.0, 3.0, 1.0],
        [1.0, 2.0, f64::NAN, 3.0, 1.0],
        [1.0, 2.0, 3.0, f64::INFINITY, 1.0],
        [1.0, 2.0, 3.0, 4.0, f64::NAN],
    ] {
        assert!(real_roots(&bad).is_empty(), "{bad:?}");
    }
    // Huge and tiny coefficients together: bounded, finite roots only.
    let got = real_roots(&[1e-300, 1e300, -1e-300, 1e300, 1.0]);
    assert!(got.iter().all(|x| x.is_finite()));
}

#[test]
fn sp5_recovers_angle_triples() {
    use screwkit_solve::subproblem::sp5;
    let mut r = Sampler::new(22);
    let mut found = 0;
    for _ in 0..3000 {
        let (k1, k2, k3) = (unit(&mut r), unit(&mut r), unit(&mut r));
        let (p1, p2, p3) = (point(&mut r), point(&mut r), point(&mut r));
        let (t1, t2, t3) = (angle(&mut r), angle(&mut r), angle(&mut r));
        // p0 + R1 p1 = R2 (p2 + R3 p3).
        let p0 = rot(&k2, t2, &(p2 + rot(&k3, t3, &p3))) - rot(&k1, t1, &p1);
        let sols = sp5(&p0, &p1, &p2, &p3, &k1, &k2, &k3);
        for &(a, b, c) in sols.iter() {
            let lhs = p0 + rot(&k1, a, &p1);
            let rhs = rot(&k2, b, &(p2 + rot(&k3, c, &p3)));
            assert!((lhs - rhs).norm() < 1e-6, "residual {}", (lhs - rhs).norm());
        }
        if sols
            .iter()
            .any(|&(a, b, c)| close(a, t1) && close(b, t2) && close(c, t3))
        {
            found += 1;
        } else {
            // Only near a double root may the known triple be missed (it is then within √ε).
            assert!(
                sols.iter().any(|&(a, b, c)| wrap(a - t1).abs() < 1e-4
                    && wrap(b - t2).abs() < 1e-4
                    && wrap(c - t3).abs() < 1e-4),
                "{sols:?} lacks ({t1}, {t2}, {t3})"
            );
        }
    }
    assert!(found >= 2990, "{found}");
    // k1 ∥ k2: circle 1 keeps its height; still solved.
    let (k, p1, p2, p3) = (
        Vector3::z(),
        Vector3::new(1.0, 0.0, 0.3),
        Vector3::new(0.2, 0.5, 0.0),
        Vector3::new(0.0, 0.4, 0.1),
    );
    let k3 = Vector3::new(1.0, 1.0, 0.0).normalize();
    let p0 = rot(&k, 0.4, &(p2 + rot(&k3, -0.7, &p3))) - rot(&k, 1.1, &p1);
    let sols = sp5(&p0, &p1, &p2, &p3, &k, &k, &k3);
    assert!(sols.iter().all(|&(a, b, c)| {
        ((p0 + rot(&k, a, &p1)) - rot(&k, b, &(p2 + rot(&k3, c, &p3)))).norm() < 1e-9
    }));
    assert!(!sols.is_empty());
    // Out of reach: no solution.
    let far = Vector3::new(100.0, 0.0, 0.0);
    assert!(sp5(&far, &p1, &p2, &p3, &Vector3::x(), &Vector3::y(), &k3).is_empty());
}

#[test]
fn sp6_recovers_angle_pairs() {
    use screwkit_solve::subproblem::sp6;
    let mut r = Sampler::new(23);
    let mut found = 0;
    for _ in 0..3000 {
        let h: Vec<Vector3<f64>> = (0..4).map(|_| unit(&mut r)).collect();
        let k: Vec<Vector3<f64>> = (0..4).map(|_| unit(&mut r)).collect();
        let p: Vec<Vector3<f64>> = (0..4).map(|_| point(&mut r)).collect();
        let (t1, t2) = (angle(&mut r), angle(&mut r));
        let f = |i: usize, t: f64| h[i].dot(&rot(&k[i], t, &p[i]));
        let (d1, d2) = (f(0, t1) + f(1, t2), f(2, t1) + f(3, t2));
        let sols = sp6(
            [&h[0], &h[1], &h[2], &h[3]],
            [&k[0], &k[1], &k[2], &k[3]],
            [&p[0], &p[1], &p[2], &p[3]],
            d1,
            d2,
        );
        for &(a, b) in sols.iter() {
            assert!((f(0, a) + f(1, b) - d1).abs() < 1e-6);
            assert!((f(2, a) + f(3, b) - d2).abs() < 1e-6);
        }
        if sols.iter().any(|&(a, b)| close(a, t1) && close(b, t2)) {
            found += 1;
        } else {
            assert!(
                sols.iter()
                    .any(|&(a, b)| wrap(a - t1).abs() < 1e-4 && wrap(b - t2).abs() < 1e-4),
                "{sols:?} lacks ({t1}, {t2})"
            );
        }
    }
    assert!(found >= 2990, "{found}");
}

#[test]
fn sp6_of_non_finite_input_has_no_solution_and_returns() {
    use nalgebra::Vector3;
    use screwkit_solve::subproblem::sp6;
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let bad = Vector3::new(f64::NAN, 0.0, 1.0);
    assert!(sp6(
        [&x, &y, &x, &y],
        [&z, &x, &z, &x],
        [&bad, &y, &x, &z],
        0.1,
        0.0
    )
    .is_empty());
    assert!(sp6(
        [&x, &y, &x, &y],
        [&z, &x, &z, &x],
        [&x, &y, &x, &z],
        f64::NAN,
        0.0
    )
    .is_empty());
}
