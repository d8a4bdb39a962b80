"""Scenario files: a YAML description of axes, a command timeline, recording and checks."""

from openmotion.scenario.load import (
    Problem,
    ScenarioError,
    default_scenario,
    examples_dir,
    load_scenario,
    parse_scenario,
)
from openmotion.scenario.run import CheckRow, CommandRow, ScenarioResult, run_scenario
from openmotion.scenario.schema import Scenario

__all__ = ["CheckRow", "CommandRow", "Problem", "Scenario", "ScenarioError", "ScenarioResult",
           "default_scenario", "examples_dir", "load_scenario", "parse_scenario", "run_scenario"]
