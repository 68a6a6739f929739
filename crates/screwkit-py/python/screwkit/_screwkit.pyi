"""Type stubs of screwkit's native module (pyo3). Arrays are float64 unless said otherwise."""

import os
from collections.abc import Mapping, Sequence
from typing import Any, Literal, TypeAlias, final, overload

import numpy as np
import numpy.typing as npt

__version__: str
__all__ = [
    "Robot",
    "Page",
    "IkResult",
    "IkBatchResult",
    "Analysis",
    "BatchError",
    "FrameTask",
    "RelativeFrameTask",
    "AxisTask",
    "ComTask",
    "PostureTask",
    "DampingTask",
    "TaskSet",
    "TasksResult",
    "Distances",
    "Box",
    "Sphere",
    "Capsule",
    "Cylinder",
    "Mesh",
    "CollisionAvoidance",
    "exp",
    "log",
    "adjoint",
    "ad",
    "axis_angle3",
    "axis_angle6",
    "distance_to_se3",
    "distance_to_so3",
    "exp3",
    "exp6",
    "hat",
    "is_se3",
    "is_so3",
    "log3",
    "log6",
    "project_to_se3",
    "project_to_so3",
    "rot_inv",
    "screw_to_axis",
    "mr_end_effector_forces",
    "mr_forward_dynamics",
    "mr_gravity_forces",
    "mr_inverse_dynamics",
    "mr_inverse_dynamics_trajectory",
    "mr_mass_matrix",
    "mr_vel_quadratic_forces",
    "TimedPath",
    "CartesianPath",
    "time_parameterize",
    "tr_cartesian_trajectory",
    "tr_cubic_time_scaling",
    "tr_joint_trajectory",
    "tr_quintic_time_scaling",
    "tr_screw_trajectory",
    "trans_inv",
    "vee",
    "row_seed",
    "set_num_threads",
    "num_threads",
    "kernel_path",
    "xacro",
    "__version__",
]

# The option words (the floor's `screwkit_service::words`; the suite checks these against
# `_words()`).
_Frame: TypeAlias = Literal["space", "body"]
_JacobianFrame: TypeAlias = Literal["space", "body", "world-aligned", "world_aligned"]
_TableFormat: TypeAlias = Literal["markdown", "md", "text", "csv", "json"]
_TableFrames: TypeAlias = Literal["space", "body", "both"]
_Views: TypeAlias = Literal["iso", "front", "side", "top", "all"]
_Labels: TypeAlias = Literal["none", "leaves", "all"]
_Inertias: TypeAlias = Literal["check", "as-given", "as_given", "balance"]
_Interpolation: TypeAlias = Literal["screw", "line"]
_Method: TypeAlias = Literal["lm", "dls", "nr"]
_Geometry: TypeAlias = Literal["collision", "visual", "both", "none"]
_Meshes: TypeAlias = Literal["exact", "convex"]
# The overloads split it ("flag" returns flags); test_floor holds it to the floor's words.
_Collisions: TypeAlias = Literal["ignore", "flag", "filter"]  # noqa: PYI047
_Representatives: TypeAlias = Literal["nearest", "all", "none"]
_F64: TypeAlias = npt.NDArray[np.float64]
_Bool: TypeAlias = npt.NDArray[np.bool_]
_ArrayLike: TypeAlias = npt.ArrayLike
_Weights: TypeAlias = float | Sequence[float]
# Single versus batch in the types: one matrix (a pose, a rotation) as nested lists, or a stack of
# them, picks its overload; a numpy array takes the last one, whose answer is either. (numpy's
# shape types cannot tell them apart: mypy matches an (N, 4, 4) array to a (4, 4) overload.)
_Mat: TypeAlias = Sequence[Sequence[float]]
_Mats: TypeAlias = Sequence[Sequence[Sequence[float]]]

@final
class FrameTask:
    """A frame (link or added frame) to a world pose (4, 4): error log(T_F^-1 T*) in the frame."""

    def __new__(
        cls,
        frame: str,
        target: _ArrayLike,
        *,
        gain: float = 1.0,
        weight: float = 1.0,
        position_weight: _Weights | None = None,
        orientation_weight: _Weights | None = None,
        tol_pos: float = 1e-9,
        tol_rot: float = 1e-9,
    ) -> FrameTask: ...

@final
class RelativeFrameTask:
    """Frame `frame`'s pose in frame `relative_to` (T_B^-1 T_A) to `target` (4, 4)."""

    def __new__(
        cls,
        frame: str,
        relative_to: str,
        target: _ArrayLike,
        *,
        gain: float = 1.0,
        weight: float = 1.0,
        position_weight: _Weights | None = None,
        orientation_weight: _Weights | None = None,
        tol_pos: float = 1e-9,
        tol_rot: float = 1e-9,
    ) -> RelativeFrameTask: ...

@final
class AxisTask:
    """A frame's axis along a world direction, its origin at `point`; free about the axis."""

    def __new__(
        cls,
        frame: str,
        *,
        axis: _ArrayLike,
        direction: _ArrayLike,
        point: _ArrayLike | None = None,
        gain: float = 1.0,
        weight: float = 1.0,
        position_weight: _Weights | None = None,
        orientation_weight: float = 1.0,
        tol_pos: float = 1e-9,
        tol_rot: float = 1e-9,
    ) -> AxisTask: ...

@final
class ComTask:
    """The centre of mass to a world point (3,)."""

    def __new__(
        cls,
        target: _ArrayLike,
        *,
        gain: float = 1.0,
        weight: float = 1.0,
        position_weight: _Weights | None = None,
        tol_pos: float = 1e-9,
    ) -> ComTask: ...

@final
class PostureTask:
    """The joints towards q_ref (nq,): a regulariser."""

    def __new__(
        cls, q_ref: _ArrayLike, *, weight: float = 1.0, gain: float = 1.0
    ) -> PostureTask: ...

@final
class DampingTask:
    """Small steps: the squared step weighted by weight^2."""

    def __new__(cls, weight: float = 1e-3) -> DampingTask: ...

_Task: TypeAlias = FrameTask | RelativeFrameTask | AxisTask | ComTask | PostureTask | DampingTask

@final
class TaskSet:
    """Tasks prepared for one robot (`Robot.task_set`): frames found and checked once; targets
    changed in place, so that `ik_step(q, task_set, dt)` looks no name up."""

    def set_target(self, index: int, target: _ArrayLike, *, direction: bool = False) -> None: ...
    def __len__(self) -> int: ...

@final
class TasksResult:
    """The outcome of Robot.ik_tasks."""

    @property
    def q(self) -> _F64: ...
    @property
    def converged(self) -> bool: ...
    @property
    def iterations(self) -> int: ...
    @property
    def stop(
        self,
    ) -> Literal["converged", "iterations", "stalled", "conflicting", "interrupted"]: ...
    @property
    def task_errors(self) -> _F64: ...
    @property
    def task_converged(self) -> list[bool]: ...

class BatchError(ValueError):
    """Some rows of a batch had bad input; every other row was computed.

    `result` is the whole result (bad rows NaN, or not converged for IK), `rows` the bad rows
    (0-based) and `messages` what was wrong with each.
    """

    result: Any
    rows: list[int]
    messages: list[str]

@final
class IkResult:
    """The outcome of `Robot.ik` for one target (4, 4)."""

    @property
    def q(self) -> _F64: ...
    @property
    def converged(self) -> bool: ...
    @property
    def iterations(self) -> int: ...
    @property
    def restarts(self) -> int: ...
    @property
    def error_rot(self) -> float: ...
    @property
    def error_pos(self) -> float: ...
    @property
    def stop(self) -> str: ...

@final
class IkBatchResult:
    """The outcome of `Robot.ik` for N targets (N, 4, 4): one entry per target in each attribute."""

    @property
    def q(self) -> _F64: ...
    @property
    def converged(self) -> npt.NDArray[np.bool_]: ...
    @property
    def iterations(self) -> npt.NDArray[np.int64]: ...
    @property
    def restarts(self) -> npt.NDArray[np.int64]: ...
    @property
    def error_rot(self) -> _F64: ...
    @property
    def error_pos(self) -> _F64: ...
    @property
    def stop(self) -> list[str]: ...
    def __len__(self) -> int: ...

@final
class Analysis:
    """The SVD of a Jacobian and what it means (`Robot.analyze`)."""

    @property
    def frame(self) -> str: ...
    @property
    def jacobian(self) -> _F64: ...
    @property
    def singular_values(self) -> _F64: ...
    @property
    def rank(self) -> int: ...
    @property
    def rank_tolerance(self) -> float: ...
    @property
    def manipulability(self) -> float: ...
    @property
    def condition_number(self) -> float: ...
    @property
    def determinant(self) -> float | None: ...
    @property
    def lost_directions(self) -> _F64: ...
    @property
    def weakest_direction(self) -> _F64: ...
    @property
    def angular_axes(self) -> _F64: ...
    @property
    def angular_lengths(self) -> _F64: ...
    @property
    def linear_axes(self) -> _F64: ...
    @property
    def linear_lengths(self) -> _F64: ...
    @property
    def verdict(self) -> str: ...
    @property
    def position_singular_values(self) -> _F64: ...
    @property
    def position_rank(self) -> int: ...
    @property
    def position_manipulability(self) -> float: ...
    @property
    def position_condition_number(self) -> float: ...

@final
class Box:
    """A box of full side lengths `size` (x, y, z; m), centred on its pose."""
    def __new__(cls, size: tuple[float, float, float] | Sequence[float]) -> Box: ...
    @property
    def size(self) -> list[float]: ...

@final
class Sphere:
    """A sphere of `radius` (m)."""
    def __new__(cls, radius: float) -> Sphere: ...
    @property
    def radius(self) -> float: ...

@final
class Capsule:
    """A capsule along z: a cylinder of `length` with half-spheres of `radius`."""
    def __new__(cls, radius: float, length: float) -> Capsule: ...
    @property
    def radius(self) -> float: ...
    @property
    def length(self) -> float: ...

@final
class Cylinder:
    """A cylinder along z, centred."""
    def __new__(cls, radius: float, length: float) -> Cylinder: ...
    @property
    def radius(self) -> float: ...
    @property
    def length(self) -> float: ...

@final
class Mesh:
    """A triangle mesh file (STL, OBJ, COLLADA), its vertices multiplied by `scale`."""
    def __new__(
        cls, path: str | os.PathLike[str], scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ) -> Mesh: ...
    @property
    def path(self) -> str: ...
    @property
    def scale(self) -> list[float]: ...

_Shape: TypeAlias = Box | Sphere | Capsule | Cylinder | Mesh

@final
class CollisionAvoidance:
    """Collision avoidance for whole-body IK (`limits=[CollisionAvoidance(...)]`): one row
    per close pair, n·(J_b − J_a) v ≥ −gain (d − margin) / dt."""
    def __new__(
        cls,
        pairs: Literal["all"] | Sequence[tuple[str, str]] | None = None,
        margin: float = 0.005,
        detection_distance: float = 0.05,
        gain: float = 0.85,
    ) -> CollisionAvoidance: ...
    @property
    def pairs(self) -> list[tuple[str, str]] | None: ...
    @property
    def margin(self) -> float: ...
    @property
    def detection_distance(self) -> float: ...
    @property
    def gain(self) -> float: ...

@final
class Distances:
    """Every checked pair's signed distance at one configuration."""
    @property
    def pairs(self) -> list[tuple[str, str]]: ...
    @property
    def distance(self) -> _F64: ...
    @property
    def points(self) -> _F64: ...
    @property
    def normal(self) -> _F64: ...
    @property
    def jacobian(self) -> _F64 | None: ...
    def __len__(self) -> int: ...

@final
class Page:
    """An interactive page (`Robot.show`): Jupyter displays it inline; `html` holds it."""

    @property
    def html(self) -> str: ...
    @property
    def height(self) -> int: ...
    def _repr_html_(self) -> str: ...
    def save(self, path: str | os.PathLike[str]) -> None: ...

@final
class Robot:
    """A whole robot (URDF, xacro, MJCF or a screw table), ready for kinematics: its chain
    base -> tip when it has one, and every frame of its tree (`link=...`).

    Conventions: twists and screw axes (omega, v); metres, radians; poses row-major (4, 4)
    float64; the space frame is the base link, the body frame the frame asked for (the tip by
    default). q of shape (dof,)
    gives one result, q of shape (N, dof) N results computed on all cores, GIL released.
    """

    @classmethod
    def from_urdf(
        cls,
        path: str | os.PathLike[str],
        base: str | None = None,
        tip: str | None = None,
        *,
        package_paths: Sequence[str | os.PathLike[str]] | None = None,
        xacro_args: Mapping[str, str] | None = None,
        tool: Sequence[float] | None = None,
        floating_base: bool = False,
        geometry: _Geometry = "both",
        meshes: _Meshes | None = None,
    ) -> Robot: ...
    @classmethod
    def from_file(
        cls,
        path: str | os.PathLike[str],
        base: str | None = None,
        tip: str | None = None,
        *,
        package_paths: Sequence[str | os.PathLike[str]] | None = None,
        xacro_args: Mapping[str, str] | None = None,
        tool: Sequence[float] | None = None,
        floating_base: bool = False,
        geometry: _Geometry = "both",
        meshes: _Meshes | None = None,
    ) -> Robot: ...
    @classmethod
    def from_screws(
        cls,
        m: _ArrayLike,
        s: _ArrayLike,
        frame: _Frame = "space",
        limits: _ArrayLike | None = None,
        names: Sequence[str] | None = None,
        *,
        tool: Sequence[float] | None = None,
        floating_base: bool = False,
    ) -> Robot:
        """A robot from its home pose M (4, 4) and screw axes S (n, 6), rows (omega, v), in the
        space or body frame (Modern Robotics' Slist/Blist are columns: pass Slist.T); helical
        rows (pitch omega . v above 2e-6 * max(1, |v|), what six printed decimals leave) and
        prismatic rows (omega = 0) included."""
    @classmethod
    def from_string(
        cls,
        xml: str,
        base: str | None = None,
        tip: str | None = None,
        source: str = "<string>",
        *,
        tool: Sequence[float] | None = None,
        floating_base: bool = False,
    ) -> Robot: ...
    @classmethod
    def _restore(
        cls,
        xml: str,
        base: str | None,
        tip: str | None,
        source: str,
        tool: Sequence[float] | None,
        floating_base: bool,
        frames: Sequence[tuple[str, str, Sequence[float]]],
        body: tuple[str | os.PathLike[str], Sequence[str | os.PathLike[str]], str, str | None],
        state: tuple[
            Sequence[tuple[str, str]],
            Sequence[
                tuple[
                    str, tuple[str, Sequence[float], str | os.PathLike[str] | None], Sequence[float]
                ]
            ],
        ],
    ) -> Robot: ...
    def __reduce__(self) -> Any: ...
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def base(self) -> str: ...
    @property
    def tip(self) -> str: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def axis_names(self) -> list[str]: ...
    @property
    def link_names(self) -> list[str]: ...
    @property
    def lower(self) -> _F64: ...
    @property
    def upper(self) -> _F64: ...
    @property
    def midpoint(self) -> _F64: ...
    @property
    def home(self) -> _F64: ...
    def screw_axes(self, frame: _Frame = "space") -> _F64: ...
    def table(self, fmt: _TableFormat = "markdown", frame: _TableFrames = "both") -> str: ...
    def fk(self, q: _ArrayLike, link: str | None = None, *, relative_to: str | None = None) -> _F64:
        """q (dof,) -> the pose (4, 4); q (N, dof) -> N poses (N, 4, 4).

        With ``link``: that frame of the whole tree, q of shape (nq,) or (N, nq)."""
    def fk_all_links(self, q: _ArrayLike) -> _F64:
        """q (dof,) -> (links, 4, 4); q (N, dof) -> (N, links, 4, 4)."""
    def fk_all_frames(self, q: _ArrayLike) -> _F64:
        """The whole tree: q (nq,) -> (frames, 4, 4); q (N, nq) -> (N, frames, 4, 4)."""
    def jacobian(
        self,
        q: _ArrayLike,
        frame: _JacobianFrame = "space",
        link: str | None = None,
        *,
        relative_to: str | None = None,
    ) -> _F64:
        """q (dof,) -> (6, dof); q (N, dof) -> (N, 6, dof); with ``link``: (6, nv)."""
    @property
    def variable_names(self) -> list[str]: ...
    @property
    def q_names(self) -> list[str]: ...
    @property
    def v_names(self) -> list[str]: ...
    @property
    def nq(self) -> int: ...
    @property
    def nv(self) -> int: ...
    @property
    def floating_base(self) -> bool: ...
    @property
    def frame_names(self) -> list[str]: ...
    def add_frame(self, name: str, parent_link: str, pose: _ArrayLike) -> None: ...
    def to_urdf(self, path: str | os.PathLike[str] | None = None) -> str: ...
    def from_mujoco_qpos(self, qpos: _ArrayLike) -> _F64: ...
    def to_mujoco_qpos(self, q: _ArrayLike, qpos: _ArrayLike | None = None) -> _F64: ...
    def integrate(self, q: _ArrayLike, v: _ArrayLike, dt: float) -> _F64: ...
    def difference(self, q0: _ArrayLike, q1: _ArrayLike) -> _F64: ...
    def neutral(self) -> _F64: ...
    def random_configuration(self, seed: int = 0) -> _F64: ...
    def com(self, q: _ArrayLike) -> _F64: ...
    def com_jacobian(self, q: _ArrayLike) -> _F64: ...
    def info(self) -> dict[str, Any]: ...
    def in_collision(self, q: _ArrayLike) -> Any: ...
    def collisions(self, q: _ArrayLike) -> Any: ...
    def distances(self, q: _ArrayLike, *, jacobians: bool = False) -> Any: ...
    def min_distance(self, q: _ArrayLike) -> Any: ...
    @property
    def collision_pairs(self) -> list[tuple[str, str]]: ...
    def srdf(self, path: str | os.PathLike[str]) -> None: ...
    def write_srdf(
        self,
        path: str | os.PathLike[str] | None = None,
        *,
        samples: int = 10000,
        seed: int = 0,
        never: bool = False,
    ) -> str: ...
    def add_obstacle(self, name: str, shape: _Shape, pose: _ArrayLike) -> None: ...
    def add_obstacles(self, path: str | os.PathLike[str]) -> list[str]: ...
    def remove_obstacle(self, name: str) -> bool: ...
    @property
    def obstacles(self) -> list[str]: ...
    @property
    def total_mass(self) -> float: ...
    @property
    def velocity_limits(self) -> _F64: ...
    def time_parameterize(
        self,
        path: _ArrayLike,
        acc_limits: _ArrayLike,
        vel_limits: _ArrayLike | None = None,
        *,
        grid: int | None = None,
        check: float = 0.001,
    ) -> TimedPath:
        """`screwkit.time_parameterize` with the file's velocity limits by default."""
    def cartesian_path(
        self,
        targets: _ArrayLike,
        seed: _ArrayLike | None = None,
        *,
        interpolation: _Interpolation = "screw",
        max_step: float = 0.005,
        max_joint_step: float = 0.1,
        max_deviation: float = 0.001,
        min_sigma: float = 0.005,
        lock: str | int | None = None,
        avoid_collisions: bool = False,
        margin: float = 0.0,
    ) -> CartesianPath:
        """The tool along a screw (or line) through `targets`, the joints on one IK branch."""
    def cartesian_paths(
        self,
        targets: _ArrayLike,
        seed: _ArrayLike | None = None,
        *,
        interpolation: _Interpolation = "screw",
        max_step: float = 0.005,
        max_joint_step: float = 0.1,
        max_deviation: float = 0.001,
        min_sigma: float = 0.005,
        lock: str | int | None = None,
        avoid_collisions: bool = False,
        margin: float = 0.0,
    ) -> list[CartesianPath]:
        """Many paths on all cores: (N, K, 4, 4) targets, one seed or (N, dof)."""
    def plot_joints(
        self,
        q: _ArrayLike,
        x: _ArrayLike | None = None,
        path: str | os.PathLike[str] | None = None,
        *,
        x_label: str | None = None,
        title: str | None = None,
    ) -> str:
        """An SVG plot of a joint path (K, dof), one panel per joint against x, limits dashed."""
    def set_dynamics_options(
        self, *, inertias: _Inertias = "check", armature: bool = False, damping: bool = False
    ) -> None:
        """How dynamics takes the file: the inertials' rule, joint armature and damping."""
    def inverse_dynamics(
        self,
        q: _ArrayLike,
        v: _ArrayLike,
        a: _ArrayLike,
        f_ext: Mapping[str, _ArrayLike] | None = None,
    ) -> _F64:
        """τ = ID(q, v, a) of the whole tree (nv), by recursive Newton–Euler; `f_ext`: wrenches
        (m, f) on the robot at frames, each in its frame's coordinates."""
    def static_torques(
        self, q: _ArrayLike, wrenches: Mapping[str, _ArrayLike], *, gravity: bool = False
    ) -> _F64:
        """τ = Σ J_fᵀ F_f for the wrenches the robot exerts at frames (+ g(q) with gravity)."""
    def gravity(self, q: _ArrayLike) -> _F64:
        """The gravity forces g(q) (nv)."""
    def nonlinear_effects(self, q: _ArrayLike, v: _ArrayLike) -> _F64:
        """h(q, v) = C(q, v) v + g(q) (nv)."""
    def mass_matrix(self, q: _ArrayLike) -> _F64:
        """M(q) (nv, nv), by the composite-rigid-body algorithm."""
    def forward_dynamics(
        self,
        q: _ArrayLike,
        v: _ArrayLike,
        tau: _ArrayLike,
        f_ext: Mapping[str, _ArrayLike] | None = None,
    ) -> _F64:
        """a = M(q)⁻¹ (τ − h(q, v)) (nv); `f_ext`: wrenches (m, f) on the robot at frames."""
    def centroidal_map(self, q: _ArrayLike) -> _F64:
        """A_G(q) (6, nv): momentum about the CoM per unit speed, (angular, linear) rows."""
    def centroidal_momentum(self, q: _ArrayLike, v: _ArrayLike) -> _F64:
        """h_G = A_G(q) v (6,): (k_G, p) about the centre of mass, in the world's axes."""
    def kinetic_energy(self, q: _ArrayLike, v: _ArrayLike) -> Any:
        """½ vᵀ M v (J): a float, or (N,) for a batch."""
    def potential_energy(self, q: _ArrayLike) -> Any:
        """−Σ m gᵀ c (J): a float, or (N,) for a batch."""
    def task_set(self, tasks: Sequence[_Task]) -> TaskSet: ...
    def ik_step(
        self,
        q: _ArrayLike,
        tasks: Sequence[_Task] | TaskSet,
        dt: float,
        *,
        position_limits: bool = True,
        velocity_limits: bool = True,
        velocity_caps: _ArrayLike | None = None,
        limits: Sequence[CollisionAvoidance] | None = None,
    ) -> _F64: ...
    @overload
    def ik_step_qp(
        self,
        q: _ArrayLike,
        tasks: Sequence[_Task] | TaskSet,
        dt: float,
        *,
        position_limits: bool = True,
        velocity_limits: bool = True,
        velocity_caps: _ArrayLike | None = None,
        limits: Sequence[CollisionAvoidance] | None = None,
        with_rows: Literal[False] = False,
    ) -> tuple[_F64, _F64, _F64, _F64]: ...
    @overload
    def ik_step_qp(
        self,
        q: _ArrayLike,
        tasks: Sequence[_Task] | TaskSet,
        dt: float,
        *,
        position_limits: bool = True,
        velocity_limits: bool = True,
        velocity_caps: _ArrayLike | None = None,
        limits: Sequence[CollisionAvoidance] | None = None,
        with_rows: Literal[True],
    ) -> tuple[_F64, _F64, _F64, _F64, _F64, _F64]: ...
    def ik_tasks(
        self,
        tasks: Sequence[_Task],
        seed: _ArrayLike | None = None,
        *,
        max_iterations: int = 100,
        restarts: int = 50,
        seed_rng: int = 0,
        position_limits: bool = True,
        limits: Sequence[CollisionAvoidance] | None = None,
    ) -> TasksResult: ...
    def ik_trajectory(
        self,
        task_sets: Sequence[Sequence[_Task]],
        seed: _ArrayLike | None = None,
        *,
        segment: int = 0,
        warm_up: int = 0,
        max_iterations: int = 100,
        restarts: int = 50,
        seed_rng: int = 0,
        position_limits: bool = True,
        limits: Sequence[CollisionAvoidance] | None = None,
    ) -> list[TasksResult]: ...
    def analyze(
        self,
        q: _ArrayLike,
        frame: _JacobianFrame = "space",
        link: str | None = None,
        *,
        relative_to: str | None = None,
    ) -> Analysis: ...
    def draw(
        self,
        q: _ArrayLike | None = None,
        path: str | os.PathLike[str] | None = None,
        *,
        view: _Views = "iso",
        labels: _Labels = "leaves",
        axes: str | Sequence[str | int] | None = None,
    ) -> str: ...
    def viewer(
        self,
        q: _ArrayLike | None = None,
        path: str | os.PathLike[str] | None = None,
        *,
        motion: _ArrayLike | str | os.PathLike[str] | None = None,
        fps: float = 30.0,
        show_collisions: bool = False,
        show_distances: bool = False,
    ) -> str: ...
    def show(
        self,
        q: _ArrayLike | None = None,
        *,
        motion: _ArrayLike | str | os.PathLike[str] | None = None,
        fps: float = 30.0,
        height: int = 600,
        show_collisions: bool = False,
        show_distances: bool = False,
    ) -> Page:
        """The interactive page as a notebook shows it (inline, in an iframe)."""
    @overload
    def ik_all(
        self,
        target: _Mat,
        seed: _ArrayLike | None = None,
        *,
        lock: str | int | None = None,
        lock_value: float | None = None,
        sweep: int | None = None,
        representatives: _Representatives = "nearest",
        arm_angle: float | None = None,
        collisions: Literal["ignore", "filter"] = "ignore",
    ) -> _F64: ...
    @overload
    def ik_all(
        self,
        target: _Mats,
        seed: _ArrayLike | None = None,
        *,
        lock: str | int | None = None,
        lock_value: float | None = None,
        sweep: int | None = None,
        representatives: _Representatives = "nearest",
        arm_angle: float | None = None,
        collisions: Literal["ignore", "filter"] = "ignore",
    ) -> list[_F64]: ...
    @overload
    def ik_all(
        self,
        target: _Mat,
        seed: _ArrayLike | None = None,
        *,
        lock: str | int | None = None,
        lock_value: float | None = None,
        sweep: int | None = None,
        representatives: _Representatives = "nearest",
        arm_angle: float | None = None,
        collisions: Literal["flag"],
    ) -> tuple[_F64, _Bool]: ...
    @overload
    def ik_all(
        self,
        target: _Mats,
        seed: _ArrayLike | None = None,
        *,
        lock: str | int | None = None,
        lock_value: float | None = None,
        sweep: int | None = None,
        representatives: _Representatives = "nearest",
        arm_angle: float | None = None,
        collisions: Literal["flag"],
    ) -> list[tuple[_F64, _Bool]]: ...
    @overload
    def ik_all(
        self,
        target: _ArrayLike,
        seed: _ArrayLike | None = None,
        *,
        lock: str | int | None = None,
        lock_value: float | None = None,
        sweep: int | None = None,
        representatives: _Representatives = "nearest",
        arm_angle: float | None = None,
        collisions: Literal["flag"],
    ) -> tuple[_F64, _Bool] | list[tuple[_F64, _Bool]]: ...
    @overload
    def ik_all(
        self,
        target: _ArrayLike,
        seed: _ArrayLike | None = None,
        *,
        lock: str | int | None = None,
        lock_value: float | None = None,
        sweep: int | None = None,
        representatives: _Representatives = "nearest",
        arm_angle: float | None = None,
        collisions: Literal["ignore", "filter"] = "ignore",
    ) -> _F64 | list[_F64]:
        """One target (4, 4) -> its solutions (K, dof); N targets (N, 4, 4) -> a list of N.
        `collisions="flag"`: each answer is (q, collides); "filter": colliding ones dropped."""
    def arm_angle(self, q: _ArrayLike) -> float:
        """The arm angle (rad) of q for a 7R arm with a spherical shoulder and wrist."""
    @overload
    def ik(
        self,
        target: _Mat,
        seed: _ArrayLike | None = None,
        *,
        method: _Method = "lm",
        tol_rot: float = 1e-9,
        tol_pos: float = 1e-9,
        position_only: bool = False,
        timeout_ms: float | None = None,
        seed_rng: int = 0,
        max_iterations: int = 2000,
        max_restarts: int = 200,
        damping: float | None = None,
        weights: Sequence[float] | None = None,
        avoid_collisions: bool = False,
        margin: float = 0.0,
    ) -> IkResult: ...
    @overload
    def ik(
        self,
        target: _Mats,
        seed: _ArrayLike | None = None,
        *,
        method: _Method = "lm",
        tol_rot: float = 1e-9,
        tol_pos: float = 1e-9,
        position_only: bool = False,
        timeout_ms: float | None = None,
        seed_rng: int = 0,
        max_iterations: int = 2000,
        max_restarts: int = 200,
        damping: float | None = None,
        weights: Sequence[float] | None = None,
        avoid_collisions: bool = False,
        margin: float = 0.0,
    ) -> IkBatchResult: ...
    @overload
    def ik(
        self,
        target: _ArrayLike,
        seed: _ArrayLike | None = None,
        *,
        method: _Method = "lm",
        tol_rot: float = 1e-9,
        tol_pos: float = 1e-9,
        position_only: bool = False,
        timeout_ms: float | None = None,
        seed_rng: int = 0,
        max_iterations: int = 2000,
        max_restarts: int = 200,
        damping: float | None = None,
        weights: Sequence[float] | None = None,
        avoid_collisions: bool = False,
        margin: float = 0.0,
    ) -> IkResult | IkBatchResult:
        """One target (4, 4) -> IkResult; N targets (N, 4, 4) -> IkBatchResult."""

# The screw calculus (`screwkit.lie` re-exports these; `exp`/`log` are `exp6`/`log6`). Each
# takes one value or a stack of N along a leading axis; single results of scalar functions are
# Python floats and bools.
_Scalars: TypeAlias = float | _ArrayLike

def screw_to_axis(q: _ArrayLike, s: _ArrayLike, h: _Scalars | None = None) -> _F64: ...
def mr_inverse_dynamics(
    thetalist: _ArrayLike,
    dthetalist: _ArrayLike,
    ddthetalist: _ArrayLike,
    g: _ArrayLike,
    ftip: _ArrayLike,
    mlist: _ArrayLike,
    glist: _ArrayLike,
    slist: _ArrayLike,
) -> _F64: ...

@final
class CartesianPath:
    """A Cartesian path (`Robot.cartesian_path`)."""

    @property
    def q(self) -> _F64: ...
    @property
    def place(self) -> _F64: ...
    @property
    def fraction(self) -> float: ...
    @property
    def stop(self) -> str: ...
    @property
    def message(self) -> str: ...

@final
class TimedPath:
    """A joint path timed time-optimally (`time_parameterize`)."""

    @property
    def duration(self) -> float: ...
    @property
    def grid_times(self) -> _F64: ...
    @property
    def limits(self) -> tuple[_F64, _F64]: ...
    def __call__(self, t: float | _ArrayLike) -> _F64:
        """q at time(s) t: (n,) for a float, (M, n) for M times."""
    def sample(self, t: float | _ArrayLike) -> tuple[_F64, _F64, _F64]:
        """(q, q̇, q̈) at time(s) t."""

def time_parameterize(
    path: _ArrayLike,
    vel_limits: _ArrayLike,
    acc_limits: _ArrayLike,
    *,
    grid: int | None = None,
    check: float = 0.001,
) -> TimedPath:
    """The time-optimal timing (TOPP-RA) of the joint path through `path` (m, n)."""

def tr_cubic_time_scaling(Tf: float, t: _ArrayLike) -> Any: ...
def tr_quintic_time_scaling(Tf: float, t: _ArrayLike) -> Any: ...
def tr_joint_trajectory(
    thetastart: _ArrayLike, thetaend: _ArrayLike, Tf: float, N: int, method: int
) -> _F64: ...
def tr_screw_trajectory(
    Xstart: _ArrayLike, Xend: _ArrayLike, Tf: float, N: int, method: int
) -> _F64: ...
def tr_cartesian_trajectory(
    Xstart: _ArrayLike, Xend: _ArrayLike, Tf: float, N: int, method: int
) -> _F64: ...
def mr_mass_matrix(
    thetalist: _ArrayLike, mlist: _ArrayLike, glist: _ArrayLike, slist: _ArrayLike
) -> _F64: ...
def mr_vel_quadratic_forces(
    thetalist: _ArrayLike,
    dthetalist: _ArrayLike,
    mlist: _ArrayLike,
    glist: _ArrayLike,
    slist: _ArrayLike,
) -> _F64: ...
def mr_gravity_forces(
    thetalist: _ArrayLike, g: _ArrayLike, mlist: _ArrayLike, glist: _ArrayLike, slist: _ArrayLike
) -> _F64: ...
def mr_end_effector_forces(
    thetalist: _ArrayLike,
    ftip: _ArrayLike,
    mlist: _ArrayLike,
    glist: _ArrayLike,
    slist: _ArrayLike,
) -> _F64: ...
def mr_forward_dynamics(
    thetalist: _ArrayLike,
    dthetalist: _ArrayLike,
    taulist: _ArrayLike,
    g: _ArrayLike,
    ftip: _ArrayLike,
    mlist: _ArrayLike,
    glist: _ArrayLike,
    slist: _ArrayLike,
) -> _F64: ...
def mr_inverse_dynamics_trajectory(
    thetamat: _ArrayLike,
    dthetamat: _ArrayLike,
    ddthetamat: _ArrayLike,
    g: _ArrayLike,
    ftipmat: _ArrayLike,
    mlist: _ArrayLike,
    glist: _ArrayLike,
    slist: _ArrayLike,
) -> _F64: ...
def axis_angle3(expc3: _ArrayLike) -> tuple[_F64, Any]: ...
def axis_angle6(expc6: _ArrayLike) -> tuple[_F64, Any]: ...
def hat(x: _ArrayLike) -> _F64: ...
def vee(m: _ArrayLike) -> _F64: ...
def exp3(w: _ArrayLike, theta: _Scalars | None = None) -> _F64: ...
def log3(r: _ArrayLike) -> _F64: ...
def exp6(twist: _ArrayLike, theta: _Scalars | None = None) -> _F64: ...
def log6(t: _ArrayLike) -> _F64: ...
def adjoint(t: _ArrayLike) -> _F64: ...
def ad(v: _ArrayLike) -> _F64: ...
def trans_inv(t: _ArrayLike) -> _F64: ...
def rot_inv(r: _ArrayLike) -> _F64: ...
def project_to_so3(m: _ArrayLike) -> _F64: ...
def project_to_se3(m: _ArrayLike) -> _F64: ...
@overload
def distance_to_so3(m: _Mat) -> float: ...
@overload
def distance_to_so3(m: _Mats) -> _F64: ...
@overload
def distance_to_so3(m: _ArrayLike) -> Any: ...
@overload
def distance_to_se3(m: _Mat) -> float: ...
@overload
def distance_to_se3(m: _Mats) -> _F64: ...
@overload
def distance_to_se3(m: _ArrayLike) -> Any: ...
@overload
def is_so3(m: _Mat, tol: float = 1e-06) -> bool: ...
@overload
def is_so3(m: _Mats, tol: float = 1e-06) -> npt.NDArray[np.bool_]: ...
@overload
def is_so3(m: _ArrayLike, tol: float = 1e-06) -> Any: ...
@overload
def is_se3(m: _Mat, tol: float = 1e-06) -> bool: ...
@overload
def is_se3(m: _Mats, tol: float = 1e-06) -> npt.NDArray[np.bool_]: ...
@overload
def is_se3(m: _ArrayLike, tol: float = 1e-06) -> Any: ...

exp = exp6
log = log6

def row_seed(seed: int, k: int) -> int: ...
def set_num_threads(threads: int | None = None) -> None: ...
def num_threads() -> int: ...
def kernel_path() -> str:
    """The kernel path of this CPU, chosen at run time: "avx512", "avx2+fma" or "portable"."""

def xacro(
    path: str | os.PathLike[str],
    package_paths: Sequence[str | os.PathLike[str]] | None = None,
    args: Mapping[str, str] | None = None,
) -> str: ...

# Plumbing of the Python layer (not in __all__, not public API).
def _reach_build(
    robot: Robot,
    path: str,
    *,
    resolution: float,
    orientations: int,
    mode: str,
    bounds: tuple[float, ...] | None,
    solver: str,
    seed: int,
    restarts: int,
    iterations: int,
    shard_index: int,
    shard_count: int,
    collision_margin: float | None = None,
    obstacles: str | None = None,
) -> dict[str, Any]:
    """Builds shard `shard_index` of `shard_count` of a reachability map into the .npz `path`
    (the GIL released); a summary dict. Use `screwkit.reach`."""

def _reach_merge(shards: list[str], path: str) -> dict[str, Any]:
    """Joins map shards into `path`. Use `screwkit.merge`."""

def _reach_svg(path: str) -> str:
    """The SVG slices through the base of the whole map `path`."""

def _defaults() -> dict[str, dict[str, Any]]:
    """The one set of defaults (IK, maps), as the floor holds them."""

def _words() -> dict[str, list[str]]:
    """Every option word family and its words."""
