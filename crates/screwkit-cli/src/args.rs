//! Command-line arguments (clap derive).

use std::path::PathBuf;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand, ValueEnum};
use screwkit_service::words::{
    self, Axes, Collisions, GeometryRoles, Inertias, JacobianFrame, Labels, Meshes, Method,
    OrientationMode, RepresentativesChoice, SolverChoice, TableFrames, View, Views, Word,
};
use screwkit_service::{IkSettings, LoadOptions, Lock, ReachSpec, Shard};

/// The value parser of an option word: the floor's words (`--help` lists them, aliases are
/// accepted and hidden), parsed by the floor.
fn word<W: Word + Send + Sync + Clone>() -> impl TypedValueParser<Value = W> {
    let values = W::ALL.iter().flat_map(|w| {
        std::iter::once(PossibleValue::new(w.as_str())).chain(
            w.aliases()
                .iter()
                .map(|a| PossibleValue::new(*a).hide(true)),
        )
    });
    PossibleValuesParser::new(values).try_map(|s: String| words::parse::<W>(&s))
}

/// The defaults of numerical IK (the library's, through the floor).
fn ik() -> IkSettings {
    IkSettings::default()
}

/// The defaults of a map.
fn map() -> ReachSpec {
    ReachSpec::default()
}

/// Robot kinematics from URDF with screw theory: screw axes, FK, Jacobians, IK.
#[derive(Debug, Parser)]
#[command(name = "screwkit", version, about, long_about = None)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
    /// Output format: human-readable text/Markdown (default), csv (table only) or json.
    #[arg(long, value_enum, global = true, default_value_t = Format::Text)]
    pub format: Format,
}

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Human-readable text.
    Text,
    /// Markdown (same as text).
    Md,
    /// Comma-separated values (table only).
    Csv,
    /// One JSON object (per line in batch mode).
    Json,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Robot name, links, joints, leaves, default chain and a tree drawing.
    Info(InfoArgs),
    /// The screw-axis table (space and/or body) and the home pose M.
    Table(TableArgs),
    /// Forward kinematics: the tip pose (or every link's) at joint values.
    Fk(FkArgs),
    /// The 6 x n Jacobian (space or body) at joint values, optionally analysed.
    Jacobian(JacobianArgs),
    /// Inverse kinematics: joint values reaching a target pose.
    Ik(Box<IkArgs>),
    /// Matrix exponential of a twist: e^[S]θ.
    Exp(ExpArgs),
    /// Matrix logarithm of a transform: screw axis, θ, pitch, axis point.
    Log(LogArgs),
    /// The IK benchmark protocol (solve rate, mean/median/p99) plus FK and Jacobian ns/call.
    Bench(BenchArgs),
    /// An SVG picture of the chain at q: skeleton, joints, screw axes S_i(q), base/tip frames.
    Draw(DrawArgs),
    /// A self-contained interactive HTML page: the chain in 3D with a slider per joint.
    View(ViewArgs),
    /// Expand a xacro file and print the URDF.
    Xacro(XacroFileArgs),
    /// Write the robot's kinematic tree as URDF (links, joints, limits, mimic rules, masses;
    /// an MJCF model's sites as fixed child links), so that URDF-only tools can use it.
    Urdf(UrdfArgs),
    /// A reachability map: voxels x orientations solved by IK, written as .npz (`reach merge`
    /// joins shards).
    Reach(Box<ReachArgs>),
    /// The robot's body at q: in collision or not, the colliding link pairs, the closest pair
    /// (its signed distance, witness points and normal), from the file's <collision> shapes.
    Collide(CollideArgs),
    /// Generate the allowed-collision matrix as MoveIt's setup assistant does and write it as
    /// SRDF (adjacent links, pairs colliding at the default pose or almost always).
    Srdf(SrdfArgs),
    /// The whole tree's dynamics at (q, v, a): inverse dynamics τ, gravity g(q), nonlinear
    /// effects h(q, v), the mass matrix M(q) and the energies, from the links' <inertial>s.
    Dynamics(DynamicsArgs),
    /// A Cartesian path: the tool from the configuration --from through --via poses to --to,
    /// along one screw per segment (or a straight line), the joints on one IK branch; stops
    /// (and says why) at a singularity, where a branch ends or a pose is out of reach. With
    /// --timed, the time-optimal timing within the joints' velocity and acceleration limits.
    Path(PathArgs),
}

/// The library's path options, whose defaults the flags show.
fn path_defaults() -> screwkit_solve::path::PathOptions {
    screwkit_solve::path::PathOptions::default()
}

/// `path`.
#[derive(Debug, Args)]
pub struct PathArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// The start configuration q1,q2,... (the tool starts at its pose).
    #[arg(long = "from", value_parser = parse_list, allow_hyphen_values = true, required_unless_present = "input")]
    pub start: Option<List>,
    /// The goal pose: x,y,z,roll,pitch,yaw (6 numbers), x,y,z,qx,qy,qz,qw (7) or a 4x4 matrix
    /// row-major (16).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true, required_unless_present_any = ["input", "waypoints"])]
    pub to: Option<List>,
    /// The poses to pass through from a .npy file of float64, the last the goal: (K, 4, 4), or
    /// K rows of 6, 7 or 16 numbers (as --to).
    #[arg(long, value_name = "FILE.npy", conflicts_with_all = ["to", "via", "input"])]
    pub waypoints: Option<String>,
    /// A pose on the way (as --to), in order; repeat for several.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true, conflicts_with = "input")]
    pub via: Vec<List>,
    /// Many paths: a file (or - for stdin) of JSON lines {"from": [q...], "to": [pose...],
    /// "via": [[pose...], ...]} (via optional), computed on all cores; one JSON line out per
    /// line in (the path's report, or {"error", "line"}).
    #[arg(long, conflicts_with_all = ["start", "to", "output"])]
    pub input: Option<String>,
    /// The origin along straight lines (the rotation about one axis) instead of one screw
    /// motion per segment.
    #[arg(long)]
    pub line: bool,
    /// The largest tool motion per step (m along the chord, and rad of turn).
    #[arg(long, default_value_t = path_defaults().max_step)]
    pub max_step: f64,
    /// The largest joint motion per step (rad or m).
    #[arg(long, default_value_t = path_defaults().max_joint_step)]
    pub max_joint_step: f64,
    /// A 7R arm: the joint held at the start's value along the path (by name or index in q,
    /// from 0), or arm_angle (an arm with a spherical shoulder and wrist: its arm angle held);
    /// default: the joint the closed-form solver chooses.
    #[arg(long, value_name = "JOINT", value_parser = |s: &str| Ok::<_, String>(screwkit_service::joint::JointRef::parse(s)))]
    pub lock: Option<screwkit_service::joint::JointRef>,
    /// Keeping the body clear of contact: the path stops before a sample that is not, naming
    /// the pair.
    #[command(flatten)]
    pub avoid: Avoid,
    /// Write the joint path (K × dof; with --timed: M × (1 + dof), t then q every --dt) to this
    /// .npy file.
    #[arg(short = 'o', long)]
    pub output: Option<String>,
    /// Write the joint plot (SVG: each joint against the place on the path, or against time
    /// with --timed; the limits dashed) to this file.
    #[arg(long, value_name = "FILE.svg", conflicts_with = "input")]
    pub plot: Option<String>,
    /// Time the path: its fastest timing within the velocity limits (--vel, default the
    /// file's) and the acceleration limits --acc.
    #[arg(long, requires = "acc")]
    pub timed: bool,
    /// Velocity limits v1,v2,... (default: the file's <limit velocity>).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub vel: Option<List>,
    /// Acceleration limits a1,a2,...
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub acc: Option<List>,
    /// The timed path's sample step (s).
    #[arg(long, default_value_t = 0.001)]
    pub dt: f64,
}

/// Keeping a robot's body clear of contact (`path`, `reach`): the flag, the margin, and the
/// body's SRDF and obstacles.
#[derive(Debug, Args)]
pub struct Avoid {
    /// Keep the body clear of contact — itself, the rest of the robot at its neutral pose, and
    /// the --obstacles — by --margin.
    #[arg(long)]
    pub avoid_collisions: bool,
    /// With --avoid-collisions: the least distance (m) kept between every checked pair.
    #[arg(long, requires = "avoid_collisions", default_value_t = screwkit_service::body::DEFAULT_MARGIN)]
    pub margin: f64,
    /// With --avoid-collisions: an SRDF whose disable_collisions pairs are not checked.
    #[arg(long, requires = "avoid_collisions")]
    pub srdf: Option<PathBuf>,
    /// With --avoid-collisions: a scene file (JSON) of obstacles (as `collide --obstacles`).
    #[arg(long, requires = "avoid_collisions")]
    pub obstacles: Option<PathBuf>,
}

impl Avoid {
    /// The body's model (the SRDF and obstacles applied) when --avoid-collisions is given.
    pub fn model(
        &self,
        robot: &screwkit_service::Robot,
    ) -> Result<Option<screwkit_collision::CollisionModel>, screwkit_service::Error> {
        if !self.avoid_collisions {
            return Ok(None);
        }
        screwkit_service::body::robot_model(robot, self.srdf.as_deref(), self.obstacles.as_deref())
            .map(Some)
    }
}

/// `dynamics`.
#[derive(Debug, Args)]
pub struct DynamicsArgs {
    /// The robot.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// The whole tree's configuration q1,q2,... (nq values: `info --format json`'s
    /// "variables"; a floating base's x,y,z,qx,qy,qz,qw first).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true, required_unless_present = "input")]
    pub q: Option<List>,
    /// The velocity (nv values; default zero).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true, conflicts_with = "input")]
    pub v: Option<List>,
    /// The acceleration (nv values; default zero).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true, conflicts_with = "input")]
    pub a: Option<List>,
    /// How to take an <inertial> that no rigid body has: refuse it naming its link (check),
    /// take it as it is (as-given), or balance a triangle-inequality breach as MuJoCo's
    /// balanceinertia does (balance: the three principal moments set to their mean).
    #[arg(long, value_parser = word::<Inertias>(), default_value_t = Inertias::Check)]
    pub inertias: Inertias,
    /// Add each joint's armature (MJCF `armature`) to the mass matrix's diagonal (off by
    /// default, as in Pinocchio; MuJoCo always adds it).
    #[arg(long)]
    pub armature: bool,
    /// Add each joint's viscous damping (MJCF `damping`, URDF <dynamics damping>) to τ and h:
    /// damping · v (off by default; MuJoCo counts it among its passive forces).
    #[arg(long)]
    pub damping: bool,
    /// Batch mode: JSON lines {"q": [...], "v": [...], "a": [...]} (v and a optional, zero
    /// when left out) from FILE or - (stdin); one JSON report per line, a bad line's error
    /// naming it, the others computed.
    #[arg(long, conflicts_with = "q")]
    pub input: Option<String>,
}

/// `collide`.
#[derive(Debug, Args)]
pub struct CollideArgs {
    /// The robot.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// The configurations (the whole tree's q, or the chain's joint values; with --input
    /// FILE.npy and --output FILE.npy: each row's smallest signed distance, (N,)).
    #[command(flatten)]
    pub at: Configurations,
    /// An SRDF whose disable_collisions pairs are not checked.
    #[arg(long)]
    pub srdf: Option<PathBuf>,
    /// A scene file (JSON) of obstacles checked against every link: {"obstacles": [{"name",
    /// "shape": box|sphere|cylinder|capsule|mesh, "size"|"radius"|"length"|"path"|"scale",
    /// "xyz", "rpy" | "pose"}]} (docs/guide/collision.md).
    #[arg(long)]
    pub obstacles: Option<PathBuf>,
    /// Also every checked pair's signed distance with its Jacobian row (nv: the distance's
    /// rate along the tree's velocity), JSON `distances`.
    #[arg(long)]
    pub distances: bool,
}

/// `srdf`.
#[derive(Debug, Args)]
pub struct SrdfArgs {
    /// The robot.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// Where to write the SRDF (- or nothing: standard output).
    #[arg(short, long, default_value = "-")]
    pub output: String,
    /// Random configurations sampled.
    #[arg(long, default_value_t = screwkit_collision::acm::Generate::default().samples)]
    pub samples: usize,
    /// The sampling seed (the same seed, the same file).
    #[arg(long, default_value_t = screwkit_collision::acm::Generate::default().seed)]
    pub seed: u64,
    /// Also disable the pairs that never collided in the samples (flagged "Never").
    #[arg(long)]
    pub never: bool,
}

/// `reach`: build a map (or a shard of one), or `reach merge` shards.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct ReachArgs {
    /// `merge`: join shards into one map.
    #[command(subcommand)]
    pub merge: Option<ReachCommand>,
    /// The URDF or xacro file.
    #[arg(required = true)]
    pub urdf: Option<PathBuf>,
    /// xacro expansion.
    #[command(flatten)]
    pub xacro: XacroArgs,
    /// Base link of the chain (default: the root link).
    #[arg(long)]
    pub base: Option<String>,
    /// Tip link of the chain (default: the only leaf below the base).
    #[arg(long)]
    pub tip: Option<String>,
    /// A tool frame (TCP) fixed to the tip link: x,y,z,roll,pitch,yaw (m, rad).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub tool: Option<List>,
    /// Voxel edge in metres.
    #[arg(long, default_value_t = map().resolution)]
    pub resolution: f64,
    /// Orientations tested per voxel (K).
    #[arg(long, default_value_t = map().orientations)]
    pub orientations: usize,
    /// free: K rotations spread over SO(3); directions: K approach directions on a sphere,
    /// the tool's z axis pointing at the voxel centre (capability maps).
    #[arg(long, value_parser = word::<OrientationMode>(), default_value_t = map().mode)]
    pub mode: OrientationMode,
    /// The box to map, xmin,ymin,zmin,xmax,ymax,zmax in metres (default: the chain's reach).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub bounds: Option<List>,
    /// auto (analytic for non-degenerate 6R arms of revolute joints, else numerical), analytic,
    /// numerical.
    #[arg(long, value_parser = word::<SolverChoice>(), default_value_t = map().solver)]
    pub solver: SolverChoice,
    /// Seed of numerical IK's restarts.
    #[arg(long, default_value_t = map().seed)]
    pub seed: u64,
    /// Numerical IK: restarts per pose.
    #[arg(long, default_value_t = map().restarts)]
    pub restarts: usize,
    /// Numerical IK: iterations per attempt.
    #[arg(long, default_value_t = map().iterations)]
    pub iterations: usize,
    /// Compute part i of N (0-based), a contiguous 1/N of the voxels: `reach merge` joins
    /// the N files into the map the unsharded run writes.
    #[arg(long, value_name = "i/N", value_parser = Shard::parse)]
    pub shard: Option<Shard>,
    /// Also write the SVG slices through the base (xy, xz, yz) to this file (whole maps).
    #[arg(long, value_name = "FILE")]
    pub svg: Option<String>,
    /// Keeping the body clear of contact: only clear solutions count (every analytic posture
    /// is checked; numerical IK steers away from contact), and the summary says how many poses
    /// were reached only in contact.
    #[command(flatten)]
    pub avoid: Avoid,
    /// With --avoid-collisions: how the body's meshes are read, exact (their triangles) or
    /// convex (their hulls, faster); default exact for URDF, convex for MJCF.
    #[arg(long, requires = "avoid_collisions", value_parser = word::<Meshes>())]
    pub meshes: Option<Meshes>,
    /// The map to write: .npz (numpy), or for small maps (≤ 10⁷ poses) .csv (one line per
    /// voxel) or .json (per voxel and per pose).
    #[arg(short, long, required = true)]
    pub output: Option<String>,
}

/// Subcommands of `reach`.
#[derive(Debug, clap::Subcommand)]
pub enum ReachCommand {
    /// Join the shards of a map (any order) into the map the unsharded run writes.
    Merge {
        /// The .npz map to write.
        #[arg(short, long)]
        output: String,
        /// Also write the SVG slices through the base to this file.
        #[arg(long, value_name = "FILE")]
        svg: Option<String>,
        /// The shard files (all N of them).
        #[arg(required = true)]
        shards: Vec<String>,
    },
}

/// How to expand a xacro file: package folders and `xacro:arg` values.
#[derive(Debug, Args, Clone, Default)]
pub struct XacroArgs {
    /// A folder to find ROS packages in for `$(find pkg)` (repeatable; searched before
    /// ROS_PACKAGE_PATH and AMENT_PREFIX_PATH).
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_path: Vec<PathBuf>,
    /// A xacro argument, name:=value (repeatable).
    #[arg(long = "xacro-arg", value_name = "NAME:=VALUE", value_parser = parse_xacro_arg)]
    pub xacro_arg: Vec<(String, String)>,
}

impl XacroArgs {
    /// The library's options.
    pub fn options(&self) -> screwkit_model::XacroOptions {
        screwkit_model::XacroOptions {
            package_paths: self.package_path.clone(),
            args: self.xacro_arg.clone(),
        }
    }
}

fn parse_xacro_arg(s: &str) -> Result<(String, String), String> {
    screwkit_model::XacroOptions::parse_arg(s)
}

/// A URDF file and the chain in it.
#[derive(Debug, Args)]
pub struct ChainArgs {
    /// The URDF or xacro file (- reads it from standard input).
    pub urdf: PathBuf,
    /// xacro expansion.
    #[command(flatten)]
    pub xacro: XacroArgs,
    /// Base link of the chain (default: the root link).
    #[arg(long)]
    pub base: Option<String>,
    /// Tip link of the chain (default: the only leaf below the base).
    #[arg(long)]
    pub tip: Option<String>,
    /// A tool frame (TCP) fixed to the tip link: x,y,z,roll,pitch,yaw (m, rad; URDF rpy).
    /// FK, Jacobians, IK and tables are then of the tool frame.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub tool: Option<List>,
    /// Put a free joint (6 DoF) between the world and the root link: q starts with the base's
    /// x,y,z and quaternion qx,qy,qz,qw, the Jacobians with the base's six columns (its
    /// twist (ω, v) in its own frame). Whole-tree commands only (fk, jacobian, draw, view of the
    /// whole tree).
    #[arg(long)]
    pub floating_base: bool,
    /// Which of the file's shapes are read: collision, visual, both or none.
    #[arg(long, value_parser = word::<GeometryRoles>(), default_value_t = GeometryRoles::default())]
    pub geometry: GeometryRoles,
    /// How the body's meshes are read: exact (their triangles) or convex (their hulls);
    /// default exact for URDF, convex for MJCF (MuJoCo's rule).
    #[arg(long, value_parser = word::<Meshes>())]
    pub meshes: Option<Meshes>,
}

impl ChainArgs {
    /// The floor's load options.
    pub fn options(&self) -> LoadOptions {
        LoadOptions {
            xacro: self.xacro.options(),
            base: self.base.clone(),
            tip: self.tip.clone(),
            tool: self.tool.as_ref().map(|t| t.0.clone()),
            floating_base: self.floating_base,
            geometry: self.geometry,
            meshes: self.meshes,
        }
    }
}

/// A comma-separated list of numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct List(pub Vec<f64>);

/// Parses `1,2.5,-3` (spaces allowed); every entry must be a finite number. An empty string
/// is the empty list (a chain with no joints).
pub fn parse_list(s: &str) -> Result<List, String> {
    if s.trim().is_empty() {
        return Ok(List(Vec::new()));
    }
    let v: Result<Vec<f64>, String> = s
        .split(',')
        .map(|t| {
            let t = t.trim();
            match t.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(format!("\"{t}\" is not a finite number")),
                Err(_) => Err(format!("\"{t}\" is not a number")),
            }
        })
        .collect();
    v.map(List)
}

/// `info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The URDF or xacro file (- reads it from standard input).
    pub urdf: PathBuf,
    /// xacro expansion.
    #[command(flatten)]
    pub xacro: XacroArgs,
    /// List every chain from the root to a leaf with its DoF (end effectors first,
    /// sensor-like leaves last) instead of the full description.
    #[arg(long)]
    pub chains: bool,
    /// Describe the chain from this link (default: the root) — its DoF and IK family.
    #[arg(long, conflicts_with = "chains")]
    pub base: Option<String>,
    /// Describe the chain to this link (default: the only leaf below the base).
    #[arg(long, conflicts_with = "chains")]
    pub tip: Option<String>,
}

/// `table`.
#[derive(Debug, Args)]
pub struct TableArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// Which axes: space (S_i), body (B_i) or both.
    #[arg(long, value_parser = word::<TableFrames>(), default_value_t = TableFrames::Both)]
    pub frame: TableFrames,
}

/// Joint values, one configuration or a batch of them (`fk`, `jacobian`).
#[derive(Debug, Args)]
pub struct Configurations {
    /// Joint values q1,q2,... (rad or m), one per variable.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true, required_unless_present = "input")]
    pub q: Option<List>,
    /// Batch mode: JSON lines {"q": [...]} from FILE or - (stdin).
    #[arg(long, conflicts_with = "q")]
    pub input: Option<String>,
    /// With --input FILE.npy (N × dof float64): write the results to this .npy file instead
    /// of JSON lines (binary, streamed, for large batches).
    #[arg(long, requires = "input")]
    pub output: Option<String>,
}

/// `fk`.
#[derive(Debug, Args)]
pub struct FkArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// The configurations.
    #[command(flatten)]
    pub at: Configurations,
    /// Give the pose of every link on the chain (on a file with several leaves and no tip:
    /// every link and frame of the tree).
    #[arg(long)]
    pub all_links: bool,
    /// The frames (links) to give, comma-separated, in the whole tree (q: the tree's
    /// variables in the file's joint order; `info --format json` lists them). Without it, a
    /// file with several leaves and no tip gives every leaf.
    #[arg(long, value_delimiter = ',', value_name = "FRAME,…")]
    pub frames: Vec<String>,
}

/// `jacobian`.
#[derive(Debug, Args)]
pub struct JacobianArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// The configurations.
    #[command(flatten)]
    pub at: Configurations,
    /// Which Jacobian: space (J_s: twist of the body at the base origin, base axes), body (J_b:
    /// at the tip, tip axes) or world-aligned (J_wa: angular velocity and tip-point velocity,
    /// base axes; Pinocchio's LOCAL_WORLD_ALIGNED, Robotics Toolbox's jacob0).
    #[arg(long, value_parser = word::<JacobianFrame>(), default_value_t = JacobianFrame::Space)]
    pub frame: JacobianFrame,
    /// Add singular values, rank, manipulability, condition number and a verdict.
    #[arg(long)]
    pub analyze: bool,
    /// The frame (link) whose Jacobian to give, in the whole tree: one column per variable of
    /// the tree (zeros for joints not on its path).
    #[arg(long, value_name = "FRAME")]
    pub of: Option<String>,
    /// Give the motion of --of relative to this frame (its pose T_B⁻¹ T_A; space: in this
    /// frame, body: in --of's frame, world-aligned: this frame's axes at --of's origin).
    #[arg(long, value_name = "FRAME", requires = "of")]
    pub relative_to: Option<String>,
}

impl IkArgs {
    /// The floor's IK settings from the flags.
    pub fn settings(&self) -> IkSettings {
        IkSettings {
            method: self.method,
            damping: self.damping,
            tol_rot: self.tol_rot,
            tol_pos: self.tol_pos,
            max_iterations: self.max_iter.unwrap_or(ik().max_iterations),
            max_restarts: self.restarts.unwrap_or(ik().max_restarts),
            timeout_ms: self.timeout_ms,
            seed: self.random_seed,
            position_only: self.position_only,
            weights: self
                .weights
                .as_ref()
                .map_or_else(|| ik().weights, |w| w.0.clone()),
        }
    }
}

/// `ik`.
#[derive(Debug, Args)]
pub struct IkArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// Whole-body IK on the whole tree: a JSON file (or -) of tasks — frames to poses, relative
    /// frames, axes, the centre of mass, a posture, damping (README, "Whole-body IK") — solved
    /// together to convergence within the joint limits; q is the tree's (the floating base's
    /// seven values first with --floating-base). With --input: JSON lines {"tasks": [a change
    /// of each task's fields, or null], "seed": [...]}, one answer per line.
    #[arg(long, value_name = "FILE", conflicts_with_all = [
        "target_xyz_quat", "target_xyz_rpy", "target_matrix", "all", "output", "target_frame",
        "position_only", "weights", "damping", "timeout_ms", "method", "tol_rot", "tol_pos",
    ])]
    pub tasks: Option<PathBuf>,
    /// Target as x,y,z,qx,qy,qz,qw.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub target_xyz_quat: Option<List>,
    /// Target as x,y,z,roll,pitch,yaw (URDF fixed-axis rpy).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub target_xyz_rpy: Option<List>,
    /// Target as 16 numbers of the 4x4 matrix, row-major.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub target_matrix: Option<List>,
    /// Initial guess (default: the midpoint of the limits).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub seed: Option<List>,
    /// Method: lm (Levenberg–Marquardt, adaptive damping), dls (damped least squares, fixed
    /// damping), nr (Newton–Raphson with the SVD pseudo-inverse).
    #[arg(long, value_parser = word::<Method>(), default_value_t = ik().method)]
    pub method: Method,
    /// LM's damping floor or DLS's damping λ (default: the library's).
    #[arg(long)]
    pub damping: Option<f64>,
    /// Rotation tolerance (rad).
    #[arg(long, default_value_t = ik().tol_rot)]
    pub tol_rot: f64,
    /// Position tolerance (m).
    #[arg(long, default_value_t = ik().tol_pos)]
    pub tol_pos: f64,
    /// Iteration budget: over all attempts (default: the library's, 2000); with --tasks, of
    /// each descent (default 100).
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// Random restarts allowed (default: the library's, 200; with --tasks, 50).
    #[arg(long)]
    pub restarts: Option<usize>,
    /// Wall-time budget per target in ms (0, the default: none, so answers do not depend on
    /// the machine's load; the budget is --max-iter and --restarts).
    #[arg(long, default_value_t = ik().timeout_ms)]
    pub timeout_ms: f64,
    /// Solve for the position only.
    #[arg(long)]
    pub position_only: bool,
    /// Weights of the six twist-error components ω1,ω2,ω3,v1,v2,v3 (0 masks one out).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub weights: Option<List>,
    /// Seed of the random restarts.
    #[arg(long, default_value_t = ik().seed)]
    pub random_seed: u64,
    /// The frame the target is given in: any link rigidly attached to the base (e.g. `world`;
    /// default: the base).
    #[arg(long, value_name = "LINK")]
    pub target_frame: Option<String>,
    /// Batch mode: JSON lines {"target": [[4x4]], "seed": [...]} from FILE or - (stdin), or a
    /// .npy of N × 4 × 4 float64 targets (with --output).
    #[arg(long)]
    pub input: Option<String>,
    /// With --input FILE.npy: write the solutions (N × dof) to this .npy file and the status
    /// (N × 4: converged 0/1, iterations, rotation error, position error) beside it as
    /// NAME.status.npy.
    #[arg(long, requires = "input")]
    pub output: Option<String>,
    /// Trajectory mode for --input: one line after the other, each seeded with the previous
    /// line's answer (when it converged and the line gives no seed), so a smooth path is
    /// followed without branch flips. One thread.
    #[arg(long, requires = "input")]
    pub sequential: bool,
    /// Every solution, from the analytic solver (any 6R arm of revolute joints: the special
    /// families in closed form, the others by algebraic elimination; 7R arms with one joint
    /// locked or at an arm angle), nearest to --seed first. With --input: one JSON line per
    /// target.
    #[arg(long, conflicts_with_all = ["output", "sequential"])]
    pub all: bool,
    /// With --all on a 7R arm: the joint to lock, by name or by its index in q (counted from
    /// 0), and its value (JOINT=VALUE; default value: the seed's; default joint: among those
    /// leaving the most specialised closed form, the one reaching the most poses); or
    /// arm_angle[=ψ] for an arm with a spherical shoulder and wrist (the iiwa): the solutions
    /// at arm angle ψ (default: the seed's; ψ = 0 puts the elbow in the plane of axis 1 and
    /// the shoulder–wrist line, on axis 1's side).
    #[arg(long, requires = "all", value_name = "JOINT[=VALUE]", value_parser = Lock::parse)]
    pub lock: Option<Lock>,
    /// With --all on a 7R arm: solve with the locked joint (or the arm angle) at N values
    /// evenly spaced over its limits ([−π, π) for the arm angle) and list the solutions of
    /// all of them.
    #[arg(long, requires = "all", value_name = "N")]
    pub sweep: Option<usize>,
    /// With --all: which 2π representatives of each posture to list (a joint with limits
    /// wider than 2π reaches a posture at several angles): nearest (the seed's, one row per
    /// posture), all (every one inside the limits), none (one row per posture, angles in
    /// (−π, π] where the limits allow).
    #[arg(long, requires = "all", value_parser = word::<RepresentativesChoice>(), default_value_t = RepresentativesChoice::Nearest)]
    pub representatives: RepresentativesChoice,
    /// With --all: what to do with the solutions whose body collides (itself, or the
    /// --obstacles): ignore (the default), flag (JSON "collides" per solution), filter (drop
    /// them).
    #[arg(long, requires = "all", value_parser = word::<Collisions>(), default_value_t = Collisions::default())]
    pub collisions: Collisions,
    /// Numerical IK (not --all): only answers whose body is clear of contact (itself, and
    /// the --obstacles) by --margin; steps are steered away from close pairs. The status says
    /// "in collision" when the budget ends with only colliding answers. With --tasks: every
    /// step keeps every checked pair --margin apart (collision avoidance, one velocity-damper
    /// row per pair within 5 cm).
    #[arg(long, conflicts_with = "all")]
    pub avoid_collisions: bool,
    /// With --avoid-collisions: the least distance (m) kept between every checked pair.
    #[arg(long, requires = "avoid_collisions", default_value_t = screwkit_service::body::DEFAULT_MARGIN)]
    pub margin: f64,
    /// With --collisions or --avoid-collisions: an SRDF whose disable_collisions pairs are
    /// not checked.
    #[arg(long)]
    pub srdf: Option<PathBuf>,
    /// With --collisions or --avoid-collisions: a scene file (JSON) of obstacles (as `collide
    /// --obstacles`).
    #[arg(long)]
    pub obstacles: Option<PathBuf>,
}

/// `exp`.
#[derive(Debug, Args)]
pub struct ExpArgs {
    /// The twist (ω1,ω2,ω3,v1,v2,v3), or a unit screw axis with --theta.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub twist: List,
    /// Distance θ along the screw (default 1).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub theta: f64,
}

/// `log`.
#[derive(Debug, Args)]
pub struct LogArgs {
    /// 16 numbers of the 4x4 matrix, row-major (rounded input is accepted to 1e-3 and
    /// re-orthonormalised).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub matrix: List,
}

/// `bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// Number of IK queries (1 to 10,000,000).
    #[arg(long, default_value_t = 10_000, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=10_000_000))]
    pub n: usize,
    /// Seed of the random targets.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// IK method.
    #[arg(long, value_parser = word::<Method>(), default_value_t = ik().method)]
    pub method: Method,
}

/// `draw`.
#[derive(Debug, Args)]
pub struct DrawArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// Joint values q1,q2,... (default: all zeros, the home configuration).
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub q: Option<List>,
    /// The view: iso, front (from +x), side (from -y), top (from +z), or all four on one sheet.
    #[arg(long, value_parser = word::<Views>(), default_value_t = Views::One(View::Iso))]
    pub view: Views,
    /// The names written, each placed off the others (or left out when there is no room):
    /// none, leaves (a chain's tip, a tree's leaves) or all (every link).
    #[arg(long, value_parser = word::<Labels>(), default_value_t = Labels::Leaves)]
    pub labels: Labels,
    /// The screw axes drawn: all, none, or joints by name or number (J1,J2 or 1,2). Default:
    /// all for a chain, or for a tree of at most 12 joints; none for a larger tree.
    #[arg(long, value_parser = |s: &str| s.parse::<Axes>())]
    pub axes: Option<Axes>,
    /// The SVG file to write (- for standard output).
    #[arg(short, long)]
    pub output: String,
}

/// `view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The chain.
    #[command(flatten)]
    pub chain: ChainArgs,
    /// Joint values q1,q2,... shown first (default: all zeros); a `#q=...` in the page's URL
    /// overrides them.
    #[arg(long, value_parser = parse_list, allow_hyphen_values = true)]
    pub q: Option<List>,
    /// A motion to play back: configurations, one per frame, as .npy (frames × values) or JSON
    /// (an array of rows, or lines each a row or {"q": row}).
    #[arg(long, value_name = "FILE")]
    pub motion: Option<PathBuf>,
    /// With --motion: frames per second.
    #[arg(long, requires = "motion", default_value_t = screwkit_draw::html::DEFAULT_FPS)]
    pub fps: f64,
    /// A scene file (JSON) of obstacles to draw in the world (as `collide --obstacles`).
    #[arg(long)]
    pub obstacles: Option<PathBuf>,
    /// Tint the links (and obstacles) in collision red, at the configuration first shown and
    /// at each motion frame (the body's <collision> shapes, the pairs an --srdf leaves).
    #[arg(long)]
    pub show_collisions: bool,
    /// With the collisions, draw each pair closer than 5 cm as its minimum-distance segment,
    /// with the distances listed in the panel.
    #[arg(long)]
    pub show_distances: bool,
    /// An SRDF whose disabled pairs the collisions leave out (implies --show-collisions).
    #[arg(long, value_name = "FILE")]
    pub srdf: Option<PathBuf>,
    /// The HTML file to write (- for standard output).
    #[arg(short, long)]
    pub output: String,
}

/// `urdf`.
#[derive(Debug, Args)]
pub struct UrdfArgs {
    /// The robot file (URDF, xacro or MJCF; - reads it from standard input).
    pub file: PathBuf,
    /// xacro expansion.
    #[command(flatten)]
    pub xacro: XacroArgs,
    /// The URDF file to write (- for standard output).
    #[arg(short, long)]
    pub output: String,
}

/// `xacro`.
#[derive(Debug, Args)]
pub struct XacroFileArgs {
    /// The xacro file (- reads it from standard input).
    pub file: PathBuf,
    /// xacro expansion.
    #[command(flatten)]
    pub xacro: XacroArgs,
}
