"""One exception hierarchy for ecoplan.

The command line maps :class:`InputError` (and subclasses) to exit code 2 and
every other :class:`EcoplanError` to exit code 1.
"""

from __future__ import annotations

__all__ = [
    "EcoplanError",
    "InfeasibleError",
    "InputError",
    "LogFormatError",
    "PlanningError",
    "ScenarioError",
]


class EcoplanError(Exception):
    """Base class of every error ecoplan raises on purpose."""


class InputError(EcoplanError, ValueError):
    """The user gave something invalid: a parameter, a file, a request (exit code 2)."""


class InfeasibleError(InputError):
    """A request violates a vehicle constraint; the message names the constraint."""


class ScenarioError(InputError):
    """A scenario file is invalid; the message names the file, line and field."""


class LogFormatError(InputError):
    """A log file is malformed; the message names the column or row."""


class PlanningError(EcoplanError):
    """A planner failed (no path found within its budget) on valid input (exit code 1)."""
