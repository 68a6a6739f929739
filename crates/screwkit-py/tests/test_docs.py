"""The Python examples of the README and of the guide (docs/guide/*.md) are real.

Every ```python block is run, in a scratch folder holding the bundled ``assets/`` (so the files
an example writes land there), with the ``screwkit`` binary (``SCREWKIT_CLI``) first on the
PATH. A block followed by "prints (a real run):" and a ```text block must print that block, line
for line, numbers to 1e-9 relative (1e-12 absolute: an IK residual of 3e-15 is noise, not a
result). ``SCREWKIT_UPDATE_DOCS=1`` pastes what the examples print into the pages instead;
read every changed line in ``git diff`` before committing it.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO

# numpy's print options as an example finds them (an example may change them for itself).
PRINT_OPTIONS = np.get_printoptions()

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
BLOCK = re.compile(
    r"```python\n((?:[^`]|`(?!``))*)```\n(?:\s*prints \(a real run\):\s*\n```text\n(.*?)```)?",
    re.DOTALL,
)


def documents() -> list[Path]:
    return [REPO / "README.md", *sorted((REPO / "docs" / "guide").glob("*.md"))]


@dataclass(frozen=True)
class Example:
    doc: Path
    line: int
    code: str
    printed: str | None
    # Character span of the printed block's content in the document.
    span: tuple[int, int] | None

    @property
    def where(self) -> str:
        return f"{self.doc.relative_to(REPO)}:{self.line}"


def examples() -> list[Example]:
    out = []
    for doc in documents():
        text = doc.read_text()
        for m in BLOCK.finditer(text):
            line = text[: m.start()].count("\n") + 1
            span = m.span(2) if m[2] is not None else None
            out.append(Example(doc, line, m[1], m[2], span))
    return out


def same(got: str, want: str) -> bool:
    """Equal text outside the numbers, and equal numbers within the tolerances."""
    if NUMBER.sub("#", got) != NUMBER.sub("#", want):
        return False
    for a, b in zip(NUMBER.findall(got), NUMBER.findall(want), strict=False):
        x, y = float(a), float(b)
        if abs(x - y) > max(1e-12, 1e-9 * abs(y)):
            return False
    return True


def run(example: Example, scratch: Path) -> tuple[str, dict[str, object]]:
    """What the example prints, and its namespace, run in `scratch` (with assets/)."""
    (scratch / "assets").symlink_to(REPO / "assets")
    out = io.StringIO()
    here, path = Path.cwd(), os.environ.get("PATH", "")
    cli = os.environ.get("SCREWKIT_CLI")
    if cli:
        os.environ["PATH"] = str(Path(cli).parent) + os.pathsep + path
    elif "screwkit" in example.code and "subprocess" in example.code:
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    os.chdir(scratch)
    np.set_printoptions(**PRINT_OPTIONS)
    namespace: dict[str, object] = {"__name__": "__docs__"}
    try:
        with contextlib.redirect_stdout(out):
            exec(compile(example.code, example.where, "exec"), namespace)
    finally:
        os.chdir(here)
        os.environ["PATH"] = path
        np.set_printoptions(**PRINT_OPTIONS)
        ray = sys.modules.get("ray")
        if ray is not None and ray.is_initialized():
            ray.shutdown()  # a local Ray the example started: other tests start their own
    return out.getvalue(), namespace


def test_there_are_examples() -> None:
    found = examples()
    assert len(found) >= 12
    assert sum(e.printed is not None for e in found) >= 9


@pytest.mark.parametrize("example", examples(), ids=lambda e: e.where)
def test_example_prints_what_the_page_says(example: Example, tmp_path: Path) -> None:
    got_text, _ = run(example, tmp_path)
    if example.printed is None:
        return  # it ran without an error: that is its check
    got, want = got_text.splitlines(), example.printed.splitlines()
    ok = len(got) == len(want) and all(same(g, w) for g, w in zip(got, want, strict=False))
    if not ok and os.environ.get("SCREWKIT_UPDATE_DOCS") and example.span is not None:
        text = example.doc.read_text()
        start, end = example.span
        assert text[start:end] == example.printed, f"{example.where} changed under the test"
        example.doc.write_text(text[:start] + got_text + text[end:])
        pytest.fail(f"{example.where}: pasted the new output; read it in git diff")
    assert len(got) == len(want), f"{example.where}: {len(got)} lines, the page has {len(want)}"
    for g, w in zip(got, want, strict=False):
        assert same(g, w), f"{example.where}: got\n  {g}\nthe page has\n  {w}"


def test_whole_body_picture_is_current(tmp_path: Path) -> None:
    """docs/talos-whole-body.svg is the `svg` the guide's whole-body example draws; regenerate
    it with SCREWKIT_UPDATE_PICTURES=1 and look at it (a headless-browser screenshot) first."""
    found = [e for e in examples() if "svg = robot.draw(" in e.code]
    assert len(found) == 1, "the guide's whole-body example draws the picture"
    _, namespace = run(found[0], tmp_path)
    svg = namespace["svg"]
    assert isinstance(svg, str) and "<svg" in svg[:200]
    path = REPO / "docs" / "talos-whole-body.svg"
    if os.environ.get("SCREWKIT_UPDATE_PICTURES"):
        path.write_text(svg)
    assert path.read_text() == svg, (
        "docs/talos-whole-body.svg is stale: regenerate it with SCREWKIT_UPDATE_PICTURES=1"
    )


def test_path_joint_plot_is_current(tmp_path: Path) -> None:
    """docs/ur5-path-joints.svg is the plot the guide's screw-path example writes (the UR5 of
    example-robot-data); regenerate it with SCREWKIT_UPDATE_PICTURES=1 and look at it first."""
    found = [e for e in examples() if "robot.plot_joints(path.q, path.place" in e.code]
    assert len(found) == 1, "the guide's screw-path example plots the joints"
    run(found[0], tmp_path)
    svg = (tmp_path / "ur5-path-joints.svg").read_text()
    assert "<svg" in svg[:200] and svg.count('class="joint"') == 6
    path = REPO / "docs" / "ur5-path-joints.svg"
    if os.environ.get("SCREWKIT_UPDATE_PICTURES"):
        path.write_text(svg)
    assert path.read_text() == svg, (
        "docs/ur5-path-joints.svg is stale: regenerate it with SCREWKIT_UPDATE_PICTURES=1"
    )
