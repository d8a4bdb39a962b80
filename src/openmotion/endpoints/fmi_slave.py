"""The pythonfmu class of an exported FMU: ``MachineUnit`` behind FMI 2.0's calls.

pythonfmu's binary loads the FMU's script from its resources; the script's class derives
from ``MachineSlave``, which reads the scenario and the options ``export_fmu`` wrote there.
This module imports pythonfmu at once; ``fmi`` does not, so that the rest of the endpoints
never need it.

pythonfmu reports any Python exception of a call as ``fmi2Fatal`` with its message in the
log (the only error path its binary has): a refused step (``StepError``) reaches an importer
so, and fmpy raises with it (D-272).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import (
    Boolean,
    DefaultExperiment,
    Fmi2Causality,
    Fmi2Slave,
    Fmi2Variability,
    Integer,
    Real,
    String,
)
from pythonfmu.enums import Fmi2Status

from openmotion.endpoints.fmi import MODEL_NAME, SCENARIO, FmuOptions, MachineUnit

__all__ = ["MachineSlave"]

#: namespaces of the FMU scripts, one reference per instance made (D-270): pythonfmu 0.7's
#: binary releases a reference to the script module's namespace it never took (its findClass
#: decrefs the borrowed ``PyModule_GetDict``), so a second instance in one process would meet
#: a freed namespace and crash the importer
_PINNED: list[dict[str, Any]] = []
_TYPES = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}


class MachineSlave(Fmi2Slave):
    """A co-simulation slave that steps the scenario in its resources."""

    author = "openmotion"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        _PINNED.append(vars(sys.modules[type(self).__module__]))
        resources = Path(kwargs["resources"])
        options = FmuOptions.read(resources)
        self.modelName = MODEL_NAME
        self.description = options.description
        self.default_experiment = DefaultExperiment(0.0, options.stop_time, options.step_size)
        self.unit = MachineUnit(resources / SCENARIO, options.commands, options.signals)
        self.unit.log = lambda message: self.log(message, Fmi2Status.warning)
        self.units: dict[str, str] = {}  #: variable name -> its unit
        for variable in self.unit.variables:
            inputs = variable.causality == "input"
            self.register_variable(_TYPES[variable.type](
                variable.name, causality=Fmi2Causality.input if inputs else
                Fmi2Causality.output, variability=Fmi2Variability.discrete,
                description=variable.description or None, getter=variable.get,
                setter=variable.set), nested=False)
            if variable.unit:
                self.units[variable.name] = variable.unit

    def setup_experiment(self, start_time: float, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        if start_time != 0.0:
            raise ValueError(f"the machine starts at t = 0, not {start_time!r}")

    def exit_initialization_mode(self) -> None:
        self.unit.start()

    def do_step(self, current_time: float, step_size: float) -> bool:
        self.unit.step(current_time, step_size)
        return True

    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        """pythonfmu's model description, with the units of the Real variables (and their
        UnitDefinitions) and NaN start values spelt as XML Schema spells them."""
        root = super().to_xml(model_options or {})
        for scalar in root.iter("ScalarVariable"):
            real = scalar.find("Real")
            if real is None:
                continue
            unit = self.units.get(scalar.get("name", ""))
            if unit:
                real.set("unit", unit)
            start = real.get("start")
            if start is not None and math.isnan(float(start)):
                real.set("start", "NaN")
        if self.units:
            definitions = Element("UnitDefinitions")
            for unit in sorted(set(self.units.values())):
                SubElement(definitions, "Unit", {"name": unit})
            after = list(root).index(root.find("CoSimulation")) + 1  # the schema's order
            root.insert(after, definitions)
        return root

