"""A sweep's points: every combination of the listed values, each drawn sample of the random
ones and each repeat, as a fully resolved scenario document with its own seed and id.

The seed of a point comes from the sweep's seed and the point's listed values, sample and
repeat numbers, never from its position in the expansion: adding a value to a list leaves
the other points' seeds, draws and ids as they were, so that a resumed sweep finds them
(D-251). The id hashes the resolved document and the seed (canonical JSON, sha256).
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
from dataclasses import dataclass
from typing import Any

import numpy as np

from openmotion.sweep import paths
from openmotion.sweep.spec import Parameter, Sweep

SEED_BITS = 63  #: seeds fit a signed 64-bit column


@dataclass(frozen=True)
class Point:
    """One run of a sweep."""

    index: int  #: position in the expansion; the table's row order
    point_id: str  #: sha256 of the canonical JSON of the document and the seed
    seed: int  #: drew this point's random values
    sample: int  #: number of the random draw of its combination (0 without random values)
    repeat: int
    params: dict[str, Any]  #: column -> value, in the sweep file's order
    document: dict[str, Any]  #: the scenario to run
    scenario_hash: str  #: sha256 of the canonical JSON of the document alone


def canonical_json(data: Any) -> str:
    """One text per value: sorted keys, no spaces, floats as Python's shortest repr."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=False,
                      default=str)


def digest(data: Any) -> str:
    return hashlib.sha256(canonical_json(data).encode("utf-8")).hexdigest()


def expand(sweep: Sweep) -> list[Point]:
    """Every point of a sweep, in expansion order: the listed values (a grid in the order of
    the file, the last parameter fastest, or side by side with ``combine: zip``), then the
    samples, then the repeats."""
    spec = sweep.spec
    listed = [p for p in spec.parameters if not p.random]
    drawn = [p for p in spec.parameters if p.random]
    columns = [p.listed() for p in listed]
    combinations = itertools.product(*columns) if spec.combine == "grid" else zip(*columns,
                                                                                strict=True)
    points: list[Point] = []
    for combination in combinations:
        fixed = {p.column: value for p, value in zip(listed, combination, strict=True)}
        for sample in range(spec.samples if drawn else 1):
            for repeat in range(spec.repeat):
                seed = int(digest([spec.seed, fixed, sample, repeat])[:16], 16) \
                    >> (64 - SEED_BITS)
                rng = np.random.default_rng(seed)
                values = {**fixed, **{p.column: _draw(p, rng) for p in drawn}}
                params = {p.column: values[p.column] for p in spec.parameters}
                document = resolve(sweep.base, spec.parameters, params)
                points.append(Point(len(points), digest({"scenario": document, "seed": seed}),
                                    seed, sample, repeat, params, document, digest(document)))
    return points


def resolve(base: dict[str, Any], parameters: list[Parameter],
            values: dict[str, Any]) -> dict[str, Any]:
    """A copy of ``base`` with each parameter's value in its place, in the file's order."""
    document = copy.deepcopy(base)
    for parameter in parameters:
        value = values[parameter.column]
        if parameter.path is not None:
            paths.assign(document, parameter.path, copy.deepcopy(value))
            continue
        for text in parameter.first or ():
            for container, key in paths.targets(document, text):
                container[key] = container[key][:value]
    return document


def _draw(parameter: Parameter, rng: np.random.Generator) -> Any:
    if parameter.uniform is not None:
        return float(rng.uniform(*parameter.uniform))
    if parameter.integers is not None:
        low, high = parameter.integers
        return int(rng.integers(low, high, endpoint=True))
    choices = parameter.choice or []
    return copy.deepcopy(choices[int(rng.integers(len(choices)))])
