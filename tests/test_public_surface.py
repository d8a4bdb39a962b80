"""The public import surface of the system packages (issue 21 item 6, D-224).

Each system package (plcopen, transport, coordinated, planar) lists its public names in
``__all__``, as the top-level package does (tests/runtime/test_runtime.py pins that one). The
rule, checked on every module of a package: a class defined there under its own name that is a
block (``MC_*``), an option type (``ST_*``) or an enumeration is in the package's ``__all__``,
as the same object. Objects that no name pattern finds (the group, the frames, the
parameters...) are pinned below. A new block added to a module without an export fails here.
"""

from __future__ import annotations

import enum
import importlib
import inspect
import pkgutil
import subprocess
import sys
import types
from collections.abc import Iterable

import pytest

import openmotion as om

PACKAGES = ("openmotion.plcopen", "openmotion.transport", "openmotion.coordinated",
            "openmotion.planar")

#: enumerations a package keeps to itself, with the reason: never an input or an output
INTERNAL = {
    "openmotion.coordinated.states.GroupEvent": "the state machine's own event names",
    "openmotion.planar.states.ErrorReaction": "how the state machine reacts to an error",
    "openmotion.planar.states.StateCommand": "the state machine's own command names",
    "openmotion.planar.states.MoverCommand": "the mover's command kinds, for mode checks",
}

#: documented objects and option types that no name pattern finds
OBJECTS = {
    "openmotion.plcopen": {"EnableBlock", "ExecuteBlock", "FunctionBlock", "InputRef",
                           "PowerStepperParams"},
    "openmotion.transport": {"CaGroup", "CaGroupParameters", "GeoCompensation", "GroupInterface",
                             "IdentInGroup", "MoverTemplate", "Part", "StarterKitGeometry",
                             "Track", "TrackPositions", "TrackTable"},
    "openmotion.coordinated": {"AxesGroup", "CartesianGantry", "CartesianTransform",
                               "CoordinateView", "DeltaRobot", "Frame", "Kinematics",
                               "LinearFrame", "PathData", "PathDynamics", "Scara"},
    "openmotion.planar": {"DynamicConstraint_PathXY", "IPlcDynamicConstraint", "Limits",
                          "MoverVector", "Part", "PartLayout", "PartPosition", "PlanarCommand",
                          "PlanarMoverParameters", "PlanarObjectInfo", "PlanarSystem", "Pose",
                          "PositionXYC", "StatorField"},
}


def _modules(package: types.ModuleType) -> list[types.ModuleType]:
    return [importlib.import_module(f"{package.__name__}.{info.name}")
            for info in pkgutil.iter_modules(package.__path__)]


def _ruled(name: str, value: object) -> bool:
    """Whether the rule asks ``name`` to be exported: a block, an option type or an enum."""
    return name.startswith(("MC_", "ST_")) or (inspect.isclass(value)
                                               and issubclass(value, enum.Enum))


def unexported(package: types.ModuleType, modules: Iterable[types.ModuleType]) -> list[str]:
    """The classes of ``modules`` the rule asks ``package`` to export that it does not.

    A class counts where it is defined under its own name (``cls.__name__``), so an alias
    such as coordinated's short block names (``MC_MoveLinAbs``, §1.3.1) does not; a private
    name (``_Move``) never does.
    """
    exported = set(getattr(package, "__all__", ()))
    missing = []
    for module in modules:
        for name, value in vars(module).items():
            if name.startswith("_") or not inspect.isclass(value):
                continue
            if value.__module__ != module.__name__ or value.__name__ != name:
                continue
            if f"{module.__name__}.{name}" in INTERNAL or not _ruled(name, value):
                continue
            if name not in exported or getattr(package, name, None) is not value:
                missing.append(f"{module.__name__}.{name}")
    return missing


@pytest.mark.parametrize("name", PACKAGES)
def test_every_block_option_type_and_enum_of_a_package_is_exported(name: str) -> None:
    package = importlib.import_module(name)
    assert unexported(package, _modules(package)) == []


@pytest.mark.parametrize("name", PACKAGES)
def test_every_name_in_all_imports_once(name: str) -> None:
    package = importlib.import_module(name)
    names = package.__all__
    assert len(names) == len(set(names)), sorted(n for n in set(names) if names.count(n) > 1)
    missing = [n for n in names if not hasattr(package, n)]
    assert not missing, f"{name}.__all__ names what it cannot import: {missing}"
    space: dict[str, object] = {}
    exec(f"from {name} import *", space)  # noqa: S102 - what a user's star import gets
    assert set(names) <= set(space)


@pytest.mark.parametrize("name", PACKAGES)
def test_the_documented_objects_are_exported(name: str) -> None:
    package = importlib.import_module(name)
    assert OBJECTS[name] <= set(package.__all__), sorted(OBJECTS[name] - set(package.__all__))


@pytest.mark.parametrize("name", PACKAGES)
def test_the_enum_a_block_input_defaults_to_is_exported_with_it(name: str) -> None:
    """A block's enum inputs come from the same package, or from ``openmotion`` itself."""
    package = importlib.import_module(name)
    public = {id(getattr(package, n)) for n in package.__all__}
    public |= {id(getattr(om, n)) for n in om.__all__}
    lacking = []
    for block in (getattr(package, n) for n in package.__all__ if n.startswith("MC_")):
        for field, default in getattr(block, "INPUTS", {}).items():
            if isinstance(default, enum.Enum) and id(type(default)) not in public:
                lacking.append(f"{block.__name__}.{field}: {type(default).__name__}")
    assert not lacking


def test_the_rule_finds_a_block_added_without_an_export() -> None:
    """The same rule on a made-up package: its new block, enum and option type are found;
    the exported block, an alias, a private class and a plain helper are not."""
    package = types.ModuleType("fake")
    module = types.ModuleType("fake.blocks")
    source = """
import enum
class MC_Old: pass
class MC_New: pass
class ST_NewOptions: pass
class NewMode(enum.IntEnum):
    A = 1
class _Hidden: pass
class Helper: pass
MC_OldShort = MC_Old
"""
    exec(source, module.__dict__)  # noqa: S102 - a module made for the test
    package.__all__ = ["MC_Old"]
    package.MC_Old = module.MC_Old
    assert sorted(unexported(package, [module])) == [
        "fake.blocks.MC_New", "fake.blocks.NewMode", "fake.blocks.ST_NewOptions"]
    package.MC_New = module.MC_Old  # exported under the name, but another object
    package.__all__.append("MC_New")
    assert "fake.blocks.MC_New" in unexported(package, [module])


def test_coordinated_exports_the_group_and_its_inputs() -> None:
    """What users imported from deep paths before (issue 21, the review's finding)."""
    import openmotion.coordinated as coordinated
    from openmotion.coordinated.group import AxesGroup
    from openmotion.coordinated.inputs import PathDynamics, TransitionMode

    assert coordinated.AxesGroup is AxesGroup
    assert coordinated.TransitionMode is TransitionMode
    assert coordinated.PathDynamics is PathDynamics
    with pytest.raises(AttributeError, match="no attribute 'MC_MoveLinAbs'"):
        _ = coordinated.MC_MoveLinAbs  # the short names stay in coordinated.blocks (D-224)
    assert coordinated.MC_MoveLinearAbsolute.__name__ == "MC_MoveLinearAbsolute"


def test_planar_users_find_limits_in_planar() -> None:
    """PlanarMoverParameters takes Limits (TF5430 dynamics); the same object as the plan's."""
    import openmotion.planar as planar
    from openmotion.trajectory.plan import Limits

    assert planar.Limits is Limits
    fast = planar.Limits(5000.0, 30000.0, 30000.0, 500000.0)
    assert planar.PlanarMoverParameters(maximum_dynamic_xy=fast).maximum_dynamic_xy is fast


def test_importing_coordinated_loads_no_module_of_it() -> None:
    """The package loads its modules on first use (PEP 562, D-173): ``import
    openmotion.coordinated`` costs what ``import openmotion`` costs."""
    code = ("import sys, openmotion.coordinated\n"
            "print(sorted(m for m in sys.modules if m.startswith('openmotion')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120).stdout
    assert out.strip() == ("['openmotion', 'openmotion.coordinated', 'openmotion.core', "
                           "'openmotion.core.lazy']")
