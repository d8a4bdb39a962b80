"""A scenario stepped live: a runtime, whether it has ended, and the signals to show first.

``scenario_machine`` sets a scenario file up as ``run_scenario`` does (objects, timeline,
checks) but leaves the stepping to its caller (the viewer's session, the endpoints' host),
cycle by cycle, and offers the run's own end rule, so a scenario ends in the viewer at the
cycle it ends in ``openmotion run``. The trace recorder is left out: a live run keeps no trace.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from openmotion.runtime.runtime import Runtime
from openmotion.scenario.load import load_scenario
from openmotion.scenario.run import ScenarioRun
from openmotion.scenario.schema import Scenario


def _never() -> bool:
    return False


@dataclass
class Machine:
    """A runtime and how the session treats it."""

    runtime: Runtime
    name: str = "runtime"
    finished: Callable[[], bool] = _never  #: asked once before every cycle
    signals: list[str] = field(default_factory=list)  #: scope signals selected at the start


def scenario_machine(source: str | Path | Scenario) -> Machine:
    """A scenario file (or model) ready to step; raises ``ConfigError`` as ``run_scenario``."""
    scenario = source if isinstance(source, Scenario) else load_scenario(source)
    run = ScenarioRun(scenario)
    rt = run.rt
    run.fire_due()  # entries at t = 0 act before the first cycle, as in ScenarioRun.run
    run.observe(rt)
    rt.add_program(run.program)
    rt.add_observer(run.observe)
    return Machine(rt, scenario.name, run.finished, list(scenario.signals))
