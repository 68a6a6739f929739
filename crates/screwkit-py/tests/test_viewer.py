"""The interactive page from Python: `Robot.viewer(motion=…)` plays a motion back, the same page
`screwkit view --motion` writes from a file; bad motions raise `ValueError` naming the frame."""

from __future__ import annotations

import html
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import screwkit

from conftest import ASSETS


def model_of(page: str) -> dict[str, object]:
    start = page.index('id="model">') + len('id="model">')
    end = page.index("</script>", start)
    out: dict[str, object] = json.loads(page[start:end])
    return out


def test_viewer_plays_a_motion(tmp_path: Path) -> None:
    robot = screwkit.Robot.from_urdf(ASSETS / "ur5.urdf")
    t = np.linspace(0.0, 1.0, 40)[:, None]
    frames = np.hstack([t, -1 + 0.5 * t, np.full_like(t, 1.4), -0.8 + 0 * t, -1.2 + t, 0.4 + 0 * t])
    page = robot.viewer(motion=frames, fps=25.0)
    model = model_of(page)
    motion = model["motion"]
    assert isinstance(motion, dict)
    np.testing.assert_array_equal(motion["frames"], frames)
    assert motion["fps"] == 25.0
    np.testing.assert_array_equal(model["q"], frames[0])
    # The same page from a file, from Python and from the command line.
    npy = tmp_path / "motion.npy"
    np.save(npy, frames)
    assert robot.viewer(motion=npy, fps=25.0) == page
    assert robot.viewer(motion=str(npy), fps=25.0) == page
    exe = os.environ.get("SCREWKIT_CLI")
    if exe and Path(exe).exists():
        out = tmp_path / "page.html"
        args = [exe, "view", str(ASSETS / "ur5.urdf"), "--motion", str(npy), "--fps", "25"]
        done = subprocess.run([*args, "-o", str(out)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        assert out.read_text() == page
    # The page is never written over the motion it plays, by any name, nor over the robot.
    before = npy.read_bytes()
    for out_name in [npy, tmp_path / "." / "motion.npy"]:
        with pytest.raises(ValueError, match="is also an input"):
            robot.viewer(motion=npy, path=out_name)
    assert npy.read_bytes() == before
    copy = tmp_path / "ur5.urdf"
    copy.write_bytes((ASSETS / "ur5.urdf").read_bytes())
    held = screwkit.Robot.from_urdf(copy)  # its file stays protected while it lives
    with pytest.raises(ValueError, match="is an input of this run"):
        held.show().save(copy)
    with pytest.raises(ValueError, match="is an input of this run"):
        held.viewer(path=copy)
    assert copy.read_bytes() == (ASSETS / "ur5.urdf").read_bytes()
    # Bad motions: the frame named.
    bad = frames.copy()
    bad[7, 2] = np.nan
    with pytest.raises(ValueError, match="frame 7"):
        robot.viewer(motion=bad)
    with pytest.raises(ValueError, match="shape"):
        robot.viewer(motion=frames[0])
    with pytest.raises(ValueError, match="fps"):
        robot.viewer(motion=frames, fps=0.0)
    with pytest.raises(ValueError, match="frame 0"):
        robot.viewer(motion=frames[:, :5])


def test_show_is_the_page_in_a_notebook(tmp_path: Path) -> None:
    """`Robot.show` gives what Jupyter displays: the whole page (the viewer's, byte for byte)
    in an iframe's `srcdoc`, quoted so that the attribute holds all of it."""
    robot = screwkit.Robot.from_urdf(ASSETS / "ur5.urdf")
    q = [0.3, -1.0, 1.4, -0.8, -1.2, 0.4]
    page = robot.show(q, height=480)
    assert isinstance(page, screwkit.Page)
    assert page.html == robot.viewer(q)
    frame = page._repr_html_()
    assert frame.startswith('<iframe srcdoc="') and "height: 480px" in frame
    srcdoc = frame[len('<iframe srcdoc="') : frame.index('" style=')]
    assert '"' not in srcdoc
    assert html.unescape(srcdoc) == page.html
    out = tmp_path / "ur5.html"
    page.save(out)
    assert out.read_text() == page.html
    with pytest.raises(ValueError, match="height"):
        robot.show(q, height=5)


def test_obstacles_are_drawn(tmp_path: Path) -> None:
    """Obstacles added to the robot (Python) or given as a scene file (CLI `view --obstacles`)
    stand in the page's world, the same shape at the same pose."""
    robot = screwkit.Robot.from_urdf(ASSETS / "ur5.urdf")
    pose = np.eye(4)
    pose[:3, 3] = [0.6, 0.0, 0.1]
    robot.add_obstacle("table", screwkit.Box((0.6, 1.2, 0.05)), pose)
    body = model_of(robot.viewer())["body"]
    assert isinstance(body, dict)
    (table,) = [s for s in body["shapes"] if s["role"] == "obstacle"]
    assert table["link"] is None and table["kind"] == "box"
    assert table["size"] == [0.6, 1.2, 0.05]
    np.testing.assert_array_equal(np.reshape(table["origin"], (4, 4)), pose)
    exe = os.environ.get("SCREWKIT_CLI")
    if exe and Path(exe).exists():
        scene = tmp_path / "scene.json"
        obstacle = {"name": "table", "shape": "box", "size": [0.6, 1.2, 0.05], "xyz": [0.6, 0, 0.1]}
        scene.write_text(json.dumps({"obstacles": [obstacle]}))
        out = tmp_path / "page.html"
        args = [exe, "view", str(ASSETS / "ur5.urdf"), "--obstacles", str(scene), "-o", str(out)]
        done = subprocess.run(args, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        cli_body = model_of(out.read_text())["body"]
        assert isinstance(cli_body, dict)
        assert [s for s in cli_body["shapes"] if s["role"] == "obstacle"] == [table]
