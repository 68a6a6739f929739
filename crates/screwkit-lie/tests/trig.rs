//! The inlined sin/cos against the standard library over millions of arguments.

use screwkit_lie::trig::sin_cos;

fn check(x: f64) -> f64 {
    let (s, c) = sin_cos(x);
    let (s0, c0) = x.sin_cos();
    (s - s0).abs().max((c - c0).abs())
}

#[test]
fn matches_std_within_a_few_ulp_of_one() {
    let mut worst: f64 = 0.0;
    // Dense over the joint-angle range, including every multiple of π/4 and its neighbours.
    let n = 2_000_000;
    for i in 0..=n {
        let x = -20.0 + 40.0 * i as f64 / n as f64;
        worst = worst.max(check(x));
    }
    for k in -64i32..=64 {
        let base = k as f64 * std::f64::consts::FRAC_PI_4;
        for d in [0.0, 1e-300, 1e-17, 1e-12, 1e-8, -1e-12, -1e-8] {
            worst = worst.max(check(base + d));
        }
    }
    // Random-looking wide arguments up to the reduction limit.
    let mut s = 0x1234_5678_9ABC_DEF0u64;
    for _ in 0..1_000_000 {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let u = (s >> 11) as f64 / (1u64 << 53) as f64;
        worst = worst.max(check((u - 0.5) * 1.6e6));
    }
    assert!(worst <= 2.3e-16, "worst absolute error {worst:e}");
    // Fallbacks and corners.
    assert_eq!(sin_cos(0.0), (0.0, 1.0));
    assert!(sin_cos(f64::NAN).0.is_nan());
    assert!(sin_cos(f64::INFINITY).1.is_nan());
    assert!(check(1e10) == 0.0 && check(-3e7) == 0.0);
}
