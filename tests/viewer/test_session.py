"""The viewer's session on a fake wall clock: pacing, pause, step, speed, the end of a scenario,
and what a frame holds for an axis, a CA and a planar example."""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest

import openmotion.viewer as viewer
from openmotion import PacedRuntime, Runtime
from openmotion.scenario import examples_dir, run_scenario
from openmotion.viewer import Layer, Row, Session, registered_layers, scenario_machine
from openmotion.viewer.layers import Reader

EXAMPLES = examples_dir()


class FakeClock:
    """A wall clock that moves only when told (``step``: seconds added at every reading)."""

    def __init__(self, step: float = 0.0) -> None:
        self.now, self.step = 100.0, step

    def __call__(self) -> float:
        self.now += self.step
        return self.now

    def advance(self, seconds: float) -> None:
        self.now += seconds


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


def session(name: str, clock: FakeClock, **options: object) -> Session:
    made = Session.for_scenario(EXAMPLES / name, clock=clock, **options)
    made.tick()
    return made


def cycle(made: Session) -> int:
    return made.machine.runtime.cycle


def frame(made: Session) -> dict:
    """The latest frame as a page receives it."""
    assert made.frame is not None
    return json.loads(made.frame.text)


# -- pacing --------------------------------------------------------------------------------


def test_virtual_time_follows_the_wall_clock(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock)
    assert cycle(made) == 0
    clock.advance(0.5)
    made.tick()
    assert cycle(made) == 500
    assert frame(made)["time"] == pytest.approx(0.5)


def test_pause_stops_virtual_time_and_play_goes_on_without_catching_up(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock)
    clock.advance(0.2)
    made.tick()
    made.pause()
    made.tick()
    clock.advance(1.0)
    made.tick()
    assert cycle(made) == 200
    assert frame(made)["paused"] is True and frame(made)["time"] == pytest.approx(0.2)
    made.play()
    made.tick()
    clock.advance(0.1)
    made.tick()
    assert cycle(made) == 300


def test_step_pauses_and_advances_one_frame_worth(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock, paused=True)  # 25 frames per second
    clock.advance(1.0)
    made.tick()
    assert cycle(made) == 0
    made.step()
    made.tick()
    assert cycle(made) == 40 and made.paused  # 1/25 s of 1 ms cycles
    made.set_speed(2.0)
    made.step()
    made.step()
    made.tick()
    assert cycle(made) == 40 + 2 * 80  # twice the virtual time per frame at twice the speed
    made.play()
    made.tick()
    made.step()
    made.tick()
    assert made.paused and cycle(made) == 280


def test_a_step_is_at_least_one_cycle(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock, paused=True, speed=0.01, frame_rate=50.0)
    made.step()
    made.tick()
    assert cycle(made) == 1


def test_speed_scales_virtual_time_from_the_moment_it_changes(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock, speed=4.0)
    clock.advance(0.25)
    made.tick()
    assert cycle(made) == 1000
    made.set_speed(0.5)
    made.tick()
    clock.advance(1.0)
    made.tick()
    assert cycle(made) == 1500
    assert frame(made)["speed"] == 0.5


@pytest.mark.parametrize("speed", [0, -1.0, 1e6, True, "fast", float("nan")])
def test_a_speed_out_of_range_is_refused(speed: object) -> None:
    with pytest.raises(ValueError, match="speed"):
        Session(Runtime(), speed=speed)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="speed"):
        Session(Runtime()).set_speed(speed)  # type: ignore[arg-type]


# -- a machine that cannot keep up: frames give way first, the motion never ----------------


def costly(made: Session, clock: FakeClock, cost: list[float]) -> Session:
    """Every cycle of ``made`` from now on takes ``cost[0]`` seconds of the fake wall clock."""
    made.machine.runtime.add_observer(lambda rt: clock.advance(cost[0]))
    return made


def endless(clock: FakeClock, **options: Any) -> Session:
    """A runtime of one's own that never ends: an axis moving at 100 mm/s."""
    rt = Runtime()
    x = rt.add_axis("x")
    x.power()
    x.move_velocity(100.0)
    made = Session(rt, clock=clock, **options)
    made.tick()
    return made


def run_wall(made: Session, clock: FakeClock, seconds: float) -> list[dict]:
    """The kernel loop for ``seconds`` of the fake wall clock: a pass, then a pass again at
    once when it had work (a late kernel does not sleep), else 1 ms later. Returns the frames
    published, in order."""
    frames, end = [], clock.now + seconds
    while clock.now < end:
        before, seq = clock.now, made.frame.seq if made.frame else 0
        made.tick()
        if made.frame is not None and made.frame.seq != seq:
            frames.append(frame(made))
        if clock.now == before:
            clock.advance(0.001)
    return frames


def test_a_late_machine_drops_frames_before_the_pace_falls_and_says_so(
        clock: FakeClock) -> None:
    made = costly(endless(clock), clock, [0.002])  # 2 ms a 1 ms cycle: 0.5x at most
    frames = run_wall(made, clock, 1.0)
    first_behind = next(index for index, data in enumerate(frames) if data["behind"])
    rates = [data["frame_rate"] for data in frames[:first_behind + 1]]
    assert rates[0] == 25.0 and rates == sorted(rates, reverse=True)
    assert rates[-1] == 5.0  # the pace falls only at the fewest frames
    assert {12.5, 6.25} <= set(rates)  # halved frame by frame on the way there
    frames = run_wall(made, clock, 2.0)
    last = frames[-1]
    assert last["behind"] and last["frame_rate"] == 5.0
    assert last["rate"] == pytest.approx(0.5, abs=0.05)
    assert 9 <= len(frames) <= 11  # 5 frames a second
    assert last["notice"] == (
        f"This computer runs the simulation at {last['rate']:.2f}× real time, slower than the "
        "1× asked, even with 5 frames a second instead of 25. Every 1 ms cycle is still "
        "computed: the motion is the same, only slower.")
    made.pause()
    made.tick()
    assert frame(made)["notice"] == "" and not frame(made)["behind"]  # nothing runs late


class _CostlyFrames(Layer):
    """A layer whose panel takes ``cost`` seconds of the fake wall clock to build."""

    kind = "costly"

    def __init__(self, clock: FakeClock, cost: float) -> None:
        self.name, self._clock, self._cost = "costly", clock, cost

    def panel(self) -> dict[str, Any]:
        self._clock.advance(self._cost)
        return {}


def test_when_frames_are_what_costs_fewer_frames_keep_the_asked_speed(
        clock: FakeClock) -> None:
    made = costly(endless(clock, layers=[*registered_layers(),
                                         lambda rt: [_CostlyFrames(clock, 0.03)]]),
                  clock, [0.0005])  # 25 frames of 30 ms and 1000 cycles of 0.5 ms: 1.25 s
    run_wall(made, clock, 3.0)
    frames = run_wall(made, clock, 2.0)
    last = frames[-1]
    assert not any(data["behind"] for data in frames)  # the pace holds ...
    assert last["rate"] == pytest.approx(1.0, abs=0.02)
    assert 5.0 <= last["frame_rate"] < 25.0  # ... on fewer frames
    assert last["notice"] == (
        f"{last['frame_rate']:g} frames a second instead of 25: frames are dropped so that "
        "this computer keeps the 1× asked. Every 1 ms cycle is still computed.")


def test_a_machine_that_keeps_up_again_gets_every_frame_back(clock: FakeClock) -> None:
    cost = [0.002]
    made = costly(endless(clock), clock, cost)
    assert run_wall(made, clock, 1.0)[-1]["behind"]
    cost[0] = 0.0001  # the load has gone
    frames = run_wall(made, clock, 1.0)
    assert frames[-1]["frame_rate"] == 25.0
    assert frames[-1]["rate"] == pytest.approx(1.0, abs=0.01)
    assert frames[-1]["behind"]  # the slip is reported for a while ...
    frames = run_wall(made, clock, 2.0)
    assert not frames[-1]["behind"] and frames[-1]["notice"] == ""  # ... then all is well


def test_dropping_frames_never_changes_the_motion(clock: FakeClock) -> None:
    """The trace of a paced machine is its own, whatever the pace: the scope samples of a
    machine that fell behind (frames dropped, clock slipped) equal those of one that kept up,
    and the scenario ends at the cycle ``openmotion run`` ends it."""
    quick = session("ca_starter_kit.yaml", clock)
    slow_clock = FakeClock()
    slow = costly(session("ca_starter_kit.yaml", slow_clock), slow_clock, [0.003])
    frames = run_wall(slow, slow_clock, 8.0)
    assert any(data["behind"] for data in frames)
    assert min(data["frame_rate"] for data in frames) == 5.0
    assert slow.finished
    while not quick.finished:
        clock.advance(0.1)
        quick.tick()
    assert cycle(slow) == cycle(quick) == run_scenario(EXAMPLES / "ca_starter_kit.yaml").cycles
    assert slow.scope_since(0, 0)[0] == quick.scope_since(0, 0)[0]


# -- waiting for a page --------------------------------------------------------------------


def test_a_session_waiting_for_a_page_holds_at_the_start_until_one_connects(
        clock: FakeClock) -> None:
    made = session("single_move.yaml", clock, wait_for_page=True)
    clock.advance(3.0)  # longer than the whole scenario
    made.tick()
    data = frame(made)
    assert cycle(made) == 0 and data["waiting"] and not data["paused"]
    assert (data["time"], data["finished"], data["notice"]) == (0.0, False, "")
    made.page_connected()
    made.tick()
    assert cycle(made) == 0  # time runs from the connection, without a burst
    clock.advance(0.2)
    made.tick()
    assert cycle(made) == 200 and not frame(made)["waiting"]
    made.page_connected()  # a second page sees the run as it is
    made.tick()
    clock.advance(0.1)
    made.tick()
    assert cycle(made) == 300


def test_a_waiting_session_starts_on_play_and_a_paused_one_stays_paused(
        clock: FakeClock) -> None:
    made = session("single_move.yaml", clock, wait_for_page=True)
    made.play()  # headless: /api/control or Python
    made.tick()
    clock.advance(0.1)
    made.tick()
    assert cycle(made) == 100 and not made.waiting
    held = session("single_move.yaml", clock, wait_for_page=True, paused=True)
    held.page_connected()
    held.tick()
    clock.advance(0.5)
    held.tick()
    assert cycle(held) == 0 and frame(held)["paused"] and not frame(held)["waiting"]
    held.step()
    held.tick()
    assert cycle(held) == 40


def test_a_scenario_ends_at_the_cycle_openmotion_run_ends_it(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock)
    clock.advance(10.0)
    for _ in range(3):
        made.tick()
    result = run_scenario(EXAMPLES / "single_move.yaml")
    assert made.finished and frame(made)["finished"] is True
    assert cycle(made) == result.cycles
    made.play()
    made.step()
    clock.advance(1.0)
    made.tick()
    assert cycle(made) == result.cycles


@pytest.mark.parametrize("name", ["single_move.yaml", "planar_two_movers.yaml",
                                  "ca_tracks.yaml"])
def test_the_machine_of_a_scenario_runs_the_cycles_of_run_scenario(name: str) -> None:
    machine = scenario_machine(EXAMPLES / name)
    while not machine.finished():
        machine.runtime.step()
    result = run_scenario(EXAMPLES / name)
    assert machine.runtime.cycle == result.cycles


# -- what a frame holds --------------------------------------------------------------------


def test_frame_of_an_axis_example(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock)
    clock.advance(0.3)
    made.tick()
    data = frame(made)
    assert [panel["kind"] for panel in data["panels"]] == ["axes"]
    (bar,) = data["panels"][0]["axes"]
    assert bar["name"] == "x" and 0.0 < bar["set_position"] < 200.0
    assert bar["velocity"] > 0.0 and bar["min"] is None and not bar["error"]
    (row,) = data["rows"]
    assert (row["kind"], row["name"], row["state"], row["command"]) == (
        "axis", "x", "discrete_motion", "move_absolute")
    assert float(row["position"]) == pytest.approx(bar["set_position"], abs=1e-3)
    assert row["error"] == ""
    assert data["scope"] == ["x.set_position", "x.position", "x.set_velocity", "x.velocity",
                             "x.set_acceleration", "x.following_error"]  # the recorded ones
    assert "x.following_error" in json.loads(made.hello())["signals"]


def test_frame_of_a_ca_example(clock: FakeClock) -> None:
    made = session("ca_starter_kit.yaml", clock)
    clock.advance(0.5)
    made.tick()
    data = frame(made)
    axes, rail = data["panels"]
    assert axes["axes"] == []  # every axis rides on the rail
    assert (rail["kind"], rail["name"], rail["length"], rail["ring"]) == ("rail", "xts", 3000.0,
                                                                          True)
    movers = rail["movers"]
    assert len(movers) == 10 and movers[0]["name"] == "m2"  # CA order: the leader first
    assert {m["wanted_gap"] for m in movers} == {100.0}
    assert all(m["gap"] >= 100.0 - 1e-6 for m in movers)  # CA keeps the gap
    assert any(m["velocity"] > 0.0 for m in movers)
    kinds = [row["kind"] for row in data["rows"]]
    assert kinds == ["CA group"] + ["CA mover"] * 10
    assert data["rows"][0]["detail"] == "10 movers"
    assert data["rows"][1]["detail"].startswith("gap ")
    assert "m5.gap" in json.loads(made.hello())["signals"]


def test_frame_of_a_ca_example_with_parts_and_tracks(clock: FakeClock) -> None:
    made = session("ca_tracks.yaml", clock)
    clock.advance(0.2)
    made.tick()
    data = frame(made)
    rail = data["panels"][1]
    assert rail["parts"] == [{"id": 11, "start": 0.0, "end": 1500.0},
                             {"id": 12, "start": 1500.0, "end": 0.0}]
    m1 = next(row for row in data["rows"] if row["name"] == "m1")
    assert m1["detail"].endswith("track 21")


def test_frame_of_a_planar_example(clock: FakeClock) -> None:
    made = session("planar_choreography.yaml", clock)
    clock.advance(0.2)
    made.tick()
    data = frame(made)
    (field,) = data["panels"]
    assert field["kind"] == "planar" and field["stator_size"] == 240.0
    assert len(field["stators"]) == 16 and [720.0, 720.0] in field["stators"]
    movers = {mover["name"]: mover for mover in field["movers"]}
    assert len(movers) == 8 and movers["m3"]["width"] == 155.0
    assert movers["m3"]["busy"] and 600.0 < movers["m3"]["y"] < 840.0  # one cell on, on its way
    reserved = {area["mover"] for area in field["reserved"]}
    assert {"m3", "m5", "m7", "m8"} <= reserved  # the movers on their way hold their areas
    assert all(ring[0] == ring[-1] for area in field["reserved"] for ring in area["rings"])
    rows = {row["name"]: row for row in data["rows"]}
    assert rows["environment"]["detail"] == "16 stators, boundary"
    assert (rows["field"]["kind"], rows["field"]["state"]) == ("planar group", "enabled")
    assert rows["m3"]["command"] == "moving" and rows["m1"]["command"] == ""
    assert rows["m1"]["error"] == ""  # its first step was refused, the mover has no error
    assert {"m1.x", "m8.velocity"} <= set(json.loads(made.hello())["signals"])


def test_a_runtime_of_ones_own_never_ends_and_cannot_restart(clock: FakeClock) -> None:
    rt = Runtime()
    x = rt.add_axis("x")
    x.power()
    x.move_velocity(100.0)
    made = Session(rt, clock=clock)
    made.tick()
    clock.advance(2.0)
    made.tick()
    assert rt.cycle == 2000 and not made.finished
    assert frame(made)["name"] == "runtime" and frame(made)["rows"][0]["name"] == "x"
    assert frame(made)["scope"] == ["x.set_position", "x.position"]
    assert not made.restartable
    with pytest.raises(ValueError, match="restart"):
        made.restart()


def test_a_paced_runtime_is_refused_the_session_paces_itself() -> None:
    with pytest.raises(ValueError, match="PacedRuntime"):
        Session(PacedRuntime())


# -- controls and scope --------------------------------------------------------------------


def test_control_messages_map_to_the_controls(clock: FakeClock) -> None:
    made = session("single_move.yaml", clock)
    made.control({"op": "speed", "value": 3})
    made.control({"op": "pause"})
    made.control({"op": "scope", "signals": ["x.velocity"]})
    made.tick()
    data = frame(made)
    assert (data["speed"], data["paused"], data["scope"]) == (3.0, True, ["x.velocity"])
    for bad in ({"op": "fly"}, {}, ["pause"], {"op": "speed", "value": "x"},
                {"op": "scope", "signals": "x.velocity"}):
        with pytest.raises(ValueError):
            made.control(bad)  # type: ignore[arg-type]


def test_the_scope_samples_every_10_ms_and_a_page_gets_only_what_it_has_not_seen(
        clock: FakeClock) -> None:
    made = session("single_move.yaml", clock)
    message, scope_id, count = made.scope_since(0, 0)
    assert message is not None and message["reset"] and count == 1
    assert message["samples"][0][0] == 0.0 and len(message["samples"][0]) == 7
    assert made.scope_since(scope_id, count)[0] is None  # nothing new
    clock.advance(0.1)
    made.tick()
    message, scope_id, count = made.scope_since(scope_id, count)
    assert message is not None and not message["reset"]
    assert [round(sample[0], 9) for sample in message["samples"]] == [
        round(0.01 * k, 9) for k in range(1, 11)]
    made.select(["x.velocity", "no.such_signal", "x.velocity"])
    made.tick()
    message, _, _ = made.scope_since(scope_id, count)
    assert message is not None and message["reset"] and message["names"] == ["x.velocity"]


def test_restart_reads_the_file_again(tmp_path: Path, clock: FakeClock) -> None:
    path = tmp_path / "move.yaml"
    shutil.copy(EXAMPLES / "single_move.yaml", path)
    made = Session.for_scenario(path, clock=clock)
    made.tick()
    clock.advance(0.5)
    made.tick()
    path.write_text(path.read_text().replace("name: single move", "name: edited move"))
    made.restart()
    made.tick()
    data = frame(made)
    assert (data["name"], data["time"], data["generation"]) == ("edited move", 0.0, 2)
    path.write_text("name: [broken")
    made.restart()
    made.tick()
    assert frame(made)["failure"].startswith("restart failed: ")
    assert frame(made)["name"] == "edited move"  # the machine that ran goes on


# -- layers and names ----------------------------------------------------------------------


class _Counter(Layer):
    """A layer of a subsystem the viewer does not know: how many cycles have run."""

    kind = "counter"

    def __init__(self, runtime: Runtime) -> None:
        self.name, self._rt = "cycles", runtime

    def panel(self) -> dict[str, Any]:
        return {"cycle": self._rt.cycle}

    def rows(self) -> list[Row]:
        return [Row("counter", self.name, "counting", detail=str(self._rt.cycle))]

    def signals(self) -> dict[str, Reader]:
        return {"cycles.count": lambda: float(self._rt.cycle)}


def test_a_subsystem_plugs_in_with_its_own_layer(clock: FakeClock) -> None:
    rt = Runtime()
    made = Session(rt, clock=clock,
                   layers=[*registered_layers(), lambda runtime: [_Counter(runtime)]])
    made.tick()
    clock.advance(0.05)  # more than a frame period: a new frame is due
    made.tick()
    data = frame(made)
    assert data["panels"] == [{"kind": "counter", "name": "cycles", "cycle": 50}]
    assert data["rows"][0]["detail"] == "50" and data["scope"] == ["cycles.count"]


def test_the_shipped_layers_and_public_names() -> None:
    assert [factory.__name__ for factory in registered_layers()] == [
        "axes_layers", "rail_layers", "planar_layers"]  # drawing order
    assert sorted(viewer.__all__) == sorted([
        "AxesLayer", "Frame", "Layer", "LayerFactory", "Machine", "PlanarLayer", "RailLayer",
        "Row", "Session", "create_app", "register_layer", "registered_layers",
        "scenario_machine", "serve", "serving"])
