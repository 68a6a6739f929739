"""The textbook's dynamics of an open chain (*Modern Robotics* ch. 8), with the arguments of
the `modern_robotics` package of the textbook's authors (each function is tested equal to
its namesake there): the chain is given by `Mlist` (n + 1, 4, 4), the link frames at home
one in the previous, the last the end effector's {n+1} in link n's; `Glist` (n, 6, 6), each
link's spatial inertia in its own frame ((omega, v) order); `Slist` (6, n), the space screw
axes as columns. `g` is gravity in the base frame (e.g. [0, 0, -9.8]); `Ftip` the wrench
(m, f) the end effector applies to the environment, in {n+1}.

For a robot file, `Robot.inverse_dynamics`, `Robot.mass_matrix`, `Robot.forward_dynamics`,
... answer for the whole tree.

>>> import numpy as np
>>> from screwkit import dynamics
>>> M = [np.eye(4), np.eye(4)]
>>> M[1][0, 3] = 1.0  # one link: its frame at the joint, the tip 1 m along x
>>> G = [np.diag([0, 0, 1.0, 2.0, 2.0, 2.0])]  # 2 kg at the joint, 1 kg m² about z
>>> S = np.array([[0, 0, 1, 0, 0, 0]]).T
>>> dynamics.mass_matrix([0.3], M, G, S)
array([[1.]])
"""

from ._screwkit import (
    mr_end_effector_forces as end_effector_forces,
)
from ._screwkit import (
    mr_forward_dynamics as forward_dynamics,
)
from ._screwkit import (
    mr_gravity_forces as gravity_forces,
)
from ._screwkit import (
    mr_inverse_dynamics as inverse_dynamics,
)
from ._screwkit import (
    mr_inverse_dynamics_trajectory as inverse_dynamics_trajectory,
)
from ._screwkit import (
    mr_mass_matrix as mass_matrix,
)
from ._screwkit import (
    mr_vel_quadratic_forces as vel_quadratic_forces,
)

__all__ = [
    "end_effector_forces",
    "forward_dynamics",
    "gravity_forces",
    "inverse_dynamics",
    "inverse_dynamics_trajectory",
    "mass_matrix",
    "vel_quadratic_forces",
]
