//! A seeded mutation fuzzer for the parsers (no nightly toolchain needed): inputs start from
//! real files and are mutated — bytes flipped, spans deleted, duplicated or moved, tokens of
//! the format spliced in, numbers replaced by absurd ones — and fed to the code under test
//! for a bounded time. Reproducible: the same seed gives the same inputs.
//!
//! The time each run takes is `SCREWKIT_FUZZ_SECS` seconds (default: `default_secs`, a few
//! seconds in the test suite); set it to 600 for a ten-minute run. A panic names the seed and
//! the iteration, and the failing input is written to `target/fuzz-failure-NAME.bin`.

use std::time::{Duration, Instant};

use screwkit_solve::sample::SplitMix64;

/// Inputs are mutated from `seeds` with `dictionary` tokens spliced in.
pub struct Mutator<'a> {
    rng: SplitMix64,
    seeds: &'a [Vec<u8>],
    dictionary: &'a [&'a [u8]],
}

/// Numbers a parser may not expect.
const ABSURD: &[&[u8]] = &[
    b"NaN",
    b"-inf",
    b"1e309",
    b"-1e309",
    b"1e-320",
    b"0",
    b"-0",
    b"9223372036854775808",
    b"-9223372036854775809",
    b"18446744073709551616",
    b"4294967296",
    b"1e12",
    b"-1",
    b"3.4028236e38",
    b"0x10",
    b"1_000",
    b"\xc3\xa9",
    b"\xff\xfe",
    b"\0",
];

impl<'a> Mutator<'a> {
    /// A mutator over `seeds` (at least one) splicing in `dictionary` tokens.
    pub fn new(seed: u64, seeds: &'a [Vec<u8>], dictionary: &'a [&'a [u8]]) -> Self {
        assert!(
            !seeds.is_empty(),
            "the fuzzer needs at least one seed input"
        );
        Self {
            rng: SplitMix64(seed),
            seeds,
            dictionary,
        }
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.rng.next_u64() % n as u64) as usize
        }
    }

    fn token(&mut self) -> Vec<u8> {
        match self.below(3) {
            0 if !self.dictionary.is_empty() => {
                self.dictionary[self.below(self.dictionary.len())].to_vec()
            }
            1 => ABSURD[self.below(ABSURD.len())].to_vec(),
            _ => (0..1 + self.below(8))
                .map(|_| self.rng.next_u64() as u8)
                .collect(),
        }
    }

    /// The next input: a seed with 1 to 8 mutations.
    pub fn input(&mut self) -> Vec<u8> {
        let mut v = self.seeds[self.below(self.seeds.len())].clone();
        for _ in 0..1 + self.below(8) {
            let len = v.len();
            let at = self.below(len + 1);
            match self.below(7) {
                0 if len > 0 => {
                    let i = self.below(len);
                    v[i] ^= 1 << self.below(8);
                }
                1 => {
                    let end = (at + 1 + self.below(64)).min(len);
                    v.drain(at..end);
                }
                2 => {
                    let end = (at + 1 + self.below(256)).min(len);
                    let span = v[at..end].to_vec();
                    let to = self.below(v.len() + 1);
                    let times = 1 + self.below(3);
                    for _ in 0..times {
                        v.splice(to..to, span.iter().copied());
                    }
                }
                3 | 4 => {
                    let t = self.token();
                    v.splice(at..at, t);
                }
                5 => {
                    // Replace a number with an absurd one.
                    if let Some(s) = (at..len).find(|&i| v[i].is_ascii_digit()) {
                        let e = (s..len)
                            .find(|&i| !(v[i].is_ascii_digit() || v[i] == b'.'))
                            .unwrap_or(len);
                        let t = ABSURD[self.below(ABSURD.len())].to_vec();
                        v.splice(s..e, t);
                    }
                }
                _ => {
                    // Cross over with another seed.
                    let other = &self.seeds[self.below(self.seeds.len())];
                    let (a, b) = (self.below(other.len() + 1), self.below(other.len() + 1));
                    let (a, b) = (a.min(b), a.max(b).min(a.min(b) + 512));
                    let part = other[a..b].to_vec();
                    let end = (at + self.below(512)).min(v.len());
                    v.splice(at..end, part);
                }
            }
        }
        v
    }
}

/// Seconds a fuzz run takes: `SCREWKIT_FUZZ_SECS`, else `default_secs`.
pub fn seconds(default_secs: f64) -> f64 {
    std::env::var("SCREWKIT_FUZZ_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default_secs)
}

/// Feeds mutated inputs to `target` for [`seconds`]`(default_secs)`; a panic in `target` is
/// caught, the input saved and the test failed with the iteration named. Returns the number
/// of inputs run (printed, so a long run says how many).
pub fn run(
    name: &str,
    seed: u64,
    default_secs: f64,
    seeds: &[Vec<u8>],
    dictionary: &[&[u8]],
    mut target: impl FnMut(&[u8]),
) -> u64 {
    let secs = seconds(default_secs);
    let mut m = Mutator::new(seed, seeds, dictionary);
    let start = Instant::now();
    let mut n = 0u64;
    while start.elapsed() < Duration::from_secs_f64(secs) {
        let input = m.input();
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| target(&input)));
        if r.is_err() {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join(format!("../../target/fuzz-failure-{name}.bin"));
            let _ = std::fs::write(&path, &input);
            panic!(
                "fuzz {name}: input {n} (seed {seed}) panicked; saved to {}",
                path.display()
            );
        }
        n += 1;
    }
    eprintln!("fuzz {name}: {n} inputs in {secs:.0} s without a crash");
    n
}
