"""The README's Python examples are real: every ```python block followed by "prints (a real
run):" and a ```text block is run from the repository root, and what it prints must be that
block, line for line, numbers to 1e-9 relative (1e-12 absolute: an IK residual of 3e-15 is
noise, not a result).
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import pytest

from conftest import REPO

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def examples() -> list[tuple[int, str, str]]:
    """(line number, code, printed) of each checked example."""
    text = (REPO / "README.md").read_text()
    pattern = re.compile(
        r"```python\n((?:[^`]|`(?!``))*)```\n\s*prints \(a real run\):\s*\n```text\n(.*?)```",
        re.DOTALL,
    )
    return [(text[: m.start()].count("\n") + 1, m[1], m[2]) for m in pattern.finditer(text)]


def same(got: str, want: str) -> bool:
    """Equal text outside the numbers, and equal numbers within the tolerances."""
    if NUMBER.sub("#", got) != NUMBER.sub("#", want):
        return False
    for a, b in zip(NUMBER.findall(got), NUMBER.findall(want)):
        x, y = float(a), float(b)
        if abs(x - y) > max(1e-12, 1e-9 * abs(y)):
            return False
    return True


def test_there_are_examples() -> None:
    assert len(examples()) >= 2


@pytest.mark.parametrize("line, code, printed", examples(), ids=lambda x: str(x)[:12])
def test_readme_example_prints_what_the_readme_says(line: int, code: str, printed: str) -> None:
    out = io.StringIO()
    here = Path.cwd()
    os.chdir(REPO)
    try:
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"README.md:{line}", "exec"), {"__name__": "__readme__"})
    finally:
        os.chdir(here)
    got, want = out.getvalue().splitlines(), printed.splitlines()
    assert len(got) == len(want), f"README.md:{line}: {len(got)} lines, the README has {len(want)}"
    for g, w in zip(got, want):
        assert same(g, w), f"README.md:{line}: got\n  {g}\nthe README has\n  {w}"


def test_readme_whole_body_picture_is_current() -> None:
    """docs/talos-whole-body.svg is the `svg` the README's whole-body example draws; regenerate
    it with SCREWKIT_UPDATE_PICTURES=1 and look at it (a headless-browser screenshot) first."""
    found = [(line, code) for line, code, _ in examples() if "svg = robot.draw(" in code]
    assert len(found) == 1, "the README's whole-body example draws the picture"
    line, code = found[0]
    namespace: dict[str, object] = {"__name__": "__readme__"}
    here = Path.cwd()
    os.chdir(REPO)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            exec(compile(code, f"README.md:{line}", "exec"), namespace)
    finally:
        os.chdir(here)
    svg = namespace["svg"]
    assert isinstance(svg, str) and "<svg" in svg[:200]
    path = REPO / "docs" / "talos-whole-body.svg"
    if os.environ.get("SCREWKIT_UPDATE_PICTURES"):
        path.write_text(svg)
    assert path.read_text() == svg, (
        "docs/talos-whole-body.svg is stale: regenerate it with SCREWKIT_UPDATE_PICTURES=1"
    )
