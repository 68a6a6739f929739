"""The screw calculus of *Modern Robotics* ch. 3: exp and log on SO(3) and SE(3), screw axes,
adjoints, inverses, projections and distances, as numpy functions.

Every function takes one value (a (3,) vector, a (4, 4) transform, ...) or a stack of N along
a leading axis ((N, 3), (N, 4, 4), ...) and returns one result or N. Conventions: twists and
screw axes (omega, v); metres, radians, float64. A bad single input raises `ValueError`; a bad
row of a stack raises `screwkit.BatchError` after every other row was computed (bad rows NaN).

Where these differ from the `modern_robotics` package of the textbook's authors (each is tested
against it): `screw_to_axis` normalises the direction; `axis_angle6` takes omega = 0 exactly for
a translation (MR: norm(omega) < 1e-6); `log3`/`log6` stay accurate near theta = 0 and theta =
pi; `project_to_so3` returns the nearest proper rotation (MR negates a column instead when
det(U V^T) < 0); `distance_to_so3/se3` return +inf for det <= 0 (MR: 1e9); `is_so3/is_se3` use
screwkit's input tolerance (max |R^T R - I| <= 1e-6; MR: distance < 1e-3).

>>> import numpy as np
>>> from screwkit import lie
>>> lie.screw_to_axis([3, 0, 0], [0, 0, 1], 2)
array([ 0.,  0.,  1.,  0., -3.,  2.])
"""

from ._screwkit import (
    ad,
    adjoint,
    axis_angle3,
    axis_angle6,
    distance_to_se3,
    distance_to_so3,
    exp3,
    exp6,
    hat,
    is_se3,
    is_so3,
    log3,
    log6,
    project_to_se3,
    project_to_so3,
    rot_inv,
    screw_to_axis,
    trans_inv,
    vee,
)

__all__ = [
    "ad",
    "adjoint",
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
    "trans_inv",
    "vee",
]
