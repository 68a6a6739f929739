"""FK and Jacobians against Pinocchio (the `pin` package) on every bundled chain and the real
URDFs of the CI data (SCREWKIT_SHARED_URDF).

Pinocchio loads the whole URDF (fixed base, mimic joints as ordinary joints, which this test
drives by their <mimic> rule itself); the chain's pose is oMf[base]^-1 oMf[tip]. Its LOCAL
frame Jacobian is the body Jacobian with rows (v, omega); the space Jacobian is compared as
Ad(T_sb) J_b with Pinocchio's T_sb.
"""

from __future__ import annotations

import re

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import ChainSpec, all_chains, configurations
from urdf_oracle import UrdfChain, adjoint

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is a test dependency")

Array = npt.NDArray[np.float64]


def urdfdom_compatible(xml: str) -> str:
    """urdfdom (Pinocchio's parser) refuses a <limit> without effort or velocity, which the URDF
    spec requires but many files omit (tricky.urdf on purpose). Both are dynamics: add them."""

    def fix(m: re.Match[str]) -> str:
        tag = m.group(0)
        for attr in ("effort", "velocity"):
            if f"{attr}=" not in tag:
                tag = tag.replace("<limit", f'<limit {attr}="1"', 1)
        return tag

    return re.sub(r"<limit\b[^>]*>", fix, xml)


class PinChain:
    def __init__(self, spec: ChainSpec, robot: screwkit.Robot) -> None:
        self.model = pin.buildModelFromXML(urdfdom_compatible(spec.path.read_text()))
        self.data = self.model.createData()
        self.base = self.model.getFrameId(robot.base, pin.BODY)
        self.tip = self.model.getFrameId(robot.tip, pin.BODY)
        assert self.base < len(self.model.frames) and self.tip < len(self.model.frames)
        self.urdf = UrdfChain(str(spec.path), robot.base, robot.tip)
        self.names = robot.joint_names

    def q(self, q: Array) -> Array:
        """Pinocchio's configuration: the chain's joints (and mimic joints by their rule),
        every other joint at its neutral position."""
        values = dict(zip(self.names, q.tolist(), strict=False))
        out = pin.neutral(self.model)
        for jid in range(1, self.model.njoints):
            name = self.model.names[jid]
            try:
                x = self.urdf.joint_value(name, values)
            except AssertionError:  # off the chain, or a mimic joint led from off the chain
                continue
            iq, nq = self.model.joints[jid].idx_q, self.model.joints[jid].nq
            if nq == 2:  # continuous: (cos, sin)
                out[iq : iq + 2] = [np.cos(x), np.sin(x)]
            else:
                out[iq] = x
        return np.asarray(out, dtype=np.float64)

    def pose_and_body_jacobian(self, q: Array) -> tuple[Array, Array]:
        m, d = self.model, self.data
        pq = self.q(q)
        pin.computeJointJacobians(m, d, pq)
        pin.updateFramePlacements(m, d)
        t = (d.oMf[self.base].inverse() * d.oMf[self.tip]).homogeneous
        j_local = pin.getFrameJacobian(m, d, self.tip, pin.LOCAL)  # rows (v, omega)
        # Chain rule onto the chain's variables: a joint driven by variable k with multiplier
        # mult adds mult * its column to column k.
        values = dict(zip(self.names, q.tolist(), strict=False))
        jb = np.zeros((6, len(self.names)))
        for jid in range(1, m.njoints):
            name = m.names[jid]
            col = j_local[[3, 4, 5, 0, 1, 2], m.joints[jid].idx_v]
            for k, var in enumerate(self.names):
                # d(joint position)/d(q_k) by central differences of the mimic rule (exact for
                # the linear rule; 0 for joints off the chain's variables).
                dq = dict(values)
                dq[var] = values[var] + 1.0
                try:
                    gain = self.urdf.joint_value(name, dq) - self.urdf.joint_value(name, values)
                except (AssertionError, KeyError):
                    gain = 0.0
                jb[:, k] += gain * col
        return np.asarray(t, dtype=np.float64), jb


@pytest.mark.parametrize("spec", all_chains())
def test_fk_and_jacobians_equal_pinocchio(spec: ChainSpec) -> None:
    robot = spec.robot()
    peer = PinChain(spec, robot)
    qs = configurations(robot, 20, seed=7)
    poses = robot.fk(qs)
    jbs = robot.jacobian(qs, "body")
    jss = robot.jacobian(qs, "space")
    for q, t, jb, js in zip(qs, poses, jbs, jss, strict=False):
        t_pin, jb_pin = peer.pose_and_body_jacobian(q)
        np.testing.assert_allclose(t, t_pin, rtol=0, atol=1e-12)
        np.testing.assert_allclose(jb, jb_pin, rtol=0, atol=1e-12)
        np.testing.assert_allclose(js, adjoint(t_pin) @ jb_pin, rtol=0, atol=1e-12)
