"""``benchmarks/gap_split.py`` never runs a held-out zoo variant and refuses bad case specs.

The tool diagnoses zoo cases to split the final model's held-out gap; variants c, d and g are
held out from development (never run to choose a design), so asking for one must stop with
exit 2 and one line naming the variant, before any case is simulated.  The same for a case
spec that is not ``variant:effect:seed`` or names an unknown effect.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "gap_split.py"


def _run(cases: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), "--cases", cases],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


@pytest.mark.parametrize("variant", ["c", "d", "g"])
def test_held_out_variant_is_refused_before_any_case_runs(variant: str) -> None:
    # a held-out variant after an allowed one: nothing runs (no table header printed)
    out = _run(f"a:none:0,{variant}:none:0")
    assert out.returncode == 2
    assert out.stdout == ""
    last = out.stderr.strip().splitlines()[-1]
    assert f"variant {variant!r}" in last
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize("spec", ["h:inertia", "h:inertia:x", "h:no_such_effect:0"])
def test_malformed_case_is_refused(spec: str) -> None:
    out = _run(spec)
    assert out.returncode == 2
    assert out.stdout == ""
    assert "Traceback" not in out.stderr
