//! Space or body: which frame a twist, a screw axis or a Jacobian is expressed in.

use std::fmt;
use std::str::FromStr;

/// The frame a twist, a screw axis or a Jacobian is expressed in (*Modern Robotics* ch. 3–5):
/// the fixed **space** frame {s} (for a robot: its base link), where V_s = Ṫ T⁻¹, or the moving
/// **body** frame {b} (the tip link), where V_b = T⁻¹ Ṫ; V_s = \[Ad_{T_sb}\] V_b.
///
/// Parses from and prints as `"space"` / `"body"` (the names the CLI and the Python package
/// take).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Frame {
    /// The space (base) frame {s}.
    Space,
    /// The body (tip) frame {b}.
    Body,
}

impl Frame {
    /// Both frames, space first.
    pub const ALL: [Frame; 2] = [Frame::Space, Frame::Body];

    /// `"space"` or `"body"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Frame::Space => "space",
            Frame::Body => "body",
        }
    }
}

impl fmt::Display for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The error of parsing a [`Frame`] from a string other than `space` or `body`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown frame \"{0}\": expected \"space\" or \"body\"")]
pub struct UnknownFrame(pub String);

impl FromStr for Frame {
    type Err = UnknownFrame;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "space" => Ok(Frame::Space),
            "body" => Ok(Frame::Body),
            other => Err(UnknownFrame(other.to_string())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints_both_frames() {
        for f in Frame::ALL {
            assert_eq!(f.as_str().parse::<Frame>(), Ok(f));
            assert_eq!(f.to_string(), f.as_str());
        }
        let err = "Space".parse::<Frame>().unwrap_err().to_string();
        assert!(
            err.contains("\"Space\"") && err.contains("\"body\""),
            "{err}"
        );
    }
}
