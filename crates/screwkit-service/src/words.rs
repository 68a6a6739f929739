//! The option words every front end takes: one enum per word family, each with one spelling
//! list ([`Word::ALL`] and [`Word::as_str`]), parsed by [`FromStr`](std::str::FromStr) (or
//! [`parse`]) and printed by `Display`. The CLI's value parsers, the Python keyword arguments
//! and the stubs' literal types all come from here; an error lists the accepted words.
//!
//! **Adding a word**: add the variant and its spelling to its `words!` block below; the CLI's
//! `--help`, the Python argument check and the error messages pick it up (the stubs' `Literal`
//! is checked against [`Word::ALL`] by the Python suite).

use std::fmt;

use screwkit_lie::Frame;

/// An option word family: every spelling, and how to print one.
pub trait Word: Copy + Sized + 'static {
    /// What the word names, for messages ("IK method", "frame", …).
    const KIND: &'static str;
    /// Every word, in the order help texts list them.
    const ALL: &'static [Self];
    /// Its spelling.
    fn as_str(self) -> &'static str;
    /// Other accepted spellings (`md` for `markdown`), never printed.
    fn aliases(self) -> &'static [&'static str] {
        &[]
    }
}

/// A word that is not one of its family's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {kind} \"{given}\": expected {}", expected(.accepted))]
pub struct WordError {
    /// The family ([`Word::KIND`]).
    pub kind: &'static str,
    /// What was given.
    pub given: String,
    /// The accepted words.
    pub accepted: Vec<&'static str>,
}

fn expected(words: &[&'static str]) -> String {
    let quoted: Vec<String> = words.iter().map(|w| format!("\"{w}\"")).collect();
    match quoted.as_slice() {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// Parses a word of family `W` (exact spelling or alias).
pub fn parse<W: Word>(s: &str) -> Result<W, WordError> {
    W::ALL
        .iter()
        .copied()
        .find(|w| w.as_str() == s || w.aliases().contains(&s))
        .ok_or_else(|| WordError {
            kind: W::KIND,
            given: s.to_string(),
            accepted: names::<W>(),
        })
}

/// Every spelling of family `W`, in [`Word::ALL`] order.
pub fn names<W: Word>() -> Vec<&'static str> {
    W::ALL.iter().map(|w| w.as_str()).collect()
}

/// Defines a word enum: variants with their spellings, `Word`, `FromStr`, `Display`.
macro_rules! words {
    ($(#[$meta:meta])* $name:ident, $kind:literal {
        $($(#[$vmeta:meta])* $variant:ident = $word:literal $(| $alias:literal)*),+ $(,)?
    }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[$vmeta])* $variant),+
        }

        impl Word for $name {
            const KIND: &'static str = $kind;
            const ALL: &'static [Self] = &[$($name::$variant),+];
            fn as_str(self) -> &'static str {
                match self {
                    $($name::$variant => $word),+
                }
            }
            fn aliases(self) -> &'static [&'static str] {
                match self {
                    $($name::$variant => &[$($alias),*]),+
                }
            }
        }

        impl std::str::FromStr for $name {
            type Err = WordError;
            fn from_str(s: &str) -> Result<Self, WordError> {
                parse(s)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

words! {
    /// The numerical IK method (`screwkit ik --method`, `Robot.ik(method=…)`).
    Method, "IK method" {
        /// Levenberg–Marquardt (adaptive damping; the default).
        Lm = "lm",
        /// Damped least squares (fixed damping).
        Dls = "dls",
        /// Newton–Raphson with the SVD pseudo-inverse.
        Nr = "nr",
    }
}

impl Method {
    /// The library's method, with `damping` (LM's floor μ̄, DLS's λ; None: the library's
    /// default). Newton–Raphson takes no damping.
    pub fn with_damping(
        self,
        damping: Option<f64>,
    ) -> Result<screwkit_solve::ik::IkMethod, crate::Error> {
        use screwkit_solve::ik::IkMethod;
        Ok(match (self, damping) {
            (Method::Lm, None) => IkMethod::LM,
            (Method::Lm, Some(f)) => IkMethod::LevenbergMarquardt { damping_floor: f },
            (Method::Dls, None) => IkMethod::DLS,
            (Method::Dls, Some(l)) => IkMethod::Dls { lambda: l },
            (Method::Nr, None) => IkMethod::NewtonRaphson,
            (Method::Nr, Some(_)) => {
                return Err(crate::Error::option(
                    "damping",
                    "Newton-Raphson (method \"nr\") takes no damping",
                ))
            }
        })
    }

    /// The word of a library method.
    pub fn of(m: &screwkit_solve::ik::IkMethod) -> Method {
        use screwkit_solve::ik::IkMethod;
        match m {
            IkMethod::LevenbergMarquardt { .. } => Method::Lm,
            IkMethod::Dls { .. } => Method::Dls,
            IkMethod::NewtonRaphson => Method::Nr,
        }
    }
}

words! {
    /// How the body's meshes are read (`--meshes`, `meshes=`): exactly, as triangle meshes,
    /// or as their convex hulls (MuJoCo's rule).
    Meshes, "mesh mode" {
        /// The triangles, in a bounding-volume tree (the default).
        Exact = "exact",
        /// Each mesh's convex hull.
        Convex = "convex",
    }
}

words! {
    /// What every-solution IK does with the solutions whose body collides (`--collisions`,
    /// `collisions=`): nothing (the default), flag each, or drop them.
    #[derive(Default)]
    Collisions, "collisions mode" {
        /// Solutions as they are, the body not looked at (the default).
        #[default]
        Ignore = "ignore",
        /// Each solution flagged: does its configuration collide (self or obstacles)?
        Flag = "flag",
        /// The colliding solutions dropped.
        Filter = "filter",
    }
}

words! {
    /// Which of a robot file's shapes are read (`--geometry`, `geometry=`): its collision
    /// shapes, its visual ones, both (the default), or none.
    #[derive(Default)]
    GeometryRoles, "geometry" {
        /// Collision shapes only.
        Collision = "collision",
        /// Visual shapes only.
        Visual = "visual",
        /// Both (the default).
        #[default]
        Both = "both",
        /// No geometry: kinematics only.
        None = "none",
    }
}

impl GeometryRoles {
    /// Whether shapes of `role` are read.
    pub fn keeps(self, role: screwkit_model::geometry::Role) -> bool {
        use screwkit_model::geometry::Role;
        matches!(
            (self, role),
            (GeometryRoles::Both, _)
                | (GeometryRoles::Collision, Role::Collision)
                | (GeometryRoles::Visual, Role::Visual)
        )
    }
}

words! {
    /// The frame of a screw axis or a twist: the library's [`Frame`] as a word.
    ScrewFrame, "frame" {
        /// The space frame (the base).
        Space = "space",
        /// The body frame (the tip).
        Body = "body",
    }
}

impl From<ScrewFrame> for Frame {
    fn from(f: ScrewFrame) -> Frame {
        match f {
            ScrewFrame::Space => Frame::Space,
            ScrewFrame::Body => Frame::Body,
        }
    }
}

words! {
    /// Which Jacobian (`screwkit jacobian --frame`, `Robot.jacobian(frame=…)`).
    JacobianFrame, "frame" {
        /// J_s: the twist of the body at the base origin, base axes.
        Space = "space",
        /// J_b: at the tip, tip axes.
        Body = "body",
        /// J_wa: angular velocity and the tip point's velocity, base axes (Pinocchio's
        /// `LOCAL_WORLD_ALIGNED`).
        WorldAligned = "world-aligned" | "world_aligned",
    }
}

impl JacobianFrame {
    /// The library's one Jacobian kind, for a chain's tip and for any frame of the tree.
    pub fn kind(self) -> screwkit_solve::JacobianKind {
        match self {
            JacobianFrame::Space => screwkit_solve::JacobianKind::Space,
            JacobianFrame::Body => screwkit_solve::JacobianKind::Body,
            JacobianFrame::WorldAligned => screwkit_solve::JacobianKind::WorldAligned,
        }
    }
}

words! {
    /// The screw axes a table shows.
    TableFrames, "frame" {
        /// S_i.
        Space = "space",
        /// B_i.
        Body = "body",
        /// Both, space first.
        Both = "both",
    }
}

impl TableFrames {
    /// The library frames, in table order.
    pub fn frames(self) -> Vec<Frame> {
        match self {
            TableFrames::Space => vec![Frame::Space],
            TableFrames::Body => vec![Frame::Body],
            TableFrames::Both => Frame::ALL.to_vec(),
        }
    }
}

words! {
    /// The text form of a screw table.
    TableFormat, "table format" {
        /// A Markdown table.
        Markdown = "markdown" | "md" | "text",
        /// Comma-separated values.
        Csv = "csv",
        /// One JSON object.
        Json = "json",
    }
}

words! {
    /// A direction to look at the robot from (pictures).
    View, "view" {
        /// From (1, 1, 1), z up: the isometric view.
        Iso = "iso",
        /// From +x (y to the right, z up).
        Front = "front",
        /// From −y (x to the right, z up).
        Side = "side",
        /// From +z (x to the right, y up).
        Top = "top",
    }
}

/// The views of a picture: one of them, or all four on one sheet (`all`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Views {
    /// One view.
    One(View),
    /// The four, in [`View`]'s `ALL` order.
    All,
}

impl Word for Views {
    const KIND: &'static str = "view";
    const ALL: &'static [Self] = &[
        Views::One(View::Iso),
        Views::One(View::Front),
        Views::One(View::Side),
        Views::One(View::Top),
        Views::All,
    ];
    fn as_str(self) -> &'static str {
        match self {
            Views::One(v) => v.as_str(),
            Views::All => "all",
        }
    }
}

impl std::str::FromStr for Views {
    type Err = WordError;
    fn from_str(s: &str) -> Result<Self, WordError> {
        parse(s)
    }
}

impl fmt::Display for Views {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Views {
    /// The views drawn.
    pub fn views(self) -> Vec<View> {
        match self {
            Views::One(v) => vec![v],
            Views::All => View::ALL.to_vec(),
        }
    }
}

words! {
    /// Which names a drawing writes (`screwkit draw --labels`, `Robot.draw(labels=…)`); each
    /// placed off the others, with a leader line when moved from its point, or left out when
    /// there is no room.
    Labels, "labels" {
        /// No names.
        None = "none",
        /// The names of the ends: a chain's tip, every leaf of a tree (the default).
        Leaves = "leaves",
        /// Every link's name.
        All = "all",
    }
}

words! {
    /// How dynamics takes a file's `<inertial>`s (`screwkit dynamics --inertias`,
    /// `Robot.set_dynamics_options(inertias=…)`): one that no rigid body has is an error naming
    /// its link, taken as given, or balanced as MuJoCo's `balanceinertia` does.
    Inertias, "inertias rule" {
        /// Refuse an impossible inertial, naming its link (the default).
        Check = "check",
        /// Take the file's numbers as they are.
        AsGiven = "as-given" | "as_given",
        /// A triangle-inequality breach: all three principal moments set to their mean.
        Balance = "balance",
    }
}

impl Inertias {
    /// The library's rule.
    pub fn rule(self) -> screwkit_solve::tree::dynamics::Inertias {
        use screwkit_solve::tree::dynamics::Inertias as I;
        match self {
            Inertias::Check => I::Check,
            Inertias::AsGiven => I::AsGiven,
            Inertias::Balance => I::Balance,
        }
    }
}

words! {
    /// How a Cartesian path moves the tool between poses (`Robot.cartesian_path(interpolation=…)`).
    Interpolation, "interpolation" {
        /// One screw motion between each two poses (the default).
        Screw = "screw",
        /// The origin on the straight line, the rotation about one axis.
        Line = "line",
    }
}

impl Interpolation {
    /// The library's.
    pub fn motion(self) -> screwkit_solve::path::Interpolation {
        match self {
            Interpolation::Screw => screwkit_solve::path::Interpolation::Screw,
            Interpolation::Line => screwkit_solve::path::Interpolation::Line,
        }
    }
}

/// Which screw axes a drawing shows (`screwkit draw --axes`, `Robot.draw(axes=…)`): `all`,
/// `none`, or joints by name or by their number in the drawing (`J1,J2`, `1,2`). Not given
/// ([`Axes::Auto`]): every axis of a chain, or of a tree of at most [`Axes::AUTO_MAX`] joints;
/// none for a larger tree (a humanoid's 44 axes hide it).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Axes {
    /// The rule above.
    #[default]
    Auto,
    /// Every joint's axis.
    All,
    /// No axis.
    None,
    /// The joints named (or numbered, from 1, as the drawing labels them).
    Joints(Vec<String>),
}

impl Axes {
    /// The most joints of a tree whose axes are drawn when not told.
    pub const AUTO_MAX: usize = 12;

    /// Which of the joints `names` (in the drawing's order, numbered from 1) show their axis:
    /// an error naming a joint that is not one of them.
    pub fn shown(&self, names: &[&str], chain: bool) -> Result<Vec<bool>, String> {
        Ok(match self {
            Axes::Auto => vec![chain || names.len() <= Self::AUTO_MAX; names.len()],
            Axes::All => vec![true; names.len()],
            Axes::None => vec![false; names.len()],
            Axes::Joints(asked) => {
                let mut shown = vec![false; names.len()];
                for a in asked {
                    let k = names.iter().position(|n| n == a).or_else(|| {
                        a.parse::<usize>()
                            .ok()
                            .filter(|k| (1..=names.len()).contains(k))
                            .map(|k| k - 1)
                    });
                    match k {
                        Some(k) => shown[k] = true,
                        None => {
                            return Err(format!(
                                "no joint \"{a}\" among the {} drawn ({}{})",
                                names.len(),
                                names.iter().take(8).cloned().collect::<Vec<_>>().join(", "),
                                if names.len() > 8 { ", …" } else { "" }
                            ))
                        }
                    }
                }
                shown
            }
        })
    }
}

impl std::str::FromStr for Axes {
    type Err = String;
    /// `all`, `none`, or joint names or numbers separated by commas.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "all" => Ok(Axes::All),
            "none" => Ok(Axes::None),
            list => {
                let names: Vec<String> = list.split(',').map(|n| n.trim().to_string()).collect();
                if names.iter().any(String::is_empty) {
                    return Err(format!(
                        "expected \"all\", \"none\" or joint names separated by commas, got \"{s}\""
                    ));
                }
                Ok(Axes::Joints(names))
            }
        }
    }
}

words! {
    /// How the K orientations of each voxel of a map are chosen.
    OrientationMode, "orientation mode" {
        /// K rotations spread evenly over SO(3) (a super-Fibonacci spiral, Alexa, CVPR 2022):
        /// the reachability index of Zacharias et al. over all orientations.
        Free = "free",
        /// K directions spread evenly on the unit sphere (a Fibonacci lattice), the tool's z
        /// axis pointing from the direction's point on a sphere around the voxel towards its
        /// centre, as in capability maps; the roll about that axis is fixed (x axis in the
        /// plane of z and the base's z axis, or the base's x axis when they are parallel).
        Directions = "directions",
    }
}

words! {
    /// Which 2π representatives of each analytic posture are listed (`screwkit ik --all
    /// --representatives`, `Robot.ik_all(representatives=…)`): a joint whose limits are wider
    /// than 2π reaches a posture at several angles.
    RepresentativesChoice, "representatives" {
        /// One row per posture, each joint at its representative nearest the seed (the default).
        Nearest = "nearest",
        /// Every 2π shift inside the limits (a UR5 with ±2π limits: up to 2⁶ rows per posture).
        All = "all",
        /// One row per posture, each angle in (−π, π] where the limits allow.
        Principal = "none",
    }
}

impl RepresentativesChoice {
    /// The library's choice.
    pub fn kind(self) -> screwkit_solve::analytic::RepresentativeKind {
        use screwkit_solve::analytic::RepresentativeKind;
        match self {
            RepresentativesChoice::Nearest => RepresentativeKind::Nearest,
            RepresentativesChoice::All => RepresentativeKind::All,
            RepresentativesChoice::Principal => RepresentativeKind::One,
        }
    }
}

words! {
    /// Which IK a map uses.
    SolverChoice, "map solver" {
        /// Analytic when the chain is a 6R arm with a closed form, numerical otherwise.
        Auto = "auto",
        /// The analytic solver (every solution); an error for chains without a closed form.
        Analytic = "analytic",
        /// Numerical IK (one solution within the limits per pose).
        Numerical = "numerical",
    }
}

/// The words of the map file format: how a mode and a solver choice are spelt in a map's
/// metadata (kept as the first maps wrote them: `"Free"`, `"Auto"`, …, so that every map
/// written so far still reads and merges).
mod map_spelling {
    use super::{OrientationMode, SolverChoice};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    fn title(w: &str) -> String {
        let mut c = w.chars();
        c.next()
            .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
            .unwrap_or_default()
    }

    macro_rules! serde_title {
        ($t:ty) => {
            impl Serialize for $t {
                fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                    s.serialize_str(&title(super::Word::as_str(*self)))
                }
            }
            impl<'de> Deserialize<'de> for $t {
                fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                    let s = String::deserialize(d)?;
                    super::parse::<$t>(&s.to_ascii_lowercase()).map_err(serde::de::Error::custom)
                }
            }
        };
    }
    serde_title!(OrientationMode);
    serde_title!(SolverChoice);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_word_parses_back_and_unknown_words_list_the_family() {
        fn check<W: Word + PartialEq + std::fmt::Debug + std::str::FromStr<Err = WordError>>() {
            for &w in W::ALL {
                assert_eq!(w.as_str().parse::<W>().unwrap(), w);
                for a in w.aliases() {
                    assert_eq!(a.parse::<W>().unwrap(), w);
                }
            }
            let e = "nonsense".parse::<W>().unwrap_err();
            for &w in W::ALL {
                assert!(
                    e.to_string().contains(&format!("\"{}\"", w.as_str())),
                    "{e}"
                );
            }
        }
        check::<Method>();
        check::<ScrewFrame>();
        check::<JacobianFrame>();
        check::<TableFrames>();
        check::<TableFormat>();
        check::<View>();
        check::<Views>();
        check::<Labels>();
        check::<Inertias>();
        check::<Interpolation>();
        check::<OrientationMode>();
        check::<SolverChoice>();
        assert_eq!(
            "x".parse::<Method>().unwrap_err().to_string(),
            "unknown IK method \"x\": expected \"lm\", \"dls\" or \"nr\""
        );
    }

    /// `--axes`: the rule when not told (a chain all, a tree of ≤ 12 joints all, a larger one
    /// none), names and numbers, and an unknown joint or an empty name refused by name.
    #[test]
    fn axes_are_chosen_by_name_number_or_rule() {
        let three = ["a", "b", "c"];
        let many: Vec<String> = (0..13).map(|k| format!("j{k}")).collect();
        let many: Vec<&str> = many.iter().map(String::as_str).collect();
        assert_eq!(Axes::Auto.shown(&three, false).unwrap(), [true; 3]);
        assert_eq!(Axes::Auto.shown(&many, true).unwrap(), vec![true; 13]);
        assert_eq!(Axes::Auto.shown(&many, false).unwrap(), vec![false; 13]);
        assert_eq!(
            Axes::Auto.shown(&many[..12], false).unwrap(),
            vec![true; 12]
        );
        let pick: Axes = "c, 1".parse().unwrap();
        assert_eq!(pick.shown(&three, false).unwrap(), [true, false, true]);
        assert_eq!(
            "none".parse::<Axes>().unwrap().shown(&three, true).unwrap(),
            [false; 3]
        );
        assert_eq!(
            "all".parse::<Axes>().unwrap().shown(&many, false).unwrap(),
            vec![true; 13]
        );
        let e = "b,z"
            .parse::<Axes>()
            .unwrap()
            .shown(&three, true)
            .unwrap_err();
        assert!(e.contains("no joint \"z\"") && e.contains("a, b, c"), "{e}");
        let e = "4"
            .parse::<Axes>()
            .unwrap()
            .shown(&three, true)
            .unwrap_err();
        assert!(e.contains("\"4\""), "{e}");
        assert!("a,,b".parse::<Axes>().is_err() && "".parse::<Axes>().is_err());
    }

    #[test]
    fn map_files_keep_their_spelling() {
        assert_eq!(
            serde_json::to_string(&OrientationMode::Directions).unwrap(),
            "\"Directions\""
        );
        assert_eq!(
            serde_json::from_str::<SolverChoice>("\"Auto\"").unwrap(),
            SolverChoice::Auto
        );
    }
}
