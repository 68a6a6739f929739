"""screwkit: robot kinematics with screw theory.

A whole robot from URDF, xacro, MJCF or a screw table: screw axes and home pose, every frame's
pose (FK), space, body and world-aligned Jacobians, singularity analysis, inverse kinematics
(numerical, every analytic solution, whole-body tasks), one configuration at a time or N at
once on all cores (with the GIL released). Conventions: twists and screw axes (omega, v);
metres, radians, float64; poses are row-major 4x4 arrays; the space frame is the base link,
the body frame the frame asked for.

>>> import screwkit
>>> robot = screwkit.Robot.from_urdf("ur5.urdf")          # doctest: +SKIP
>>> robot.fk([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])             # doctest: +SKIP
"""

from . import dynamics, lie, trajectory
from ._screwkit import (
    Analysis,
    AxisTask,
    BatchError,
    Box,
    Capsule,
    CartesianPath,
    CollisionAvoidance,
    ComTask,
    Cylinder,
    DampingTask,
    Distances,
    FrameTask,
    IkBatchResult,
    IkResult,
    Mesh,
    Page,
    PostureTask,
    RelativeFrameTask,
    Robot,
    Sphere,
    TaskSet,
    TasksResult,
    TimedPath,
    __version__,
    adjoint,
    exp,
    kernel_path,
    log,
    num_threads,
    row_seed,
    set_num_threads,
    time_parameterize,
    xacro,
)
from .reach import ReachMap, merge, reach


def host() -> str:
    """Where this process runs, in one line, for benchmarks to print next to their figures: the
    CPU's model (Linux's /proc/cpuinfo), whether it has AVX-512, its hardware threads, the batch
    pool's threads and the kernel path (`kernel_path()`). Figures compare only on one host
    class."""
    import os

    model, avx512 = "unknown CPU", False
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("model name") and model == "unknown CPU":
                    model = line.split(":", 1)[1].strip()
                elif line.startswith("flags"):
                    avx512 = " avx512f" in line
                    break
    except OSError:
        pass
    return (
        f"{model}{' (AVX-512)' if avx512 else ''}, {os.cpu_count()} hardware threads, "
        f"{num_threads()} pool threads, kernels {kernel_path()}"
    )


__all__ = [
    "Analysis",
    "AxisTask",
    "BatchError",
    "Box",
    "CartesianPath",
    "Capsule",
    "CollisionAvoidance",
    "ComTask",
    "Cylinder",
    "DampingTask",
    "Distances",
    "FrameTask",
    "IkBatchResult",
    "IkResult",
    "Mesh",
    "PostureTask",
    "ReachMap",
    "RelativeFrameTask",
    "Page",
    "Robot",
    "Sphere",
    "TaskSet",
    "TasksResult",
    "TimedPath",
    "__version__",
    "adjoint",
    "exp",
    "host",
    "kernel_path",
    "dynamics",
    "lie",
    "log",
    "merge",
    "num_threads",
    "reach",
    "row_seed",
    "set_num_threads",
    "time_parameterize",
    "trajectory",
    "xacro",
]
