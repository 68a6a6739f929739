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
