"""An independent oracle: a URDF's chain composed joint by joint in numpy.

It reads the URDF with xml.etree and multiplies the joints' origin transforms and motions along
the path base -> tip; it shares nothing with screwkit but the joint order of q (by name).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]


@dataclass
class Joint:
    name: str
    kind: str
    parent: str
    child: str
    xyz: Array
    rpy: Array
    axis: Array
    mimic: tuple[str, float, float] | None


def _floats(text: str | None, default: str) -> Array:
    return np.array([float(x) for x in (text or default).split()], dtype=np.float64)


def rpy_matrix(rpy: Array) -> Array:
    """R = Rz(yaw) Ry(pitch) Rx(roll) (URDF's fixed-axis convention)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return np.asarray(rz @ ry @ rx, dtype=np.float64)


def axis_angle(axis: Array, theta: float) -> Array:
    """Rotation by theta about a unit axis (Rodrigues, written out)."""
    x, y, z = axis
    c, s = math.cos(theta), math.sin(theta)
    t = 1.0 - c
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
        ]
    )


def adjoint(t: Array) -> Array:
    """[Ad_T] = [[R, 0], [[p]R, R]] for twists ordered (omega, v)."""
    r, p = t[:3, :3], t[:3, 3]
    px = np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])
    ad = np.zeros((6, 6))
    ad[:3, :3] = r
    ad[3:, 3:] = r
    ad[3:, :3] = px @ r
    return ad


def homogeneous(r: Array, p: Array) -> Array:
    t = np.eye(4)
    t[:3, :3] = r
    t[:3, 3] = p
    return t


class UrdfChain:
    """The joints on the path base -> tip of a URDF file."""

    def __init__(self, path: str, base: str, tip: str) -> None:
        root = ET.parse(path).getroot()
        joints: dict[str, Joint] = {}
        for j in root.findall("joint"):
            origin = j.find("origin")
            axis = j.find("axis")
            mimic = j.find("mimic")
            parent = j.find("parent")
            child = j.find("child")
            assert parent is not None and child is not None
            a = _floats(axis.get("xyz") if axis is not None else None, "1 0 0")
            joints[j.attrib["name"]] = Joint(
                name=j.attrib["name"],
                kind=j.attrib["type"],
                parent=parent.attrib["link"],
                child=child.attrib["link"],
                xyz=_floats(origin.get("xyz") if origin is not None else None, "0 0 0"),
                rpy=_floats(origin.get("rpy") if origin is not None else None, "0 0 0"),
                axis=a / np.linalg.norm(a) if np.linalg.norm(a) > 0 else a,
                mimic=(
                    mimic.attrib["joint"],
                    float(mimic.get("multiplier", "1")),
                    float(mimic.get("offset", "0")),
                )
                if mimic is not None
                else None,
            )
        self.all_joints = joints
        by_child = {j.child: j for j in joints.values()}
        path_joints: list[Joint] = []
        link = tip
        while link != base:
            step = by_child[link]  # KeyError: base is not an ancestor of tip
            path_joints.append(step)
            link = step.parent
        self.joints = path_joints[::-1]
        self.links = [base] + [j.child for j in self.joints]

    def joint_value(self, name: str, q: dict[str, float]) -> float:
        """The joint's position: its own variable, or m * leader + offset for a mimic joint."""
        if name in q:
            return q[name]
        j = self.all_joints[name]
        assert j.mimic is not None, f"joint {name} is neither a variable nor a mimic joint"
        leader, m, o = j.mimic
        return m * self.joint_value(leader, q) + o

    def poses(self, names: list[str], q: npt.ArrayLike) -> list[Array]:
        """The pose of every link on the path (base first) in the base frame."""
        values = dict(zip(names, np.asarray(q, dtype=np.float64).tolist(), strict=False))
        t = np.eye(4)
        out = [t.copy()]
        for j in self.joints:
            t = t @ homogeneous(rpy_matrix(j.rpy), j.xyz)
            if j.kind in ("revolute", "continuous"):
                t = t @ homogeneous(
                    axis_angle(j.axis, self.joint_value(j.name, values)), np.zeros(3)
                )
            elif j.kind == "prismatic":
                t = t @ homogeneous(np.eye(3), j.axis * self.joint_value(j.name, values))
            else:
                assert j.kind == "fixed", j.kind
            out.append(t.copy())
        return out

    def fk(self, names: list[str], q: npt.ArrayLike) -> Array:
        """The tip pose in the base frame."""
        return self.poses(names, q)[-1]

    def home(self) -> Array:
        """M: the tip pose with every joint (mimic joints too) at position 0."""
        names = [j.name for j in self.joints]
        return self.fk(names, np.zeros(len(names)))
