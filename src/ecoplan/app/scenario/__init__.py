"""Scenario files: schema (:mod:`.schema`), loading (:mod:`.load`), building (:mod:`.build`).

Running the built cases is :mod:`ecoplan.app.run`.
"""

from ecoplan.app.scenario.build import Case, Scenario, build_scenario
from ecoplan.app.scenario.load import load_scenario, parse_scenario
from ecoplan.app.scenario.schema import ScenarioSpec

__all__ = ["Case", "Scenario", "ScenarioSpec", "build_scenario", "load_scenario", "parse_scenario"]
