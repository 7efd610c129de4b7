"""Loaders of real skid-steer datasets (read in place; never copied into the repository)."""

from ecoplan.datasets.borealtc import (
    BorealRun,
    data_root,
    list_runs,
    list_terrains,
    load_run,
    load_runs,
)

__all__ = ["BorealRun", "data_root", "list_runs", "list_terrains", "load_run", "load_runs"]
