//! The model crate's error type: every message names the file and the joint or link at fault.

use thiserror::Error;

/// An error while loading a URDF or building a chain, with the file it came from.
///
/// Displayed as `FILE: what is wrong`, e.g.
/// `arm.urdf: joint "elbow" has a zero axis`.
#[derive(Debug, Clone, Error)]
#[error("{file}: {kind}")]
pub struct ModelError {
    /// The file path, or a label such as `<string>` for text loaded from memory.
    pub file: String,
    /// What is wrong.
    pub kind: ErrorKind,
}

/// What is wrong with a URDF or with a chain request.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ErrorKind {
    /// The file could not be read: the operating system's reason (`kind`: not found,
    /// permission denied, a directory, …; `InvalidData` for bytes that are not text).
    #[error("cannot read the file: {message}")]
    Io {
        /// The I/O error's kind, so a front end can raise the matching error (Python's
        /// `FileNotFoundError`, `PermissionError`, …).
        kind: std::io::ErrorKind,
        /// What happened, in words.
        message: String,
    },
    /// The file is empty (or only whitespace).
    #[error("the file is empty")]
    Empty,
    /// The input is beyond one of the stated limits ([`crate::input`]): a file larger than
    /// 64 MiB, an endless stream, an expansion too large.
    #[error("too large: {0}")]
    TooLarge(String),
    /// Not well-formed XML.
    #[error("malformed XML: {0}")]
    Xml(String),
    /// A xacro construct that could not be expanded (the error's `file` is `FILE:LINE`).
    #[error("{0}")]
    XacroExpand(String),
    /// An MJCF element that cannot be read as kinematics (the error's `file` is `FILE:LINE`;
    /// the message names the element).
    #[error("{0}")]
    Mjcf(String),
    /// An SRDF element that cannot be read (the message names it and its line).
    #[error("{0}")]
    Srdf(String),
    /// Two links that are not rigidly attached (a frame given for a target, …).
    #[error(
        "link \"{to}\" is not rigidly attached to \"{from}\": joint \"{joint}\" between them moves"
    )]
    NotRigid {
        /// The reference link.
        from: String,
        /// The other link.
        to: String,
        /// A movable joint between them.
        joint: String,
    },
    /// The root element is not `<robot>`.
    #[error("the root element is <{0}>, expected <robot>")]
    NotARobot(String),
    /// urdf-rs rejected the document.
    #[error("URDF parser: {0}")]
    Urdf(String),
    /// A numeric attribute that is not made of the expected count of numbers.
    #[error("{element} {attribute}=\"{value}\": {problem}")]
    BadNumber {
        /// Where, e.g. `joint "elbow" <origin>`.
        element: String,
        /// The attribute name.
        attribute: String,
        /// The attribute text as written.
        value: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A link's `<inertial>` that does not give a usable mass and centre of mass.
    #[error("link \"{link}\" <inertial>: {problem}")]
    BadInertial {
        /// The link.
        link: String,
        /// What is wrong.
        problem: String,
    },
    /// A non-finite number on the requested chain.
    #[error("joint \"{joint}\": {what} is not finite")]
    NonFinite {
        /// The joint.
        joint: String,
        /// Which value.
        what: String,
    },
    /// Two links or two joints share a name.
    #[error("duplicate {what} name \"{name}\"")]
    Duplicate {
        /// "link" or "joint".
        what: &'static str,
        /// The repeated name.
        name: String,
    },
    /// A joint names a link that does not exist.
    #[error("joint \"{joint}\" names {role} link \"{link}\", which is not defined")]
    MissingLink {
        /// The joint.
        joint: String,
        /// "parent" or "child".
        role: &'static str,
        /// The missing link.
        link: String,
    },
    /// A link is the child of two joints.
    #[error("link \"{link}\" has two parent joints: \"{first}\" and \"{second}\"")]
    TwoParents {
        /// The link.
        link: String,
        /// One parent joint.
        first: String,
        /// The other parent joint.
        second: String,
    },
    /// More than one link has no parent.
    #[error("several root links (links without a parent joint): {0}")]
    SeveralRoots(String),
    /// Every link has a parent (a cycle), or there are no links.
    #[error("no root link: {0}")]
    NoRoot(String),
    /// Joints form a cycle.
    #[error("the joints form a cycle through links {0}")]
    Cycle(String),
    /// A link name that is not in the model.
    #[error("unknown link \"{link}\" ({available})")]
    UnknownLink {
        /// The requested link.
        link: String,
        /// The links that exist (`links: …`, up to 10), or for larger models the closest
        /// names (`did you mean "a", "b"? N links in all`).
        available: String,
    },
    /// The base is not an ancestor of the tip.
    #[error("base link \"{base}\" is not an ancestor of tip link \"{tip}\": no serial chain between them")]
    NotAncestor {
        /// The requested base.
        base: String,
        /// The requested tip.
        tip: String,
    },
    /// Base and tip are the same link.
    #[error("base and tip are the same link \"{0}\"")]
    SameLink(String),
    /// A frame name that is neither a link nor an added frame.
    #[error("unknown frame \"{frame}\" ({available})")]
    UnknownFrame {
        /// The requested frame.
        frame: String,
        /// The frames that exist, or the closest names (as for [`ErrorKind::UnknownLink`]).
        available: String,
    },
    /// A frame that cannot be added (no name, …).
    #[error("frame: {0}")]
    BadFrame(String),
    /// The tip was not given and there is more than one leaf below the base.
    #[error("cannot choose a tip link: {count} leaf links below \"{base}\" ({leaves}); pick one of them as the tip")]
    AmbiguousTip {
        /// The base.
        base: String,
        /// How many leaves.
        count: usize,
        /// Their names.
        leaves: String,
    },
    /// A joint type the chain cannot represent lies on the path.
    #[error("unsupported joint type in chain: joint \"{joint}\" is {kind} (only revolute, continuous, prismatic and fixed joints can be on a chain)")]
    UnsupportedJoint {
        /// The joint.
        joint: String,
        /// Its type.
        kind: String,
    },
    /// A movable joint whose axis is zero or shorter than 1e-9.
    #[error("joint \"{0}\" has a zero axis (norm below 1e-9)")]
    ZeroAxis(String),
    /// A row of a robot given by screw axes that is not a screw axis.
    #[error("screw row {row} (joint \"{joint}\"): {problem}")]
    Screw {
        /// The row (0-based).
        row: usize,
        /// The joint's name.
        joint: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A robot given by screw axes that cannot be built (its home pose, no rows, a table that
    /// cannot be read).
    #[error("{0}")]
    Screws(String),
    /// A tree that cannot be written in a file format (a name XML cannot hold).
    #[error("{0}")]
    Unwritable(String),
    /// A revolute or prismatic joint without `<limit>`.
    #[error("joint \"{0}\" is revolute/prismatic but has no <limit> element (URDF requires lower/upper; use type=\"continuous\" for an unbounded revolute joint)")]
    MissingLimit(String),
    /// lower > upper.
    #[error("joint \"{joint}\": lower limit {lower} is greater than upper limit {upper}")]
    LimitOrder {
        /// The joint.
        joint: String,
        /// The lower limit.
        lower: f64,
        /// The upper limit.
        upper: f64,
    },
    /// A mimic joint that cannot be resolved.
    #[error("joint \"{joint}\" mimics {problem}")]
    Mimic {
        /// The mimic joint.
        joint: String,
        /// What is wrong with its leader.
        problem: String,
    },
}

impl ModelError {
    /// An error of `kind` in `file`.
    pub fn new(file: impl Into<String>, kind: ErrorKind) -> Self {
        Self {
            file: file.into(),
            kind,
        }
    }
}
