"""Pictures from Python: the library's SVG drawing and HTML page, checked for content."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import screwkit

from conftest import ChainSpec, all_chains, configurations

SVG = "{http://www.w3.org/2000/svg}"


@pytest.mark.parametrize("spec", all_chains())
def test_draw_every_chain(spec: ChainSpec, tmp_path: Path) -> None:
    robot = spec.robot()
    q = configurations(robot, 1, seed=51)[0]
    out = tmp_path / "arm.svg"
    text = robot.draw(q, out, view="all")
    assert out.read_text() == text == robot.draw(list(q), view="all")
    root = ET.fromstring(text)
    assert root.tag == SVG + "svg" and root.get("version") == "1.1"
    ids = {e.get("id") for e in root.iter() if e.get("id")}
    for view in ("iso", "front", "side", "top"):
        for i, name in enumerate(robot.axis_names, start=1):
            assert f"{view}-joint-{i}" in ids and f"{view}-axis-{i}" in ids
            g = next(e for e in root.iter() if e.get("id") == f"{view}-axis-{i}")
            assert g.get("data-joint") == name
    assert robot.draw(view="top").count('class="view"') == 1


def test_viewer_embeds_the_chain(ur5: screwkit.Robot, tmp_path: Path) -> None:
    page = ur5.viewer([0.1] * 6, tmp_path / "ur5.html")
    assert (tmp_path / "ur5.html").read_text() == page
    model = json.loads(page.split('id="model">')[1].split("</script>")[0])
    assert model["q"] == [0.1] * 6
    np.testing.assert_array_equal([j["S"] for j in model["joints"]], ur5.screw_axes("space"))
    # The tip is the page's one drawn frame, at M (its home pose).
    assert [f["name"] for f in model["frames"]] == ["tool0"]
    np.testing.assert_array_equal(np.reshape(model["frames"][0]["home"], (4, 4)), ur5.home)


def test_draw_errors(ur5: screwkit.Robot, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"view: unknown view \"back\""):
        ur5.draw(view="back")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"q: expected shape \(6,\), got \(2, 6\)"):
        ur5.draw(np.zeros((2, 6)))
    with pytest.raises(ValueError, match=r"wrist_3_joint"):
        ur5.draw([0, 0, 0, 0, 0, np.nan])
    with pytest.raises(FileNotFoundError, match=r"no_dir"):
        ur5.draw(path=tmp_path / "no_dir" / "x.svg")


def test_labels_and_axes_are_chosen(tmp_path: Path) -> None:
    """Issue 49, item 4: `labels` and `axes` choose the names and screw axes, as
    `screwkit draw --labels --axes` does (the same bytes); the humanoid's body is drawn
    (a silhouette per shape); a tree of 23 joints shows no axis unless asked."""
    import os
    import subprocess

    from conftest import ASSETS

    humanoid = screwkit.Robot.from_urdf(ASSETS / "humanoid.urdf")
    default = humanoid.draw()
    root = ET.fromstring(default)
    shapes = [e for e in root.iter(SVG + "polygon") if (e.get("class") or "").startswith("shape")]
    assert len(shapes) >= 20
    assert 'id="iso-axis-' not in default
    names = [e.text for e in root.iter(SVG + "text") if e.get("class") == "label name"]
    assert sorted(n for n in names if n) == [
        "head",
        "left_hand",
        "left_sole",
        "right_hand",
        "right_sole",
    ]
    everything = humanoid.draw(labels="all", axes="all")
    assert 'id="iso-axis-23"' in everything
    assert humanoid.draw(labels="none").count('class="label ') == 0
    picked = humanoid.draw(axes=["left_knee", 1])
    assert picked == humanoid.draw(axes="left_knee,1")
    assert picked.count('class="axis ') == 2
    with pytest.raises(ValueError, match='axes: no joint "elbow"'):
        humanoid.draw(axes=["elbow"])
    with pytest.raises(TypeError, match="axes"):
        humanoid.draw(axes=[1.5])  # type: ignore[list-item]
    with pytest.raises(ValueError, match='labels: unknown labels "some"'):
        humanoid.draw(labels="some")  # type: ignore[arg-type]
    exe = os.environ.get("SCREWKIT_CLI")
    if not (exe and Path(exe).exists()):
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    out = tmp_path / "humanoid.svg"
    args = ["draw", str(ASSETS / "humanoid.urdf"), "--labels", "all", "--axes", "left_knee,1"]
    done = subprocess.run([exe, *args, "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert out.read_text() == humanoid.draw(labels="all", axes=["left_knee", 1])
