"""The ``ecoplan`` command line: scenario runs, comparisons, diagnosis, benchmarks.

Exit codes: 0 success, 2 bad input (a scenario, a log, an argument: one-line message on
stderr, never a traceback), 1 failure on valid input (no route within the budget).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any

from ecoplan.app.console import CommandOutput, progress
from ecoplan.errors import EcoplanError, InputError

__all__ = ["main"]

_EPILOG = """\
examples:
  ecoplan run scenarios/ab_obstacle.yaml --out reports/ab
  ecoplan plan scenarios/cluttered_ompl.yaml --json
  ecoplan simulate scenarios/ab_obstacle.yaml --waypoints 25,10 50,0
  ecoplan compare scenarios/ab_obstacle.yaml --out reports/ab-compare --workers 2
  ecoplan compare scenarios/cluttered_ompl.yaml --scheduler tcp://10.0.0.5:8786
  ecoplan diagnose run1.csv run2.csv --vehicle auriga-beta-wide --json gap.json --out rep/
  ecoplan bench scenarios/cluttered_ompl.yaml --planners graph,ompl:RRTstar --seeds 3
  ecoplan demo --out reports/demo

Report folders (--out): a new or empty folder is created; a folder ecoplan wrote before
is updated in place (only its own files are replaced); any other non-empty folder is
refused unless --force.  --json prints machine-readable results on stdout (or writes
them to FILE) and turns the progress bar off.
exit codes: 0 ok, 2 bad input, 1 failure on valid input.
"""


# ------------------------------------------------------------------ output helpers


def _out(args: argparse.Namespace) -> CommandOutput:
    return CommandOutput(getattr(args, "json", None), quiet=getattr(args, "quiet", False))


def _progress(
    args: argparse.Namespace, label: str, total: int
) -> AbstractContextManager[Callable[[int, int], None]]:
    """A progress bar on stderr unless --json or --quiet."""
    quiet = getattr(args, "json", None) is not None or getattr(args, "quiet", False)
    return progress(not quiet, label, total)


# ----------------------------------------------------------------------- commands


def _load(args: argparse.Namespace) -> Any:
    from ecoplan.app.scenario import load_scenario
    from ecoplan.app.scenario.load import with_vehicle

    sc = load_scenario(args.scenario)
    if getattr(args, "vehicle", None):
        sc = with_vehicle(sc, args.vehicle)
    return sc


def _budget(args: argparse.Namespace) -> float | None:
    b = getattr(args, "time_budget", None)
    if b is not None and not (b > 0 and b < 1e6):
        raise InputError(f"--time-budget {b}: expected a number of seconds > 0")
    return b


def _prepare(args: argparse.Namespace) -> Any:
    """The --out folder (checked against the overwrite policy), or None without --out."""
    if not getattr(args, "out", None):
        return None
    from ecoplan.app.outdir import prepare_out_dir

    return prepare_out_dir(args.out, force=args.force)


def _report(
    args: argparse.Namespace,
    sc: Any,
    results: Sequence[Any],
    out: CommandOutput,
    *,
    quiet: bool = False,
    **kw: Any,
) -> list[Path]:
    folder = _prepare(args)  # already checked when the command started
    if folder is None:
        return []
    from ecoplan.app.reports.scenario import write_report

    files = write_report(sc, results, folder, force=args.force, **kw)
    if not quiet:
        _print_files(out, args, files)
    return files


def _cmd_run(args: argparse.Namespace) -> int:
    from ecoplan.app.run import plan_case, simulate_case

    out = _out(args)
    sc = _load(args)
    _prepare(args)
    case = sc.base_case()
    steps = 3 if args.out else 2
    with _progress(args, f"{sc.name}: plan, simulate, report", steps) as tick:
        plan = plan_case(case, time_budget_s=_budget(args))
        tick(1, steps)
        result = simulate_case(case, plan)
        tick(2, steps)
        files = _report(args, sc, [result], out, quiet=True)
        tick(steps, steps)
    _print_case(out, result)
    _print_files(out, args, files)
    out.emit({"scenario": sc.name, "case": result.summary(), "files": files})
    return 0


def _print_files(out: CommandOutput, args: argparse.Namespace, files: Sequence[Path]) -> None:
    if files:
        out.say(f"report written to {args.out}/ ({len(files)} files):")
        for f in files:
            out.say(f"  {f}")


def _print_case(out: CommandOutput, r: Any) -> None:
    from ecoplan.app.reports.tables import case_lines

    for line in case_lines(r):
        out.say(line)


def _cmd_plan(args: argparse.Namespace) -> int:
    from ecoplan.app.reports.tables import plan_lines
    from ecoplan.app.run import CaseResult, plan_case

    out = _out(args)
    sc = _load(args)
    _prepare(args)
    case = sc.base_case()
    plan = plan_case(case, time_budget_s=_budget(args))
    for line in plan_lines(sc.name, plan):
        out.say(line)
    out.emit(
        {
            "scenario": sc.name,
            "planner": plan.planner,
            "waypoints": plan.waypoints.tolist(),
            "speed_mps": plan.speed_mps,
            "length_m": plan.length_m,
            "planning_time_s": plan.planning_time_s,
            "estimate_energy_j": plan.estimate_energy_j,
            "alternatives": [a.tolist() for a in plan.alternatives],
            "files": [
                str(f)
                for f in _report(args, sc, [CaseResult.unsimulated(case.name, plan)], out)
                + _route_files(args, plan, out)
            ],
        }
    )
    return 0


def _route_files(args: argparse.Namespace, plan: Any, out: CommandOutput) -> list[Path]:
    """``plan --out``: the route as a nav_msgs/Path bag (MCAP), GeoJSON and CSV."""
    folder = _prepare(args)
    if folder is None:
        return []
    from ecoplan.app.reports.route import write_route_files

    files = write_route_files(folder, plan, force=args.force)
    for f in files:
        out.say(f"  {f}")
    return files


def _parse_points(items: Sequence[str]) -> list[list[float]]:
    import math

    pts = []
    for item in items:
        try:
            x, y = (float(v) for v in item.split(","))
        except ValueError:
            raise InputError(f"--waypoints {item!r}: expected X,Y (two numbers)") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(f"--waypoints {item!r}: coordinates must be finite")
        pts.append([x, y])
    return pts


def _cmd_simulate(args: argparse.Namespace) -> int:
    from ecoplan.app.run import simulate_case
    from ecoplan.app.scenario.load import with_waypoints

    out = _out(args)
    sc = _load(args)
    if args.waypoints:
        sc = with_waypoints(sc, _parse_points(args.waypoints))
    _prepare(args)
    case = sc.base_case()
    if case.planner.type != "none":
        raise InputError(
            f"{sc.source}: simulate needs fixed waypoints (in the file or --waypoints X,Y ...); "
            "use `ecoplan run` to plan first"
        )
    result = simulate_case(case)
    _print_case(out, result)
    files = _report(args, sc, [result], out)
    out.emit({"scenario": sc.name, "case": result.summary(), "files": files})
    return 0


def _cmd_compare(args: argparse.Namespace) -> int:
    from functools import partial

    from ecoplan.app.executor import make_executor
    from ecoplan.app.reports.tables import summary_table
    from ecoplan.app.run import cheapest, run_case

    out = _out(args)
    sc = _load(args)
    cases = sc.cases()
    if len(cases) < 2:
        raise InputError(f"{sc.source}: compare needs a `compare:` list of at least two variants")
    _prepare(args)
    task = partial(run_case, time_budget_s=_budget(args))
    with make_executor(args.scheduler, args.workers) as ex:
        with _progress(args, f"{len(cases)} cases on {ex.description}", len(cases)) as tick:
            results = ex.map(task, cases, on_done=tick)
        where = ex.description
    for r in results:
        _print_case(out, r)
    out.say()
    out.say(summary_table(results))
    files = _report(args, sc, results, out, title=f"{sc.name}: comparison", executor=where)
    best = cheapest(results, sc.source)
    out.emit(
        {
            "scenario": sc.name,
            "executor": where,
            "best": best.name,
            "cases": [r.summary() for r in results],
            "files": files,
        }
    )
    return 0


def _cmd_diagnose(args: argparse.Namespace) -> int:
    try:
        from ecoplan.app.diagnose import diagnose_logs
    except ImportError:
        raise EcoplanError(
            "diagnosis is not available in this build (ecoplan.app.diagnose)"
        ) from None
    if args.json is not None and args.json != "-":
        target = Path(args.json)
        if target.suffix.lower() != ".json" or any(
            target.resolve() == Path(str(log)).resolve() for log in args.logs
        ):
            raise InputError(
                f"--json {target}: expected a new .json file name (it would overwrite a log or "
                "another file); put --json FILE after the logs"
            )
    out = _out(args)
    folder = _prepare(args)
    routes = None
    if args.scenario is not None:  # checked before the diagnosis starts
        from ecoplan.app.run import candidate_routes

        routes = candidate_routes(args.scenario, args.vehicle, args.terrain)
    with contextlib.nullcontext() if folder is None else folder.recording():
        run = diagnose_logs(
            [str(p) for p in args.logs],
            args.vehicle,
            args.terrain,
            out_dir=None if folder is None else folder.path,
            topics_path=None if args.topics is None else str(args.topics),
            bus_voltage_v=args.bus_voltage,
            routes=routes,
            pose_frame=args.pose_frame,
        )
    for line in run.lines:
        out.say(line)
    for what, path in run.files:
        out.say(f"{what}: {path}")
    out.emit(run.report)  # --json -: the JSON alone on stdout, the lines above on stderr
    if folder is not None:
        folder.finish()
    return 0


def _cmd_identify(args: argparse.Namespace) -> int:
    from ecoplan.app.identify import identify_from_logs
    from ecoplan.app.reports.identify import identification_lines, identification_rows

    out = _out(args)
    if args.out is not None and args.out.exists() and not args.force:
        raise InputError(f"{args.out} exists; give --force to overwrite it")
    res = identify_from_logs(
        [str(p) for p in args.logs],
        args.base,
        terrain=args.terrain,
        name=args.name,
        clamp=args.clamp,
        n_boot=args.boot,
        speed_noise_mps=args.speed_noise,
        bus_voltage_v=args.bus_voltage,
    )
    for line in identification_lines(res):
        out.say(line)
    header = f"Identified by: ecoplan identify {' '.join(str(p) for p in args.logs)}"
    text = res.to_yaml(header + f" --base {args.base}")
    if args.out is not None:
        args.out.write_text(text, encoding="utf-8")
        out.say(f"vehicle file written to {args.out}")
    elif args.json is None:
        sys.stdout.write(text)
    out.emit({"vehicle": res.name, "terrains": identification_rows(res), "file": args.out})
    return 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from ecoplan.app.bench import (
        bench_cases,
        parse_planners,
        run_bench_case,
        summarise,
        write_bench,
    )
    from ecoplan.app.executor import make_executor

    out = _out(args)
    planners = parse_planners(args.planners)
    cases = bench_cases(args.scenarios, planners, args.seeds, args.time, args.vehicle)
    folder = _prepare(args)
    with make_executor(args.scheduler, args.workers) as ex:
        with _progress(args, f"{len(cases)} cases on {ex.description}", len(cases)) as tick:
            runs = ex.map(run_bench_case, cases, on_done=tick)
        where = ex.description
    summary = summarise(runs)
    out.say(f"bench: {len(cases)} cases on {where}")
    out.say(summary.table)
    files: list[Path] = []
    if folder is not None:
        files = write_bench(folder, runs, summary, where, force=args.force)
        out.say(f"bench written to {folder.path}/")
    out.emit({"executor": where, "summary": summary.rows, "runs": runs, "files": files})
    return 0


def _cmd_demo(args: argparse.Namespace) -> int:
    from ecoplan.app.outdir import prepare_out_dir
    from ecoplan.experiments.ab_replay import run_demo

    out = _out(args)
    folder = prepare_out_dir(args.out, force=args.force)
    files = [Path(p) for p in run_demo(folder.path)]
    folder.written.extend(files)
    folder.finish()
    out.say(f"A->B replay report written to {folder.path}/:")
    for f in files:
        out.say(f"  {f}")
    out.emit({"files": files})
    return 0


# ------------------------------------------------------------------------- parser


def _common(p: argparse.ArgumentParser, *, out: bool = True) -> None:
    p.add_argument(
        "--json",
        nargs="?",
        const="-",
        metavar="FILE",
        help="machine-readable results on stdout, or into FILE",
    )
    if out:
        p.add_argument(
            "--out", metavar="DIR", help="write the report (figures, CSV, markdown) here"
        )
        p.add_argument(
            "--force",
            action="store_true",
            help="write into a non-empty folder ecoplan did not create",
        )
    p.add_argument("-q", "--quiet", action="store_true", help="no human-readable output")


def _vehicle_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--vehicle",
        metavar="FILE",
        help="drive this vehicle file, corrected model (.json) or preset instead of the "
        "scenario's vehicle",
    )


def _sweep(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--scheduler",
        metavar="ADDR",
        help="Dask scheduler address (tcp://host:8786); default: processes on this machine",
    )
    p.add_argument(
        "--workers", type=int, metavar="N", help="local worker processes (default: all cores)"
    )


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``ecoplan`` (exposed for documentation and tests)."""
    fmt = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(
        prog="ecoplan",
        description="Energy-aware planning and simulation for skid-steer robots.",
        epilog=_EPILOG,
        formatter_class=fmt,
    )
    from ecoplan import __version__

    parser.add_argument("--version", action="version", version=f"ecoplan {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    run = sub.add_parser(
        "run",
        help="plan, simulate and report a scenario",
        formatter_class=fmt,
        epilog="example:\n  ecoplan run scenarios/battery_mission.yaml --out reports/mission",
    )
    run.add_argument("scenario", type=Path, help="scenario YAML file")
    run.add_argument(
        "--time-budget",
        type=float,
        metavar="S",
        help="planner time budget [s] (replaces planner.time_s)",
    )
    _common(run)
    _vehicle_option(run)
    run.set_defaults(func=_cmd_run)

    plan = sub.add_parser(
        "plan",
        help="plan a scenario's route (no simulation)",
        formatter_class=fmt,
        epilog="example:\n  ecoplan plan scenarios/pioneer_power_limit.yaml --json",
    )
    plan.add_argument("scenario", type=Path)
    plan.add_argument(
        "--time-budget",
        type=float,
        metavar="S",
        help="planner time budget [s] (replaces planner.time_s)",
    )
    _common(plan)
    _vehicle_option(plan)
    plan.set_defaults(func=_cmd_plan)

    sim = sub.add_parser(
        "simulate",
        help="simulate fixed waypoints with the heading controller",
        formatter_class=fmt,
        epilog="example:\n  ecoplan simulate scenarios/ab_obstacle.yaml "
        "--waypoints 20,12 32,12 50,0",
    )
    sim.add_argument("scenario", type=Path)
    sim.add_argument(
        "--waypoints", nargs="+", metavar="X,Y", help="replace the waypoints (after the start)"
    )
    _common(sim)
    _vehicle_option(sim)
    sim.set_defaults(func=_cmd_simulate)

    cmp_ = sub.add_parser(
        "compare",
        help="run a scenario's compare variants side by side",
        formatter_class=fmt,
        epilog="example:\n  ecoplan compare scenarios/ab_obstacle.yaml "
        "--out reports/ab --workers 2",
    )
    cmp_.add_argument("scenario", type=Path)
    cmp_.add_argument("--time-budget", type=float, metavar="S")
    _sweep(cmp_)
    _common(cmp_)
    _vehicle_option(cmp_)
    cmp_.set_defaults(func=_cmd_compare)

    diag = sub.add_parser(
        "diagnose",
        help="locate and explain the sim-to-real gap of logs",
        formatter_class=fmt,
        epilog="examples:\n  ecoplan diagnose run1.csv --vehicle pioneer-3at "
        "--json gap.json --out rep/\n"
        "  ecoplan diagnose borealtc:FLOORING --vehicle pioneer-3at --bus-voltage 24\n"
        "  ecoplan diagnose bag/ --topics husky.topics.yaml --vehicle pioneer-3at\n"
        "  ecoplan diagnose run*.csv --vehicle auriga-beta-wide "
        "--scenario scenarios/ab_obstacle.yaml\n\n"
        "LOG is a CSV in the ecoplan log format (README), borealtc:TERRAIN[/RUN], or a ROS 2\n"
        "bag (with --topics, or <bag>.topics.yaml beside it).",
    )
    diag.add_argument("logs", nargs="+", type=Path, metavar="LOG")
    diag.add_argument(
        "--vehicle", required=True, help="vehicle preset (e.g. auriga-beta-wide) or vehicle file"
    )
    diag.add_argument("--terrain", help="terrain preset")
    diag.add_argument(
        "--json", metavar="FILE", help="write the diagnosis JSON here ('-': on stdout)"
    )
    diag.add_argument("--out", metavar="DIR", help="write plots and the summary here")
    diag.add_argument(
        "--scenario",
        type=Path,
        metavar="FILE",
        help="rank this scenario's candidate routes under the preset and the corrected model",
    )
    diag.add_argument(
        "--topics", type=Path, metavar="FILE", help="topic map (YAML) for ROS 2 bag logs"
    )
    diag.add_argument(
        "--bus-voltage",
        type=float,
        default=24.0,
        metavar="V",
        help="bus voltage assumed for borealtc:TERRAIN[/RUN] logs (default 24 V)",
    )
    diag.add_argument(
        "--pose-frame",
        choices=("world", "run"),
        help="where every log's pose is, instead of its '# pose_frame:' line: one frame for "
        "all runs (world) or each run's own (run: odometry restarted with every run)",
    )
    diag.add_argument(
        "--force", action="store_true", help="write into a non-empty folder ecoplan did not create"
    )
    diag.set_defaults(func=_cmd_diagnose)

    ident = sub.add_parser(
        "identify",
        help="identify a vehicle file from your logs (per terrain)",
        formatter_class=fmt,
        epilog="examples:\n  ecoplan identify borealtc:ASPHALT borealtc:SNOW --base husky-a200 "
        "--clamp --out husky.yaml\n"
        "  ecoplan identify run*.csv --base robot.yaml --terrain gravel --out robot.yaml\n\n"
        "LOG is a CSV in the ecoplan log format (with a terrain column, or one terrain\n"
        "given by --terrain), borealtc:TERRAIN[/RUN], or a ROS 2 bag. With a base whose\n"
        "logs are motor currents (power_log: motor_current), optional columns current_left,\n"
        "current_right [A] give each side's current; without them p_total is their sum.",
    )
    ident.add_argument("logs", nargs="+", type=Path, metavar="LOG")
    ident.add_argument(
        "--base", required=True, help="vehicle file or preset: geometry, mass, fixed values"
    )
    ident.add_argument("--out", type=Path, metavar="FILE", help="write the vehicle file here")
    ident.add_argument("--force", action="store_true", help="overwrite --out")
    ident.add_argument("--name", help="name of the identified vehicle (default: the base's)")
    ident.add_argument("--terrain", help="terrain of logs without a terrain column")
    ident.add_argument(
        "--clamp",
        action="store_true",
        help="hold parameters the logs drive negative at 0 instead of refusing",
    )
    ident.add_argument("--boot", type=int, default=200, help="bootstrap resamples (default 200)")
    ident.add_argument(
        "--speed-noise",
        type=float,
        default=0.005,
        metavar="MPS",
        help="encoder noise of the side speeds [m/s] (default 0.005; 0 = no correction)",
    )
    ident.add_argument(
        "--bus-voltage", type=float, default=24.0, metavar="V", help="for borealtc: sources"
    )
    ident.add_argument("--json", nargs="?", const="-", metavar="FILE")
    ident.add_argument("-q", "--quiet", action="store_true")
    ident.set_defaults(func=_cmd_identify)

    bench = sub.add_parser(
        "bench",
        help="planners x seeds on scenarios, through the executor",
        formatter_class=fmt,
        epilog="example:\n  ecoplan bench scenarios/cluttered_ompl.yaml "
        "--planners graph,ompl:RRTstar",
    )
    bench.add_argument("scenarios", nargs="+", type=Path, metavar="SCENARIO")
    bench.add_argument("--planners", default="graph", help="comma list: graph, ompl:<name>")
    bench.add_argument("--seeds", type=int, default=3, help="seeds per OMPL planner")
    bench.add_argument("--time", type=float, default=1.0, help="planner time budget [s]")
    _vehicle_option(bench)
    _sweep(bench)
    _common(bench)
    bench.set_defaults(func=_cmd_bench)

    demo = sub.add_parser("demo", help="replay the A->B experiment and write its report")
    demo.add_argument("--out", default="reports/demo", metavar="DIR")
    demo.add_argument(
        "--force", action="store_true", help="write into a non-empty folder ecoplan did not create"
    )
    demo.add_argument("--json", nargs="?", const="-", metavar="FILE")
    demo.add_argument("-q", "--quiet", action="store_true")
    demo.set_defaults(func=_cmd_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``ecoplan`` console script; returns the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help (0) or a usage error (2, message already printed)
        return int(exc.code) if isinstance(exc.code, int) else 2
    try:
        return int(args.func(args))
    except InputError as exc:
        print(f"ecoplan: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except EcoplanError as exc:
        print(f"ecoplan: failed: {_one_line(exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("ecoplan: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug: one line unless the user asks for the traceback
        if os.environ.get("ECOPLAN_DEBUG"):
            raise
        print(
            f"ecoplan: internal error: {type(exc).__name__}: {_one_line(exc)} "
            "(set ECOPLAN_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return 1


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


if __name__ == "__main__":
    raise SystemExit(main())
