//! Joints named the same way in every front end: by name, or by an index that counts from 0
//! like the entries of q (`--lock panda_joint7=0.1`, `--lock 6=0.1`, `lock="panda_joint7"`,
//! `lock=6`).

use screwkit_solve::Kinematics;

use crate::error::{Error, Result};

/// A joint of q, by name or by 0-based index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JointRef {
    /// The joint's name in the file.
    Name(String),
    /// Its position in q (0-based).
    Index(usize),
}

impl JointRef {
    /// Reads a name or an index: digits are an index, unless a joint has that name
    /// ([`JointRef::resolve`] tries the name first).
    pub fn parse(s: &str) -> JointRef {
        match s.trim().parse::<usize>() {
            Ok(i) => JointRef::Index(i),
            Err(_) => JointRef::Name(s.trim().to_string()),
        }
    }

    /// The joint's position in q; `option` names the option in the error.
    pub fn resolve(&self, kin: &Kinematics, option: &'static str) -> Result<usize> {
        let names = kin.names();
        match self {
            JointRef::Name(n) => names.iter().position(|x| x == n).ok_or_else(|| {
                Error::option(
                    option,
                    format!("no joint \"{n}\" (the chain's: {})", names.join(", ")),
                )
            }),
            JointRef::Index(i) => {
                // A joint named by the number first (compared without formatting it: this
                // runs on every locked `ik_all` call).
                if let Some(k) = names.iter().position(|x| names_number(x, *i)) {
                    return Ok(k);
                }
                if *i < names.len() {
                    Ok(*i)
                } else {
                    Err(Error::option(
                        option,
                        format!(
                            "joint index {i} out of range: q has {} entries, counted from 0 ({})",
                            names.len(),
                            names.join(", ")
                        ),
                    ))
                }
            }
        }
    }
}

/// The lock word for a 7R arm's arm angle instead of a joint (`--lock arm_angle[=ψ]`,
/// Python's `lock="arm_angle"` or `arm_angle=ψ`): a joint of that name, if the chain has one,
/// wins.
pub const ARM_ANGLE: &str = "arm_angle";

impl JointRef {
    /// True when this names the arm angle ([`ARM_ANGLE`]) and no joint of `kin` has that name.
    pub fn is_arm_angle(&self, kin: &Kinematics) -> bool {
        matches!(self, JointRef::Name(n) if n == ARM_ANGLE && !kin.names().iter().any(|x| x == n))
    }
}

/// True when `name` is `i` written in decimal, as `i.to_string()` writes it.
fn names_number(name: &str, i: usize) -> bool {
    let b = name.as_bytes();
    !b.is_empty()
        && b.iter().all(u8::is_ascii_digit)
        && (b.len() == 1 || b[0] != b'0')
        && name.parse::<usize>() == Ok(i)
}

/// A locked joint and, optionally, its value: `JOINT[=VALUE]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Lock {
    /// The joint.
    pub joint: JointRef,
    /// Its value (None: the seed's).
    pub value: Option<f64>,
}

impl Lock {
    /// Parses `JOINT` or `JOINT=VALUE` (a finite number).
    pub fn parse(s: &str) -> Result<Lock> {
        match s.split_once('=') {
            None => Ok(Lock {
                joint: JointRef::parse(s),
                value: None,
            }),
            Some((j, v)) => {
                let value = v
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        Error::option(
                            "lock",
                            format!("{s}: \"{}\" is not a finite number", v.trim()),
                        )
                    })?;
                Ok(Lock {
                    joint: JointRef::parse(j),
                    value: Some(value),
                })
            }
        }
    }
}

impl std::str::FromStr for Lock {
    type Err = Error;
    fn from_str(s: &str) -> Result<Lock> {
        Lock::parse(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_indices_from_zero() {
        let urdf = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../assets/urdf/panda.urdf"
        ))
        .unwrap();
        let tree = screwkit_model::urdf::load_str(&urdf, "panda").unwrap();
        let chain = screwkit_model::Chain::from_tree(&tree, None, None).unwrap();
        let kin = Kinematics::new(&chain);
        assert_eq!(
            JointRef::parse("panda_joint7")
                .resolve(&kin, "lock")
                .unwrap(),
            6
        );
        assert_eq!(JointRef::parse("6").resolve(&kin, "lock").unwrap(), 6);
        assert_eq!(JointRef::parse(" 0 ").resolve(&kin, "lock").unwrap(), 0);
        let e = JointRef::parse("7").resolve(&kin, "lock").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("lock: joint index 7 out of range: q has 7 entries"),
            "{e}"
        );
        let e = JointRef::parse("elbow").resolve(&kin, "lock").unwrap_err();
        assert!(e.to_string().contains("no joint \"elbow\""), "{e}");
        assert_eq!(
            Lock::parse("panda_joint7=0.5").unwrap(),
            Lock {
                joint: JointRef::Name("panda_joint7".into()),
                value: Some(0.5)
            }
        );
        assert_eq!(Lock::parse("3").unwrap().value, None);
        assert!(Lock::parse("3=nan").is_err() && Lock::parse("3=x").is_err());
    }

    #[test]
    fn a_number_names_a_joint_as_it_is_written() {
        for i in [0usize, 1, 7, 10, 42, 123_456, usize::MAX] {
            assert!(names_number(&i.to_string(), i), "{i}");
        }
        for (name, i) in [
            ("07", 7),
            ("+7", 7),
            (" 7", 7),
            ("", 0),
            ("7a", 7),
            ("8", 7),
        ] {
            assert!(!names_number(name, i), "{name:?} {i}");
        }
        // A joint named "3" is the one a 3 means, wherever it is in the chain.
        let urdf = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../assets/urdf/panda.urdf"
        ))
        .unwrap()
        .replace("\"panda_joint1\"", "\"3\"");
        let tree = screwkit_model::urdf::load_str(&urdf, "panda").unwrap();
        let chain = screwkit_model::Chain::from_tree(&tree, None, None).unwrap();
        let kin = Kinematics::new(&chain);
        assert_eq!(JointRef::Index(3).resolve(&kin, "lock").unwrap(), 0);
        assert_eq!(JointRef::Index(4).resolve(&kin, "lock").unwrap(), 4);
    }
}
