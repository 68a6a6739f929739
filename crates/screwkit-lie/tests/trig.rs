//! The inlined sin/cos against the standard library over millions of arguments.

use screwkit_lie::trig::{sin_cos, sin_cos_lanes, sin_cos_lanes_portable, LANES};

fn check(x: f64) -> f64 {
    let (s, c) = sin_cos(x);
    let (s0, c0) = x.sin_cos();
    (s - s0).abs().max((c - c0).abs())
}

/// The test arguments: `dense` points over [−20, 20] (the joint-angle range), every multiple of
/// π/4 in it with its close neighbours, and `wide` random-looking arguments up to the reduction
/// limit.
fn arguments(dense: usize, wide: usize, seed: u64) -> Vec<f64> {
    let mut xs: Vec<f64> = (0..=dense)
        .map(|i| -20.0 + 40.0 * i as f64 / dense as f64)
        .collect();
    for k in -64i32..=64 {
        let base = k as f64 * std::f64::consts::FRAC_PI_4;
        for d in [0.0, 1e-300, 1e-17, 1e-12, 1e-8, -1e-12, -1e-8] {
            xs.push(base + d);
        }
    }
    let mut s = seed;
    for _ in 0..wide {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let u = (s >> 11) as f64 / (1u64 << 53) as f64;
        xs.push((u - 0.5) * 1.6e6);
    }
    xs
}

#[test]
fn matches_std_within_a_few_ulp_of_one() {
    let worst = arguments(2_000_000, 1_000_000, 0x1234_5678_9ABC_DEF0)
        .into_iter()
        .map(check)
        .fold(0.0f64, f64::max);
    assert!(worst <= 2.3e-16, "worst absolute error {worst:e}");
    // Fallbacks and corners.
    assert_eq!(sin_cos(0.0), (0.0, 1.0));
    assert!(sin_cos(f64::NAN).0.is_nan());
    assert!(sin_cos(f64::INFINITY).1.is_nan());
    assert!(check(1e10) == 0.0 && check(-3e7) == 0.0);
}

/// Worst absolute error of a lanes function against the standard library over `xs`.
fn lanes_error(xs: &[f64], f: fn(&[f64; LANES], &mut [f64; LANES], &mut [f64; LANES])) -> f64 {
    let mut worst: f64 = 0.0;
    for chunk in xs.chunks(LANES) {
        let mut x = [0.25; LANES];
        x[..chunk.len()].copy_from_slice(chunk);
        let (mut s, mut c) = ([0.0; LANES], [0.0; LANES]);
        f(&x, &mut s, &mut c);
        for i in 0..LANES {
            let (s0, c0) = x[i].sin_cos();
            if s0.is_nan() {
                assert!(s[i].is_nan() && c[i].is_nan(), "{}", x[i]);
            } else {
                worst = worst.max((s[i] - s0).abs()).max((c[i] - c0).abs());
            }
        }
    }
    worst
}

/// The vectorised lanes (run-time dispatched: fused multiply-adds on AVX2+FMA machines) and the
/// portable lanes, over the same arguments as the scalar test, mixed with the fallback cases.
#[test]
fn lanes_match_std_on_every_path() {
    let xs = arguments(400_000, 400_000, 0x0FED_CBA9_8765_4321);
    for f in [sin_cos_lanes, sin_cos_lanes_portable] {
        assert!(lanes_error(&xs, f) <= 2.3e-16);
    }
    // A block with one huge or non-finite angle takes the scalar path for all of its lanes.
    let mixed = [0.3, 1e10, -2.0, f64::NAN, 5.0, f64::INFINITY, -3e7, 0.0];
    for f in [sin_cos_lanes, sin_cos_lanes_portable] {
        assert!(lanes_error(&mixed, f) <= 2.3e-16);
    }
    // The portable lanes are the scalar function, bit for bit.
    let x = [0.1, -0.7, 1.5, 2.9, -3.1, 4.0, 10.0, -100.0];
    let (mut s, mut c) = ([0.0; LANES], [0.0; LANES]);
    sin_cos_lanes_portable(&x, &mut s, &mut c);
    for i in 0..LANES {
        assert_eq!((s[i], c[i]), sin_cos(x[i]));
    }
}
