"""Planar parts and coordinate systems (TF5430 §5, §6.6, MC_PlanarPart §7.2.2.9).

OIDs follow the manual where it prints them (16#01010020/30/80 parts, 16#01010060 and
16#010100A0 coordinate systems); the others are chosen in the same range.
"""

from __future__ import annotations

import contextlib

import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, invariant, rule
from shapely.geometry import LineString

from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.planar.enums import PlanarState
from openmotion.planar.frames import Pose
from openmotion.planar.parts import STATOR_SIZE, Part, PartLayout, PartPosition

S = STATOR_SIZE
CS_1 = 0x01010060  # the single coordinate system of §6.1.4 / §6.1.7; CS 1 in §6.6.1 (inferred)
CS_2 = 0x010100A0  # coordinate system two of §6.6.1
PART_1, PART_2, PART_3 = 0x01010020, 0x01010030, 0x01010080


def part(oid: int, x: float, y: float, c: float = 0.0, system: int = CS_1,
         stators=((0.0, 0.0),)) -> Part:
    """A static part with its lower-left corner at (x, y, c) in ``system``."""
    return Part(oid, stators, [PartPosition(system, Pose(x, y, c))])


def rejected(error_id: ErrorId):
    """Expect ``CommandRejected`` with this error id."""
    return _Rejected(error_id)


class _Rejected(contextlib.AbstractContextManager):
    def __init__(self, error_id: ErrorId) -> None:
        self.error_id = error_id
        self._raises = pytest.raises(CommandRejected)

    def __enter__(self):
        return self._raises.__enter__()

    def __exit__(self, *exc):
        handled = self._raises.__exit__(*exc)
        assert self._raises.excinfo.value.error_id is self.error_id, self._raises.excinfo.value
        return handled


# --- stators and configuration (§5.1) ------------------------------------------------------

def test_an_l_shaped_part_is_one_polygon_of_three_stators():
    corner = part(PART_1, 0.0, 0.0, stators=[(0.0, 0.0), (240.0, 0.0), (0.0, 240.0)])
    assert corner.surface().geom_type == "Polygon"
    assert corner.surface().area == pytest.approx(3 * S * S)
    assert corner.stators == ((0.0, 0.0), (240.0, 0.0), (0.0, 240.0))


def test_a_ring_of_stators_is_contiguous_and_has_a_hole():
    ring = [(x * S, y * S) for x in range(3) for y in range(3) if (x, y) != (1, 1)]
    assert len(part(PART_1, 0.0, 0.0, stators=ring).surface().interiors) == 1


@pytest.mark.parametrize(("stators", "message"), [
    ([], "at least one stator"),
    ([(0.0, 0.0), (250.0, 0.0)], "not on the 240 mm grid"),
    ([(0.0, 0.0), (240.0, 0.0), (0.0, 0.0)], "overlap at (0, 0)"),
    ([(240.0, 0.0), (480.0, 0.0)], "lower-left corner"),
    ([(0.0, 0.0), (240.0, 240.0)], "(240, 240) shares no edge"),
    ([(0.0, 0.0), (480.0, 0.0), (0.0, 240.0)], "(480, 0) shares no edge"),
])
def test_bad_stator_sets_are_config_errors(stators, message):
    with pytest.raises(ConfigError, match=r"part 16#01010020: stators: .*") as info:
        part(PART_1, 0.0, 0.0, stators=stators)
    assert message in str(info.value)


def test_a_part_needs_a_position_and_a_valid_initial_index():
    with pytest.raises(ConfigError, match="at least one position"):
        Part(PART_1, [(0.0, 0.0)], [])
    with pytest.raises(ConfigError, match="position_index: position index 2 is not in 1..1"):
        Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())], position_index=2)


@pytest.mark.parametrize("oid", [0, -1, 2**32, True, "16#01010020"])
def test_object_ids_are_udints_above_zero(oid):
    with pytest.raises(ConfigError, match="is not an object id"):
        part(oid, 0.0, 0.0)
    with pytest.raises(ConfigError, match="is not an object id"):
        PartLayout([oid], [])


def test_layout_configuration_errors():
    with pytest.raises(ConfigError, match="at least one"):
        PartLayout([], [])
    with pytest.raises(ConfigError, match="16#01010020 is used twice"):
        PartLayout([CS_1], [part(PART_1, 0.0, 0.0), part(PART_1, 240.0, 0.0)])
    with pytest.raises(ConfigError, match="16#01010060 is used twice"):
        PartLayout([CS_1], [part(CS_1, 0.0, 0.0)])
    with pytest.raises(ConfigError, match=r"positions\[1\]: coordinate system 16#010100A0"):
        PartLayout([CS_1], [part(PART_1, 0.0, 0.0, system=CS_2)])
    with pytest.raises(ConfigError, match="16#01010020: position_index: overlaps part 16#01010030"):
        PartLayout([CS_1], [part(PART_1, 0.0, 0.0), part(PART_2, 120.0, 0.0)])


def test_parts_may_touch_and_overlap_in_different_systems():
    layout = PartLayout([CS_1, CS_2], [part(PART_1, 0.0, 0.0),
                                       part(PART_2, 0.0, 0.0, system=CS_2)])
    assert [p.oid for p in layout.parts_in(CS_2)] == [PART_2]


# --- state of a part (§4.1, §6.6) -----------------------------------------------------------

def test_enable_and_disable_take_one_update_and_cancel_each_other():
    p = part(PART_1, 0.0, 0.0)
    assert (p.state, p.disable_forced) == (PlanarState.DISABLED, False)
    p.enable()
    assert p.state is PlanarState.ENABLING
    p.disable()
    assert p.state is PlanarState.DISABLING
    p.enable()
    p.update()
    assert p.state is PlanarState.ENABLED
    p.enable()
    assert p.state is PlanarState.ENABLED
    p.disable()
    p.update()
    assert p.state is PlanarState.DISABLED


def test_force_disable_holds_until_allow_enable():
    p = part(PART_1, 0.0, 0.0)
    p.enable()
    p.update()
    p.force_disable()
    p.update()
    assert (p.state, p.disable_forced) == (PlanarState.DISABLED, True)
    with rejected(ErrorId.PLANAR_WRONG_STATE):
        p.enable()
    p.allow_enable()
    p.enable()
    assert p.state is PlanarState.ENABLING


def test_an_error_of_an_enabled_part_resets_to_enabled():
    p = part(PART_1, 0.0, 0.0)
    p.enable()
    p.update()
    p.fail()
    assert p.state is PlanarState.ERROR_PENDING
    p.fail()
    p.update()
    assert p.state is PlanarState.ERROR
    with rejected(ErrorId.PLANAR_WRONG_STATE):
        p.enable()
    p.reset()
    assert p.state is PlanarState.RESETTING
    p.update()
    assert p.state is PlanarState.ENABLED


@pytest.mark.parametrize("escalate", ["disable", "force_disable"])
def test_disable_during_the_error_makes_the_reset_end_disabled(escalate):
    p = part(PART_1, 0.0, 0.0)
    p.enable()
    p.update()
    p.fail()
    p.update()
    getattr(p, escalate)()
    assert p.state is PlanarState.ERROR
    p.reset()
    p.update()
    assert p.state is PlanarState.DISABLED


def test_reset_needs_an_error_and_an_error_while_resetting_fails_it():
    p = part(PART_1, 0.0, 0.0)
    with rejected(ErrorId.PLANAR_WRONG_STATE):
        p.reset()
    p.fail()
    p.update()
    p.reset()
    p.fail()
    assert p.state is PlanarState.ERROR
    p.reset()
    p.update()
    assert p.state is PlanarState.DISABLED


class PartStates(RuleBasedStateMachine):
    """Whatever the order of commands, a force-disabled part never comes on (§6.6)."""

    def __init__(self) -> None:
        super().__init__()
        self.part = part(PART_1, 0.0, 0.0)

    @rule(command=st.sampled_from(["allow_enable", "force_disable", "disable", "fail", "update",
                                   "enable", "reset"]))
    def command(self, command):
        with contextlib.suppress(CommandRejected):
            getattr(self.part, command)()

    @invariant()
    def forced_means_off(self):
        if self.part.disable_forced:
            assert self.part.state not in (PlanarState.ENABLING, PlanarState.ENABLED)


PartStates.TestCase.settings = settings(max_examples=40, stateful_step_count=25)
TestPartStates = PartStates.TestCase


def test_parts_follow_the_movers_of_their_coordinate_system():
    layout = elevator_layout()
    layout.part(PART_2).force_disable()
    layout.follow_movers({CS_2})
    layout.update()
    states = {oid: p.state for oid, p in layout.parts.items()}
    assert states == {PART_1: PlanarState.DISABLED, PART_2: PlanarState.DISABLED,
                      PART_3: PlanarState.ENABLED}
    layout.follow_movers({CS_1})
    layout.update()
    states = {oid: p.state for oid, p in layout.parts.items()}
    assert states == {PART_1: PlanarState.ENABLED, PART_2: PlanarState.DISABLED,
                      PART_3: PlanarState.DISABLED}


# --- part positions (§6.6, §7.2.2.9.2) -----------------------------------------------------

def elevator_layout() -> PartLayout:
    """§6.6.1: parts 1 and 2 at the origins of CS 1 and CS 2; part 3 above either (inferred:
    SetPos.y > 300 on part 3 puts its origin at (0, 240)); part 3 starts in CS 2."""
    elevator = Part(PART_3, [(0.0, 0.0)], [PartPosition(CS_1, Pose(0.0, 240.0)),
                                          PartPosition(CS_2, Pose(0.0, 240.0))],
                    position_index=2)
    return PartLayout([CS_1, CS_2], [part(PART_1, 0.0, 0.0), part(PART_2, 0.0, 0.0, system=CS_2),
                                     elevator])


def test_activate_position_moves_the_part_and_its_surface():
    layout = elevator_layout()
    elevator = layout.part(PART_3)
    assert elevator.active_position == PartPosition(CS_2, Pose(0.0, 240.0))
    layout.activate_position(PART_3, 1)
    assert elevator.position_index == 1
    assert elevator.active_position.coordinate_system == CS_1
    assert layout.surface(CS_1).equals(shapely.box(0.0, 0.0, S, 2 * S))
    assert layout.surface(CS_2).equals(shapely.box(0.0, 0.0, S, S))
    assert elevator.surface(2).equals(shapely.box(0.0, S, S, 2 * S))


@pytest.mark.parametrize("index", [0, 3, True, 1.0])
def test_activate_position_rejects_an_index_it_does_not_have(index):
    with rejected(ErrorId.PLANAR_INVALID_INPUT):
        elevator_layout().activate_position(PART_3, index)


def test_activate_position_rejections():
    layout = elevator_layout()
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        layout.activate_position(0x01010090, 1)
    layout.part(PART_3).fail()
    with rejected(ErrorId.PLANAR_WRONG_STATE):
        layout.activate_position(PART_3, 1)


def test_a_part_cannot_move_onto_another_part():
    shuttle = Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_1, Pose(240.0, 0.0)),
                                         PartPosition(CS_1, Pose(120.0, 0.0))])
    layout = PartLayout([CS_1], [part(PART_1, 0.0, 0.0), shuttle])
    with rejected(ErrorId.PLANAR_COLLISION):
        layout.activate_position(PART_2, 2)
    assert shuttle.position_index == 1


# --- ReferenceId (§5.3) --------------------------------------------------------------------

def two_parts() -> PartLayout:
    """§6.1.4 / §6.1.7: two static one-stator parts side by side in one coordinate system."""
    return PartLayout([CS_1], [part(PART_1, 0.0, 0.0), part(PART_2, 240.0, 0.0)])


def test_zero_maps_to_the_only_static_coordinate_system():
    assert two_parts().is_static
    assert two_parts().to_coordinate_system(0, Pose(1.0, 2.0, 3.0)) == (CS_1, (1.0, 2.0, 3.0))


def test_zero_is_rejected_with_two_coordinate_systems():
    layout = PartLayout([CS_1, CS_2], [part(PART_1, 0.0, 0.0)])
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        layout.to_coordinate_system(0, Pose())


def test_zero_is_rejected_with_a_movable_part_in_one_system():
    shuttle = Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_1, Pose(240.0, 0.0)),
                                         PartPosition(CS_1, Pose(0.0, 240.0))])
    layout = PartLayout([CS_1], [part(PART_1, 0.0, 0.0), shuttle])
    assert not layout.is_static
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        layout.resolve_target(0, Pose(10.0, 10.0))


@pytest.mark.parametrize("oid", [1, 0x01010040, 0xFFFFFFFF])
def test_an_unknown_id_is_always_rejected(oid):
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        two_parts().to_coordinate_system(oid, Pose())
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        two_parts().part(oid)


def test_a_coordinate_system_id_is_the_identity():
    assert two_parts().resolve_target(CS_1, Pose(400.0, 10.0, 7.0)) == (CS_1, (400.0, 10.0, 7.0))


def test_a_rotated_part_turns_the_target_and_its_orientation():
    turned = part(PART_2, 480.0, 0.0, c=90.0)  # occupies x 240..480 in CS 1
    layout = PartLayout([CS_1], [part(PART_1, 0.0, 0.0), turned])
    assert layout.resolve_target(PART_2, Pose(100.0, 20.0, 5.0)) == (CS_1, (460.0, 100.0, 95.0))
    assert layout.position_on_current_part(CS_1, Pose(460.0, 100.0, 95.0)) == (
        PART_2, (100.0, 20.0, 5.0))


def test_a_target_given_on_a_part_must_lie_on_it():
    """§6.1.7: past the edge of part 1 the id of part 2 must be used (and x - 240)."""
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        two_parts().resolve_target(PART_1, Pose(300.0, 100.0))
    assert two_parts().resolve_target(PART_1, Pose(240.0, 100.0)) == (CS_1, (240.0, 100.0, 0.0))


def test_a_target_on_a_part_in_another_system_is_not_enabled():
    with rejected(ErrorId.PLANAR_PART_NOT_ENABLED):
        elevator_layout().resolve_target(PART_3, Pose(120.0, 120.0), coordinate_system=CS_1)


def test_a_target_in_another_coordinate_system_is_rejected():
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        elevator_layout().resolve_target(CS_2, Pose(120.0, 120.0), coordinate_system=CS_1)


def test_a_target_where_a_part_is_not_in_position_is_not_enabled():
    layout = elevator_layout()
    with rejected(ErrorId.PLANAR_PART_NOT_ENABLED) as info:
        layout.resolve_target(CS_1, Pose(120.0, 360.0))
    assert "part 16#01010080 in position 1, but position 2 is active" in str(info.value)
    with rejected(ErrorId.PLANAR_PART_NOT_ENABLED) as info:
        layout.resolve_target(CS_1, Pose(600.0, 120.0))
    assert "lies on no part" in str(info.value)


# --- crossing between parts (§6.2.3, issue: only where the parts meet) -----------------------

def grid_layout(*corners: tuple[float, float]) -> PartLayout:
    """One-stator parts at these corners of CS 1, OIDs 1, 2, 3, ..."""
    return PartLayout([CS_1], [part(i, x, y) for i, (x, y) in enumerate(corners, start=1)])


def test_a_move_crosses_where_two_parts_share_an_edge():
    layout = grid_layout((0.0, 0.0), (240.0, 0.0))
    assert layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (360.0, 200.0)])
    assert layout.path_stays_on_surface(CS_1, [(0.0, 0.0), (480.0, 240.0)])
    assert not layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (500.0, 120.0)])


def test_a_move_cannot_jump_a_gap():
    layout = grid_layout((0.0, 0.0), (480.0, 0.0))
    assert not layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (600.0, 120.0)])


def test_a_partial_edge_joins_only_where_it_is():
    layout = grid_layout((0.0, 0.0), (240.0, 120.0))
    assert layout.path_stays_on_surface(CS_1, [(120.0, 200.0), (360.0, 200.0)])
    assert layout.path_stays_on_surface(CS_1, [(200.0, 230.0), (300.0, 250.0)])
    assert not layout.path_stays_on_surface(CS_1, [(120.0, 20.0), (360.0, 200.0)])


@pytest.mark.parametrize("path", [
    [(120.0, 120.0), (360.0, 360.0)],
    [(120.0, 120.0), (240.0, 240.0), (360.0, 360.0)],
    [(240.0, 240.0), (360.0, 360.0), (240.0, 240.0), (120.0, 120.0)],
])
def test_parts_touching_at_a_corner_are_not_connected(path):
    layout = grid_layout((0.0, 0.0), (240.0, 240.0))
    assert layout.surface(CS_1).covers(LineString(path))
    assert not layout.path_stays_on_surface(CS_1, path)


def test_a_corner_shared_with_a_third_part_connects_through_it():
    layout = grid_layout((0.0, 0.0), (240.0, 240.0), (240.0, 0.0))
    assert layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (360.0, 360.0)])
    assert layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (240.0, 240.0), (360.0, 360.0)])


def test_a_pinch_in_one_polygon_is_no_connection():
    """The union is one polygon (its hole touches the outline at (240, 240)), but there only
    parts 1 and 2 meet, at a corner."""
    loop = [(0.0, 0.0), (240.0, 0.0), (480.0, 0.0)]
    layout = PartLayout([CS_1], [
        part(1, 0.0, 0.0), part(2, 240.0, 240.0),
        part(3, 480.0, 0.0, stators=[(0.0, 0.0), (0.0, 240.0), (0.0, 480.0)]),
        part(4, 0.0, -240.0, stators=loop),
    ])
    path = [(120.0, 120.0), (360.0, 360.0)]
    assert layout.surface(CS_1).geom_type == "Polygon"
    assert layout.surface(CS_1).covers(LineString(path))
    assert not layout.path_stays_on_surface(CS_1, path)
    assert layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (120.0, -120.0), (600.0, -120.0),
                                               (600.0, 360.0), (360.0, 360.0)])


def test_a_part_counts_only_in_its_active_position():
    layout = elevator_layout()
    up = [(120.0, 120.0), (120.0, 360.0)]
    assert not layout.path_stays_on_surface(CS_1, up)
    layout.activate_position(PART_3, 1)
    assert layout.path_stays_on_surface(CS_1, up)
    assert not layout.path_stays_on_surface(CS_2, [(120.0, 360.0)])


def test_a_standstill_stays_on_its_part():
    layout = grid_layout((0.0, 0.0))
    assert layout.path_stays_on_surface(CS_1, [(120.0, 120.0), (120.0, 120.0)])
    assert not layout.path_stays_on_surface(CS_1, [(-1.0, 120.0)])


U_SHAPE = PartLayout([CS_1], [
    part(1, 0.0, 0.0, stators=[(0.0, 0.0), (0.0, 240.0), (0.0, 480.0)]),
    part(2, 240.0, 0.0, stators=[(0.0, 0.0), (240.0, 0.0)]),
    part(3, 720.0, 0.0, stators=[(0.0, 0.0), (0.0, 240.0), (0.0, 480.0)]),
])
half_mm = st.integers(-200, 2120).map(lambda n: n / 2)  # grid points: no sub-µm near misses
points = st.tuples(half_mm, half_mm)


@given(start=points, end=points)
def test_without_corner_contacts_crossing_equals_shapely_covers(start, end):
    """Parts that meet only along edges: the path check is shapely's ``covers``."""
    path = [start, end]
    covered = U_SHAPE.surface(CS_1).covers(LineString(path)) if start != end \
        else U_SHAPE.surface(CS_1).covers(shapely.Point(start))
    assert U_SHAPE.path_stays_on_surface(CS_1, path) == covered


def test_position_on_current_part_keeps_the_current_part_on_an_edge():
    layout = two_parts()
    edge = Pose(240.0, 100.0, 0.0)
    assert layout.position_on_current_part(CS_1, edge) == (PART_1, (240.0, 100.0, 0.0))
    assert layout.position_on_current_part(CS_1, edge, current_part=PART_2) == (
        PART_2, (0.0, 100.0, 0.0))
    with rejected(ErrorId.PLANAR_PART_NOT_ENABLED):
        layout.position_on_current_part(CS_1, Pose(600.0, 100.0))


# --- worked examples ------------------------------------------------------------------------

def test_section_5_1_one_place_in_several_frames():
    """§5.1: P1 = (480,480,A) = (0,0,part 3) = (0,480,part 2) = (480,480,part 1) while part 3 is
    in A; after it moves to B, P2 = (480,480,B) = (0,0,part 3) = (480,480,part 4). The origins
    follow from these equalities; the part sizes (2 x 2 stators) are not printed (inferred)."""
    cs_a, cs_b = 0x01010060, 0x01010070
    square = [(0.0, 0.0), (240.0, 0.0), (0.0, 240.0), (240.0, 240.0)]
    part_3 = Part(0x01010080, square, [PartPosition(cs_a, Pose(480.0, 480.0)),
                                      PartPosition(cs_b, Pose(480.0, 480.0))])
    layout = PartLayout([cs_a, cs_b], [
        part(0x01010020, 0.0, 0.0, system=cs_a, stators=square),
        part(0x01010030, 480.0, 0.0, system=cs_a, stators=square),
        part_3, part(0x01010090, 0.0, 0.0, system=cs_b, stators=square),
    ])
    p1 = (cs_a, (480.0, 480.0, 0.0))
    for oid, local in [(0x01010080, Pose(0.0, 0.0)), (0x01010030, Pose(0.0, 480.0)),
                       (0x01010020, Pose(480.0, 480.0)), (cs_a, Pose(480.0, 480.0))]:
        assert layout.resolve_target(oid, local) == p1
    layout.activate_position(0x01010080, 2)
    p2 = (cs_b, (480.0, 480.0, 0.0))
    for oid, local in [(0x01010080, Pose(0.0, 0.0)), (0x01010090, Pose(480.0, 480.0))]:
        assert layout.resolve_target(oid, local) == p2
    with rejected(ErrorId.PLANAR_PART_NOT_ENABLED):  # P1 can no longer be given on part 3
        layout.resolve_target(0x01010080, Pose(0.0, 0.0), coordinate_system=cs_a)


def test_section_6_1_4_target_on_the_right_part():
    """§6.1.4: target (100, 100) on the right part 16#01010030; the mover, from P1 (120, 120)
    on the left part, ends at SetPos (340, 100) in 16#01010060 (PhysicalAreaID 16842848)."""
    layout = two_parts()
    system, target = layout.resolve_target(PART_2, Pose(100.0, 100.0, 0.0), CS_1)
    assert (system, target) == (16842848, (340.0, 100.0, 0.0))
    assert layout.path_stays_on_surface(system, [(120.0, 120.0), (target.x, target.y)])
    assert layout.position_on_current_part(system, target) == (PART_2, (100.0, 100.0, 0.0))


def test_section_6_1_7_reference_ids_of_external_setpoints():
    """§6.1.7: in the static two-part layout the setpoints may use part 1's id, the coordinate
    system's id or 0; past x = 240 part 2's id with x - 240 names the same place.

    The printed profile (jerk 10, up to 100 mm/s², dt 0.01 s) would run about 10 m, which the
    reported end x = 223.2495 contradicts (digest §8 item 3); we test the consistent reading:
    the mover ends on part 1 at the reported position."""
    layout = two_parts()
    end = Pose(223.2495, 120.0357, 0.0)
    same = {layout.resolve_target(ref, end, CS_1) for ref in (0, PART_1, CS_1)}
    assert same == {(CS_1, end)}
    assert layout.position_on_current_part(CS_1, end) == (PART_1, end)
    for x in (240.0, 250.0, 470.0):
        assert layout.resolve_target(PART_2, Pose(x - 240.0, 120.0), CS_1) == \
            layout.resolve_target(CS_1, Pose(x, 120.0), CS_1)
    with rejected(ErrorId.INVALID_REFERENCE_ID):
        layout.resolve_target(PART_1, Pose(250.0, 120.0), CS_1)


def test_section_6_6_1_the_mover_rides_the_elevator():
    """§6.6.1: part 3 goes to CS 1 (index 1), the mover drives onto it (SetPos.y > 300), part 3
    goes back to CS 2 (index 2) carrying the mover, which then drives to (120, 120) on part 2:
    SetPos (120, 120) in PhysicalAreaID 16#010100A0."""
    layout = elevator_layout()
    mover = (CS_1, Pose(120.0, 120.0, 0.0))  # the middle of part 1
    layout.follow_movers({mover[0]})
    layout.update()
    with rejected(ErrorId.PLANAR_PART_NOT_ENABLED):  # why the example activates index 1 first
        layout.resolve_target(PART_3, Pose(120.0, 120.0, 0.0), mover[0])

    layout.activate_position(PART_3, 1)
    layout.follow_movers({mover[0]})
    layout.update()
    target = layout.resolve_target(PART_3, Pose(120.0, 120.0, 0.0), mover[0])
    assert target == (CS_1, (120.0, 360.0, 0.0)) and target[1].y > 300.0
    assert layout.path_stays_on_surface(CS_1, [mover[1][:2], target[1][:2]])

    on_part = layout.position_on_current_part(*target)
    layout.activate_position(PART_3, 2)
    mover = layout.to_coordinate_system(*on_part)
    assert mover == (CS_2, (120.0, 360.0, 0.0))
    layout.follow_movers({mover[0]})
    layout.update()
    assert [p.state for p in layout.parts.values()] == [
        PlanarState.DISABLED, PlanarState.ENABLED, PlanarState.ENABLED]

    target = layout.resolve_target(PART_2, Pose(120.0, 120.0, 0.0), mover[0])
    assert target == (0x010100A0, (120.0, 120.0, 0.0))
    assert layout.path_stays_on_surface(CS_2, [mover[1][:2], target[1][:2]])
    with rejected(ErrorId.INVALID_REFERENCE_ID):  # two systems and a movable part: no 0
        layout.resolve_target(0, Pose(120.0, 120.0, 0.0), mover[0])
