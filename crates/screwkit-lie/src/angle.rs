//! Angles: the one wrap of an angle into (−π, π] that every crate uses (IK projection of
//! continuous joints, analytic postures, the deduplication of postures in maps).

/// `x` moved by a multiple of 2π into (−π, π] (exactly `x` when it is in range; non-finite
/// input gives NaN).
#[inline]
pub fn wrap(x: f64) -> f64 {
    use std::f64::consts::PI;
    // The common cases without a division: already in range, or one turn off.
    if x > -PI && x <= PI {
        return x;
    }
    if x > PI && x <= 3.0 * PI {
        let y = x - 2.0 * PI;
        if y > -PI && y <= PI {
            return y;
        }
    }
    if x <= -PI && x > -3.0 * PI {
        let y = x + 2.0 * PI;
        if y > -PI && y <= PI {
            return y;
        }
    }
    let y = (x + PI).rem_euclid(2.0 * PI) - PI;
    if y <= -PI {
        y + 2.0 * PI
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::wrap;
    use std::f64::consts::PI;

    #[test]
    fn into_the_half_open_turn() {
        for x in [
            0.0,
            1.0,
            -1.0,
            PI,
            -PI,
            3.0 * PI,
            -3.0 * PI,
            7.5,
            -7.5,
            1e5,
            -1e5,
        ] {
            let y = wrap(x);
            assert!(y > -PI && y <= PI, "{x} -> {y}");
            let turns = (x - y) / (2.0 * PI);
            assert!((turns - turns.round()).abs() < 1e-9, "{x} -> {y}");
        }
        assert_eq!(wrap(1e-20), 1e-20);
        assert_eq!(wrap(-PI), PI);
        assert!(wrap(f64::NAN).is_nan() && wrap(f64::INFINITY).is_nan());
    }
}
