//! A stable 64-bit digest (FNV-1a) of words and numbers: what files written by screwkit (a
//! reachability map's metadata) store to tell whether two of them were computed from the same
//! robot. Numbers are hashed by their exact bits; the digest is the same on every machine and
//! toolchain (std's hasher is not guaranteed to be).

/// An FNV-1a 64 digest being fed.
#[derive(Debug, Clone, Copy)]
pub struct Digest(u64);

impl Default for Digest {
    fn default() -> Self {
        Digest(0xcbf2_9ce4_8422_2325)
    }
}

impl Digest {
    /// A digest of nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Feeds bytes.
    pub fn bytes(&mut self, bytes: &[u8]) -> &mut Self {
        for b in bytes {
            self.0 ^= u64::from(*b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        self
    }

    /// Feeds a word, ended by a 0 byte (so "ab", "c" and "a", "bc" differ).
    pub fn word(&mut self, word: &str) -> &mut Self {
        self.bytes(word.as_bytes()).bytes(&[0])
    }

    /// Feeds a number's exact bits.
    pub fn num(&mut self, x: f64) -> &mut Self {
        self.bytes(&x.to_bits().to_le_bytes())
    }

    /// Feeds a quantity: a number's exact bits, −0 taken as +0 (a pose built from angles of 0
    /// has −0 where one written out has 0; they place a shape alike).
    pub fn value(&mut self, x: f64) -> &mut Self {
        self.num(x + 0.0)
    }

    /// Feeds quantities ([`Digest::value`]).
    pub fn values(&mut self, xs: impl IntoIterator<Item = f64>) -> &mut Self {
        for x in xs {
            self.value(x);
        }
        self
    }

    /// Feeds numbers.
    pub fn nums(&mut self, xs: impl IntoIterator<Item = f64>) -> &mut Self {
        for x in xs {
            self.num(x);
        }
        self
    }

    /// Feeds a count or an index.
    pub fn count(&mut self, n: usize) -> &mut Self {
        self.bytes(&(n as u64).to_le_bytes())
    }

    /// The digest as 16 hex digits.
    pub fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_reference_values() {
        // The published FNV-1a 64 test vectors.
        assert_eq!(Digest::new().hex(), "cbf29ce484222325");
        assert_eq!(Digest::new().bytes(b"a").hex(), "af63dc4c8601ec8c");
        assert_eq!(Digest::new().bytes(b"foobar").hex(), "85944171f73967e8");
    }

    #[test]
    fn words_are_delimited() {
        let a = Digest::new().word("ab").word("c").hex();
        let b = Digest::new().word("a").word("bc").hex();
        assert_ne!(a, b);
        assert_ne!(Digest::new().num(0.0).hex(), Digest::new().num(-0.0).hex());
        assert_eq!(
            Digest::new().value(0.0).hex(),
            Digest::new().value(-0.0).hex()
        );
    }
}
