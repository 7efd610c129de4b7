"""Errors from one hierarchy (issue 10 item 6): ecoplan raises its own errors, the CLI maps them.

Bad input is an :class:`~ecoplan.errors.InputError` (exit code 2, one line); a failure on valid
input another :class:`~ecoplan.errors.EcoplanError` (exit code 1).  Built-in exceptions are
raised only inside pydantic validators, which pydantic turns into a ``ValidationError`` that the
readers word as one line.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import ecoplan
from ecoplan.cli import main
from ecoplan.dynamics.rollout import MAX_ROLLOUT_STEPS, rollout
from ecoplan.errors import EcoplanError, InputError
from ecoplan.presets import vehicle

SRC = Path(ecoplan.__file__).parent

#: Built-in exceptions that would escape the hierarchy.
BUILTIN = {"ValueError", "TypeError", "RuntimeError", "KeyError", "IndexError", "Exception"}
#: Helpers that only pydantic validators call (their ValueError becomes a ValidationError).
VALIDATOR_HELPERS = {"_nonneg", "_check_terrain"}


def _builtin_raises(tree: ast.AST) -> list[tuple[int, str]]:
    """``(line, exception)`` of each built-in raise outside a validator (found by walking)."""
    found: list[tuple[int, str]] = []

    def visit(node: ast.AST, in_validator: bool) -> None:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            decorators = [ast.unparse(d) for d in node.decorator_list]
            in_validator = (
                in_validator
                or node.name in VALIDATOR_HELPERS
                or any("_validator" in d for d in decorators)
            )
        if isinstance(node, ast.Raise) and node.exc is not None and not in_validator:
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            if isinstance(exc, ast.Name) and exc.id in BUILTIN:
                found.append((node.lineno, exc.id))
        for child in ast.iter_child_nodes(node):
            visit(child, in_validator)

    visit(tree, False)
    return found


def test_the_walker_finds_a_builtin_raise_and_spares_a_validator() -> None:
    code = """
def f(x):
    raise ValueError("x")
class M:
    @model_validator(mode="after")
    def check(self):
        raise ValueError("pydantic words this one")
def g():
    raise InputError("fine")
"""
    assert _builtin_raises(ast.parse(code)) == [(3, "ValueError")]


def test_no_module_raises_a_builtin_exception_outside_a_validator() -> None:
    offenders = [
        f"{path.relative_to(SRC)}:{line}: raise {name}"
        for path in sorted(SRC.rglob("*.py"))
        for line, name in _builtin_raises(ast.parse(path.read_text(encoding="utf-8")))
    ]
    # raise an ecoplan error instead; a helper only pydantic validators call goes in
    # VALIDATOR_HELPERS
    assert offenders == []


def test_the_hierarchy_keeps_value_error_for_callers_that_catch_it() -> None:
    # InputError is also a ValueError, so `except ValueError` around ecoplan still works
    assert issubclass(InputError, ValueError) and issubclass(InputError, EcoplanError)


class _Still:
    """A policy that never stops (the rollout runs to its time limit)."""

    stopped = np.zeros(1, dtype=bool)

    def command(self, x: np.ndarray, y: np.ndarray, yaw: np.ndarray) -> tuple[np.ndarray, ...]:
        return np.zeros_like(x), np.zeros_like(x)


def test_a_rollout_too_long_to_run_is_refused_before_it_starts() -> None:
    params = [vehicle("auriga-beta-wide", "asphalt")]
    pose = np.zeros((1, 3))
    dt = 1e-3
    t_max = (MAX_ROLLOUT_STEPS + 10) * dt  # just over the limit: refused
    with pytest.raises(InputError, match=r"simulation\.dt_s"):
        rollout(params, _Still(), pose, dt, t_max)
    rows, end, finished = rollout(params, _Still(), pose, dt, 50 * dt)  # well under: runs
    assert rows.shape[0] == 51 and not finished[0] and end[0] == 50


SCENARIO = """\
name: tiny-step
vehicle: {preset: auriga-beta-wide}
terrain: asphalt
map: {bounds: {min: [-1, -3], max: [21, 3]}}
start: {x: 0, y: 0}
waypoints: [[20, 0]]
simulation: {dt_s: %s}
"""


@pytest.mark.parametrize(
    ("dt", "code", "message"),
    [
        ("1e-7", 2, "raise the time step (simulation.dt_s)"),  # 20 m: >1e7 steps, refused
        ("0", 2, "simulation.dt_s: expected a number > 0"),
        ("fast", 2, "simulation.dt_s: expected a number"),
    ],
)
def test_cli_exit_codes_of_bad_simulation_steps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], dt: str, code: int, message: str
) -> None:
    scenario = tmp_path / "s.yaml"
    scenario.write_text(SCENARIO % dt)
    assert main(["run", str(scenario)]) == code
    err = capsys.readouterr().err.strip()
    assert err.startswith("ecoplan: error: ") and message in err and "\n" not in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["diagnose", "{log}", "--vehicle", "rover-9"], "rover-9"),
        (["diagnose", "{log}", "--vehicle", "pioneer-3at", "--terrain", "mud"], "mud"),
        (["diagnose", "{log}", "--vehicle", "pioneer-3at", "--bus-voltage", "0"], "--bus-voltage"),
        (["identify", "{log}", "--base", "rover-9"], "rover-9"),
    ],
)
def test_cli_exit_2_for_bad_names_in_diagnose_and_identify(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    log = tmp_path / "a.csv"
    rows = [f"{0.1 * i:.1f},0.3,0.3,{100 + i % 7}" for i in range(200)]
    log.write_text("t,v_left,v_right,p_total\n" + "\n".join(rows) + "\n")
    assert main([a.replace("{log}", str(log)) for a in argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("ecoplan: error: ") and message in err and "\n" not in err


@pytest.mark.parametrize("name", ["auriga-beta-wide", "pioneer-3at"])
@pytest.mark.parametrize(
    ("v_left", "v_right", "message"),
    [
        ("fast", 0.1, "v_left must be numbers"),
        ([0.1, [0.2, 0.3]], 0.1, "v_left must be numbers"),
        (np.zeros(3), np.zeros(4), r"shapes \(3,\) and \(4,\), which do not broadcast"),
        (0.1, np.inf, "v_right must be finite"),
    ],
)
def test_power_of_bad_speeds_is_an_input_error(
    name: str, v_left: object, v_right: object, message: str
) -> None:
    params = vehicle(name, None)
    with pytest.raises(InputError, match=message):
        params.power(v_left, v_right)  # type: ignore[arg-type]


def test_only_the_command_line_prints() -> None:
    # library code returns text; the CLI (and the console helper it prints through) prints it
    allowed = {Path("cli.py"), Path("app/console.py")}
    printing = sorted(
        f"{path.relative_to(SRC)}:{node.lineno}"
        for path in SRC.rglob("*.py")
        if path.relative_to(SRC) not in allowed
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        if isinstance(node, ast.Call) and ast.unparse(node.func) == "print"
    )
    assert printing == []
