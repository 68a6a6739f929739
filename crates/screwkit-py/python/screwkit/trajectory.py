"""The textbook's trajectories (*Modern Robotics* ch. 9), with the arguments of the
`modern_robotics` package of the textbook's authors (each function is tested equal to its
namesake there): polynomial time scalings s(t) over a duration `Tf`, and N samples of a
straight-line joint path, of the screw motion between two poses, or of the decoupled
Cartesian motion (origin on a straight line, rotation about one axis). `method` is 3 (cubic
time scaling) or 5 (quintic); other numbers raise `ValueError` (the textbook's package takes
them as quintic), as do `Tf` <= 0 and `N` < 2.

Batched: a time scaling takes a float t or an array of them; `joint_trajectory` takes (B, n)
starts and ends and gives (B, N, n); the pose trajectories take (B, 4, 4) and give
(B, N, 4, 4).

>>> import numpy as np
>>> from screwkit import trajectory
>>> round(trajectory.cubic_time_scaling(2, 0.6), 6)
0.216
>>> trajectory.joint_trajectory([0, 1], [1, 3], 2, 3, 3)
array([[0. , 1. ],
       [0.5, 2. ],
       [1. , 3. ]])
"""

from ._screwkit import (
    tr_cartesian_trajectory as cartesian_trajectory,
)
from ._screwkit import (
    tr_cubic_time_scaling as cubic_time_scaling,
)
from ._screwkit import (
    tr_joint_trajectory as joint_trajectory,
)
from ._screwkit import (
    tr_quintic_time_scaling as quintic_time_scaling,
)
from ._screwkit import (
    tr_screw_trajectory as screw_trajectory,
)

__all__ = [
    "cartesian_trajectory",
    "cubic_time_scaling",
    "joint_trajectory",
    "quintic_time_scaling",
    "screw_trajectory",
]
