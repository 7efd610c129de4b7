"""The README's Python examples run as written, and its figures and files exist."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
BLOCKS = re.findall(r"```python\n(.*?)```", README, re.S)


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{i}" for i in range(len(BLOCKS))])
def test_python_example_runs(code: str) -> None:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        exec(compile(code, "README.md", "exec"), {"__name__": "__readme__"})
    assert buf.getvalue().strip()  # every example prints what it shows


def test_quick_start_comments_match_the_models() -> None:
    # the numbers the quick start quotes in its comments are what the code prints
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        exec(compile(BLOCKS[0], "README.md", "exec"), {"__name__": "__readme__"})
    total, share = (float(x) for x in buf.getvalue().splitlines()[0].split())
    assert "≈ 2509 W, 63 % dynamic friction" in BLOCKS[0]
    assert total == pytest.approx(2509, abs=1) and share == pytest.approx(0.63, abs=0.005)


def test_linked_files_exist() -> None:
    for target in re.findall(r"\]\(([^)#]+)\)", README):
        if "://" not in target:
            assert (ROOT / target).exists(), target
