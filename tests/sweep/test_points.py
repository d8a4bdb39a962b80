"""Expansion of a sweep into points: grids, zips, linspaces, seeded random draws, repeats,
seeds and ids (D-251)."""

from __future__ import annotations

import hashlib
import json

import pytest

from openmotion.sweep import expand, load_sweep
from openmotion.sweep.points import canonical_json

VELOCITY = {"path": "timeline[go].velocity", "values": [100.0, 200.0, 300.0]}
POSITION = {"path": "timeline[1].position", "values": [10.0, 20.0]}


def test_a_grid_is_every_combination_the_last_parameter_fastest(write_sweep) -> None:
    points = expand(load_sweep(write_sweep(parameters=[VELOCITY, POSITION])))
    assert [(p.params["timeline[go].velocity"], p.params["timeline[1].position"])
            for p in points] == [(100.0, 10.0), (100.0, 20.0), (200.0, 10.0), (200.0, 20.0),
                                 (300.0, 10.0), (300.0, 20.0)]
    assert [p.index for p in points] == list(range(6))
    go = points[3].document["timeline"][1]
    assert (go["velocity"], go["position"]) == (200.0, 20.0)


def test_zip_puts_the_lists_side_by_side(write_sweep) -> None:
    points = expand(load_sweep(write_sweep(
        combine="zip", parameters=[VELOCITY, {**POSITION, "values": [1.0, 2.0, 3.0]}])))
    assert [tuple(p.params.values()) for p in points] == [(100.0, 1.0), (200.0, 2.0),
                                                         (300.0, 3.0)]


def test_a_linspace_includes_both_ends(write_sweep) -> None:
    points = expand(load_sweep(write_sweep(parameters=[
        {"path": "timeline[go].velocity", "linspace": {"start": 100, "stop": 200, "num": 5}}])))
    assert [p.params["timeline[go].velocity"] for p in points] == [100.0, 125.0, 150.0, 175.0,
                                                                   200.0]


def test_random_draws_are_in_range_and_the_same_in_every_expansion(write_sweep) -> None:
    path = write_sweep(samples=20, seed=5, parameters=[
        {"path": "timeline[go].velocity", "uniform": [100.0, 300.0]},
        {"path": "timeline[go].position", "integers": [1, 3]},
        {"path": "axes[0].position", "choice": [0.0, -5.0]}])
    first, again = expand(load_sweep(path)), expand(load_sweep(path))
    assert [p.params for p in first] == [p.params for p in again]
    assert [p.point_id for p in first] == [p.point_id for p in again]
    velocities = [p.params["timeline[go].velocity"] for p in first]
    assert all(100.0 <= v < 300.0 for v in velocities) and len(set(velocities)) == 20
    assert {p.params["timeline[go].position"] for p in first} == {1, 2, 3}
    assert {p.params["axes[0].position"] for p in first} == {0.0, -5.0}
    assert [p.sample for p in first] == list(range(20))


def test_another_sweep_seed_draws_other_values(write_sweep) -> None:
    draws = [[p.params["x"] for p in expand(load_sweep(write_sweep(
        seed=seed, samples=3, parameters=[{"path": "timeline[go].velocity", "name": "x",
                                           "uniform": [1.0, 2.0]}])))] for seed in (1, 2)]
    assert draws[0] != draws[1]


def test_repeats_have_their_own_seeds_and_ids(write_sweep) -> None:
    points = expand(load_sweep(write_sweep(repeat=3, parameters=[VELOCITY])))
    assert len(points) == 9 and [p.repeat for p in points[:3]] == [0, 1, 2]
    assert len({p.seed for p in points}) == 9 and len({p.point_id for p in points}) == 9
    assert points[0].scenario_hash == points[1].scenario_hash  # same document, other seed


def test_ids_and_hashes_are_sha256_of_canonical_json(write_sweep) -> None:
    point = expand(load_sweep(write_sweep(parameters=[VELOCITY])))[0]
    assert point.scenario_hash == hashlib.sha256(
        canonical_json(point.document).encode()).hexdigest()
    assert point.point_id == hashlib.sha256(canonical_json(
        {"scenario": point.document, "seed": point.seed}).encode()).hexdigest()
    assert canonical_json({"b": 1.5, "a": [1, None]}) == '{"a":[1,null],"b":1.5}'
    assert 0 <= point.seed < 2**63
    json.dumps(point.document)


def test_a_point_keeps_its_seed_and_id_when_values_are_added(write_sweep) -> None:
    """The seed comes from the values, not from the position in the expansion (D-251)."""
    before = expand(load_sweep(write_sweep(parameters=[VELOCITY])))
    after = expand(load_sweep(write_sweep(parameters=[{**VELOCITY,
                                                       "values": [50.0, 100.0, 200.0]}])))
    assert (after[1].seed, after[1].point_id) == (before[0].seed, before[0].point_id)
    assert after[1].index == 1 and before[0].index == 0


def test_wildcards_names_and_first_resolve_the_document(write_sweep) -> None:
    points = expand(load_sweep(write_sweep(parameters=[
        {"name": "entries", "first": ["timeline", "record.signals"], "values": [1, 2]},
        {"path": "timeline[*].at", "values": [0.5]}])))
    assert [len(p.document["timeline"]) for p in points] == [1, 2]
    assert points[0].document["record"]["signals"] == ["x.set_position"]
    assert [entry["at"] for entry in points[1].document["timeline"]] == [0.5, 0.5]
    assert points[0].params == {"entries": 1, "timeline[*].at": 0.5}


def test_without_parameters_a_sweep_is_one_point_per_repeat(write_sweep) -> None:
    assert len(expand(load_sweep(write_sweep(repeat=2)))) == 2


@pytest.mark.parametrize("samples", [1, 4])
def test_samples_multiply_only_random_parameters(write_sweep, samples: int) -> None:
    listed = expand(load_sweep(write_sweep(samples=samples, parameters=[VELOCITY])))
    assert len(listed) == 3  # no random parameter: one sample
    drawn = expand(load_sweep(write_sweep(samples=samples, parameters=[
        VELOCITY, {"path": "axes[0].position", "uniform": [0.0, 1.0]}])))
    assert len(drawn) == 3 * samples
