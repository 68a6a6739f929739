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

/// Distance from `got` to the C library's `want` in units in the last place of `want`.
fn ulps(got: f64, want: f64) -> f64 {
    let ulp = if want == 0.0 {
        f64::MIN_POSITIVE * f64::EPSILON
    } else {
        // The spacing of doubles at |want|: 2^(exponent − 52).
        let exponent = ((want.abs().to_bits() >> 52) as i64 - 1023).max(-1022);
        2f64.powi(exponent as i32 - 52)
    };
    (got - want).abs() / ulp
}

/// The accuracy the module documentation states, in ulps, over the range users pass (|θ| up to
/// 1e5 rad, and the dense joint range), on the scalar, portable-lane and dispatched-lane
/// paths: at most 1 ulp from the C library wherever |result| ≥ 1e-3; near a zero of sin or cos
/// (a result below 1e-3) the absolute error stays ≤ 2⁻⁵³ (half an ulp of 1), which is what the
/// kernels need: a rotation's entries are sums of such terms and of magnitude up to 1.
#[test]
fn error_in_ulps_over_the_users_range() {
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let mut uniform = |lo: f64, hi: f64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
    };
    for (range, count) in [(4.0, 400_000), (100.0, 400_000), (1e5, 800_000)] {
        let xs: Vec<f64> = (0..count).map(|_| uniform(-range, range)).collect();
        let (mut worst_ulps, mut worst_abs) = (0.0f64, 0.0f64);
        for chunk in xs.chunks(LANES) {
            let x: [f64; LANES] = chunk.try_into().unwrap();
            let (mut ls, mut lc, mut ps, mut pc) =
                ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
            sin_cos_lanes(&x, &mut ls, &mut lc);
            sin_cos_lanes_portable(&x, &mut ps, &mut pc);
            for i in 0..LANES {
                let (s0, c0) = x[i].sin_cos();
                let (s1, c1) = sin_cos(x[i]);
                for (got, want) in [
                    (s1, s0),
                    (c1, c0),
                    (ls[i], s0),
                    (lc[i], c0),
                    (ps[i], s0),
                    (pc[i], c0),
                ] {
                    worst_abs = worst_abs.max((got - want).abs());
                    if want.abs() >= 1e-3 {
                        worst_ulps = worst_ulps.max(ulps(got, want));
                    }
                }
            }
        }
        assert!(worst_ulps <= 1.0, "|θ| ≤ {range}: {worst_ulps} ulp");
        assert!(
            worst_abs <= f64::EPSILON / 2.0,
            "|θ| ≤ {range}: absolute {worst_abs:e}"
        );
    }
    // Non-finite and huge input: the library's answer (NaN for ±∞ and NaN), every path.
    for x in [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e300,
        -4e6,
        823_549.7,
    ] {
        let (s0, c0) = x.sin_cos();
        let (s1, c1) = sin_cos(x);
        assert!(
            s1.to_bits() == s0.to_bits() || (s1.is_nan() && s0.is_nan()),
            "{x}"
        );
        assert!(
            c1.to_bits() == c0.to_bits() || (c1.is_nan() && c0.is_nan()),
            "{x}"
        );
        let mut block = [0.5; LANES];
        block[3] = x;
        let (mut ls, mut lc) = ([0.0; LANES], [0.0; LANES]);
        sin_cos_lanes(&block, &mut ls, &mut lc);
        assert!(
            ls[3].to_bits() == s0.to_bits() || (ls[3].is_nan() && s0.is_nan()),
            "{x}"
        );
        assert!(
            lc[3].to_bits() == c0.to_bits() || (lc[3].is_nan() && c0.is_nan()),
            "{x}"
        );
        assert_eq!((ls[0], lc[0]), sin_cos(0.5));
    }
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

/// `sin_cos_in` on every lane path this CPU has: each lane bit for bit the value the scalar
/// lanes give with that path's multiply-add policy, over the users' range and the fallback cases
/// (a huge or non-finite angle beside ordinary ones gives each angle its own value).
#[test]
fn lane_sines_equal_the_scalar_lanes_on_every_path() {
    use screwkit_lie::fma::{Fused, KernelPath, MulAdd, Plain};
    use screwkit_lie::lanes::{dispatch_lanes_on, LaneKernel, Lanes};
    use screwkit_lie::trig::{sin_cos_in, sin_cos_lanes_with};

    /// Every block of eight arguments through `sin_cos_in`; the count of values that differ
    /// from the scalar lanes with the policy `A`.
    struct Sweep<'a, A>(&'a [f64], std::marker::PhantomData<A>);

    impl<A: MulAdd> LaneKernel for Sweep<'_, A> {
        type Output = usize;
        #[inline(always)]
        fn run<L: Lanes>(self, l: L) -> usize {
            let mut differ = 0;
            for x in self.0.chunks_exact(LANES) {
                let x: &[f64; LANES] = x.try_into().unwrap();
                let (mut gs, mut gc) = ([0.0; LANES], [0.0; LANES]);
                for k in (0..LANES).step_by(L::WIDTH) {
                    let (s, c) = sin_cos_in(l, l.load(&x[k..]));
                    l.store(s, &mut gs[k..]);
                    l.store(c, &mut gc[k..]);
                }
                let (mut ws, mut wc) = ([0.0; LANES], [0.0; LANES]);
                sin_cos_lanes_with::<A>(x, &mut ws, &mut wc);
                for i in 0..LANES {
                    differ += (gs[i].to_bits() != ws[i].to_bits()) as usize;
                    differ += (gc[i].to_bits() != wc[i].to_bits()) as usize;
                }
            }
            differ
        }
    }

    let mut xs = arguments(40_000, 40_000, 0x1234_5678_9ABC_DEF0);
    xs.truncate(xs.len() / LANES * LANES);
    xs.extend([0.3, 1e10, -2.0, f64::NAN, 5.0, f64::INFINITY, -3e7, 0.0]);
    xs.extend([
        -0.0,
        1e-300,
        823_549.0,
        -823_550.0,
        f64::NEG_INFINITY,
        7.0,
        1e6,
        -1e-9,
    ]);
    let mut ran = 0;
    for path in KernelPath::ALL {
        let differ = if path == KernelPath::Portable {
            dispatch_lanes_on(path, Sweep::<Plain>(&xs, Default::default())).ok()
        } else {
            dispatch_lanes_on(path, Sweep::<Fused>(&xs, Default::default())).ok()
        };
        if let Some(d) = differ {
            assert_eq!(d, 0, "{path:?}");
            ran += 1;
        }
    }
    assert_eq!(
        ran,
        KernelPath::ALL.iter().filter(|p| p.available()).count()
    );
}
