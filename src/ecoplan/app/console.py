"""Where a command's output goes: human lines, the ``--json`` payload, a progress bar.

Used by :mod:`ecoplan.cli`; human text goes to stdout, or to stderr when stdout carries
the JSON payload (``--json`` without a file), so the JSON stays machine-readable.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

from ecoplan.errors import InputError

__all__ = ["CommandOutput", "json_default", "progress"]


def json_default(obj: Any) -> Any:
    """JSON form of values ``json`` does not know: arrays as lists, paths and others as text.

    Parameters
    ----------
    obj : object
        The value.

    Returns
    -------
    list or str

    Examples
    --------
    >>> import numpy as np
    >>> json_default(np.array([1.0, 2.0])), json_default(Path("a/b"))
    ([1.0, 2.0], 'a/b')
    """
    if hasattr(obj, "tolist"):
        return obj.tolist()
    return str(obj)


@dataclass
class CommandOutput:
    """Where human text and JSON go for one command.

    Attributes
    ----------
    json_target : str or None
        ``"-"`` (JSON on stdout), a file name, or None (no JSON).
    quiet : bool
        No human-readable lines.
    """

    json_target: str | None
    quiet: bool = False

    @property
    def json_to_stdout(self) -> bool:
        """True when the JSON payload goes to stdout."""
        return self.json_target == "-"

    def say(self, text: str = "") -> None:
        """Human-readable line: stdout, or stderr when stdout carries JSON."""
        if self.quiet:
            return
        stream: IO[str] = sys.stderr if self.json_to_stdout else sys.stdout
        print(text, file=stream)

    def emit(self, payload: Any) -> None:
        """Write the JSON payload if ``--json`` was given.

        Raises
        ------
        InputError
            The target looks like a scenario (``.yaml``) or cannot be written.
        """
        if self.json_target is None:
            return
        text = json.dumps(payload, indent=1, default=json_default)
        if self.json_to_stdout:
            print(text)
            return
        path = Path(self.json_target)
        if path.suffix in (".yaml", ".yml"):
            raise InputError(
                f"--json {path}: looks like a scenario; put --json after the scenario "
                "or give it a .json file name"
            )
        try:
            path.write_text(text + "\n")
        except OSError as exc:
            raise InputError(f"--json {path}: cannot write: {exc.strerror or exc}") from None
        self.say(f"JSON written to {path}")


@contextmanager
def progress(enabled: bool, label: str, total: int) -> Iterator[Callable[[int, int], None]]:
    """A rich progress bar on stderr, yielding ``tick(done, total)``.

    Parameters
    ----------
    enabled : bool
        Whether the caller wants a bar (off for ``--json`` and ``--quiet``); it is also off
        when stderr is not a terminal or there is at most one step.
    label : str
        Text before the bar.
    total : int
        Number of steps.
    """
    if not (enabled and sys.stderr.isatty() and total > 1):
        yield lambda done, total: None
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task(label, total=total)
        yield lambda done, total: bar.update(task, completed=done, total=total)
