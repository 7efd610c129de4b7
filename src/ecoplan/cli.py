"""The ``ecoplan`` command line (grown by the scenario/CLI issue)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ecoplan.errors import EcoplanError, InputError
from ecoplan.presets import vehicle

__all__ = ["main"]


def _demo(args: argparse.Namespace) -> int:
    params = vehicle("auriga-beta-wide", "marble")
    cases = {
        "1 straight": (0.4, 0.4),
        "2 same sign": (0.8, 0.4),
        "3 one zero": (0.0, 0.4),
        "4 opposite": (-0.4, 0.4),
    }
    for label, (vl, vr) in cases.items():
        p = params.power(vl, vr)
        parts = ", ".join(f"{k[:-2]} {float(v):.0f}" for k, v in p.components().items())
        total = float(p.total_w)
        print(f"case {label:12s} V=({vl:+.1f},{vr:+.1f}) m/s  P_T {total:6.0f} W  [{parts}]")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``ecoplan`` console script; returns the exit code."""
    parser = argparse.ArgumentParser(prog="ecoplan", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="replay the A->B experiment and write its report")
    demo.add_argument("--out", default="reports/demo")
    demo.set_defaults(func=_demo)
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except InputError as exc:
        print(f"ecoplan: error: {exc}", file=sys.stderr)
        return 2
    except EcoplanError as exc:
        print(f"ecoplan: failed: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    raise SystemExit(main())
