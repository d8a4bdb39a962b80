"""Scenario files: a YAML description of axes, a command timeline, recording and checks.

The loader (and with it the schema) is imported at once: the schema and its part modules
import each other, and must be entered through the schema. The runner loads on first use
(PEP 562), so that ``openmotion check`` does not pay for the runtime it never starts.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from openmotion.core.lazy import lazy_exports
from openmotion.examples import (
    Example,
    default_scenario,
    examples_dir,
    find_example,
    list_examples,
    resolve_scenario,
)
from openmotion.scenario.load import Problem, ScenarioError, load_scenario, parse_scenario
from openmotion.scenario.schema import Scenario

_LAZY = {"CheckRow", "CommandRow", "ScenarioResult", "run_scenario"}  #: in scenario/run.py
__all__ = ["CheckRow", "CommandRow", "Example", "Problem", "Scenario", "ScenarioError",
           "ScenarioResult", "default_scenario", "examples_dir", "find_example", "list_examples",
           "load_scenario", "parse_scenario", "resolve_scenario", "run_scenario"]


__getattr__, __dir__ = lazy_exports(__name__, dict.fromkeys(_LAZY, "openmotion.scenario.run"),
                                    __all__)


if TYPE_CHECKING:
    from openmotion.scenario.run import CheckRow, CommandRow, ScenarioResult, run_scenario
