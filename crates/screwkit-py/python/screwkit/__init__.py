"""screwkit: robot kinematics from URDF with screw theory.

Screw axes and home pose, forward kinematics, space and body Jacobians, singularity analysis
and inverse kinematics of any serial chain in a URDF, one configuration at a time or N at once
on all cores (with the GIL released). Conventions: twists and screw axes (omega, v); metres,
radians, float64; poses are row-major 4x4 arrays; the space frame is the chain's base link, the
body frame its tip link.

>>> import screwkit
>>> robot = screwkit.Robot.from_urdf("ur5.urdf")          # doctest: +SKIP
>>> robot.fk([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])             # doctest: +SKIP
"""

from . import lie
from ._screwkit import (
    Analysis,
    AxisTask,
    BatchError,
    ComTask,
    DampingTask,
    FrameTask,
    IkBatchResult,
    IkResult,
    PostureTask,
    RelativeFrameTask,
    Robot,
    TasksResult,
    __version__,
    adjoint,
    exp,
    log,
    num_threads,
    row_seed,
    set_num_threads,
    xacro,
)
from .reach import ReachMap, merge, reach

__all__ = [
    "Analysis",
    "AxisTask",
    "BatchError",
    "ComTask",
    "DampingTask",
    "FrameTask",
    "IkBatchResult",
    "IkResult",
    "PostureTask",
    "ReachMap",
    "RelativeFrameTask",
    "Robot",
    "TasksResult",
    "__version__",
    "adjoint",
    "exp",
    "lie",
    "log",
    "merge",
    "num_threads",
    "reach",
    "row_seed",
    "set_num_threads",
    "xacro",
]
