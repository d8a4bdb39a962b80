"""The layers of docs/architecture.md hold: imports point inward, systems never import each
other, and no two packages import each other (directly or round a ring).

Imports under ``if TYPE_CHECKING:`` are annotations only and do not count.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "openmotion"

#: inner layers first; a package may import its own layer and the layers before it
LAYERS: tuple[frozenset[str], ...] = (
    frozenset({"core", "trajectory", "geometry"}),  # the maths
    frozenset({"kernel"}),  # cyclic runtime, System contract, machine model, handshake
    frozenset({"rail"}),  # the 1-D multi-mover engine of CA rails and planar tracks
    frozenset({"axis"}),  # the single-axis engine every axis-based system builds on
    frozenset({"runtime"}),  # the runtime users make: the kernel with its axes
    frozenset({"plcopen", "transport", "coordinated", "planar"}),  # the systems
    frozenset({"trace", "scenario", "sweep", "viewer", "endpoints", "bench", "examples", "envs",
               "testing", "warm", "cli", "__main__", "__init__"}),  # the edges
)
SYSTEMS = LAYERS[5]



def _annotation_nodes(tree: ast.Module) -> set[int]:
    inside: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            inside.update(id(child) for child in ast.walk(node))
    return inside


def package_imports(root: Path = SRC) -> dict[str, set[str]]:
    """package -> the other openmotion packages it imports when it runs."""
    graph: dict[str, set[str]] = defaultdict(set)
    for path in root.rglob("*.py"):
        relative = path.relative_to(root)
        package = relative.parts[0] if len(relative.parts) > 1 else relative.stem
        tree = ast.parse(path.read_text(encoding="utf-8"))
        skip = _annotation_nodes(tree)
        for node in ast.walk(tree):
            if id(node) in skip:
                continue
            if isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            elif isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            else:
                continue
            for name in names:
                parts = name.split(".")
                if parts[0] == "openmotion" and len(parts) > 1 and parts[1] != package:
                    graph[package].add(parts[1])
    return graph


def _layer(package: str) -> int:
    for index, members in enumerate(LAYERS):
        if package in members:
            return index
    raise AssertionError(f"package {package!r} has no layer in tests/test_layers.py")


def outward(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    return sorted((package, target) for package, targets in graph.items()
                  for target in targets if _layer(target) > _layer(package))


def cycle(graph: dict[str, set[str]]) -> list[str]:
    """One ring of packages importing each other, or [] (a depth-first search)."""
    state: dict[str, int] = {}  # 1: on the path, 2: done

    def visit(package: str, path: list[str]) -> list[str]:
        state[package] = 1
        for target in sorted(graph.get(package, ())):
            if state.get(target) == 1:
                return path[path.index(target):] + [target]
            if target not in state:
                ring = visit(target, [*path, target])
                if ring:
                    return ring
        state[package] = 2
        return []

    for package in sorted(graph):
        if package not in state:
            ring = visit(package, [package])
            if ring:
                return ring
    return []


@pytest.fixture(scope="module")
def imports() -> dict[str, set[str]]:
    """The package's import graph, parsed once for the four checks below."""
    return package_imports()


def test_every_package_imports_inward_only(imports: dict[str, set[str]]):
    assert outward(imports) == []


def test_systems_never_import_each_other(imports: dict[str, set[str]]):
    crossings = sorted((package, target) for package, targets in imports.items()
                       for target in targets if package in SYSTEMS and target in SYSTEMS)
    assert crossings == []


def test_the_kernel_knows_no_system(imports: dict[str, set[str]]):
    assert imports["kernel"] <= LAYERS[0]


def test_no_import_cycle_between_packages(imports: dict[str, set[str]]):
    assert cycle(imports) == []


def test_the_checks_see_a_cycle_and_an_outward_import(tmp_path: Path):
    """The rules above can fail: a made-up tree with both faults is caught."""
    for package, source in (("kernel", "from openmotion.axis import x\n"),
                            ("axis", "import openmotion.kernel.y\n"),
                            ("core", "if TYPE_CHECKING:\n    from openmotion.axis import z\n")):
        (tmp_path / package).mkdir()
        (tmp_path / package / "m.py").write_text(source)
    graph = package_imports(tmp_path)
    assert graph == {"kernel": {"axis"}, "axis": {"kernel"}}
    assert cycle(graph) == ["axis", "kernel", "axis"]
    assert outward(graph) == [("kernel", "axis")]
