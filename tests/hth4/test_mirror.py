"""Mirroring through the robot model: exact in counts, an involution, the fixture's own pairs."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv import hth4
from rcb4hv.errors import EditError, NoRobotModelError
from rcb4hv.hth4.edit import mirror_motion, mirror_pose
from rcb4hv.hth4.mirror import mirror_values
from rcb4hv.hth4.motioncode import branch_target
from rcb4hv.hth4.poses import Checks, motion_poses
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD
from tests.hth4._hth4_fixtures import fixture
from tests.hth4._model import PAIRS, kxr_like

TURN_LEFT, TURN_RIGHT = 69, 70
DATE = "2026-11-24T12:00:00.0000000+00:00"


@pytest.fixture(scope="module")
def project() -> hth4.Project:
    return hth4.load_project(fixture("HAC_KXR_HTH4_project.h4p"))


def test_mirrored_turn_left_is_the_fixtures_turn_right(project: hth4.Project) -> None:
    model = kxr_like()
    p = mirror_motion(project, TURN_LEFT, model, to=73, name="turn right (mirror)", date=DATE)
    made = p.motion(73)
    assert made.name == "turn right (mirror)" and made.button_data == 0 and made.date == DATE
    assert motion_poses(made) == motion_poses(project.motion(TURN_RIGHT))
    # the loop back to the start now jumps to the start of slot 73
    targets = {branch_target(f) for f in made.frames} - {None}
    assert targets == {made.address}
    assert made.address == project.motion(73).address
    for m in project.motions:
        if m.slot != 73:
            assert p.motion(m.slot) == m


def test_home_pose_is_its_own_mirror(project: hth4.Project) -> None:
    (home,) = motion_poses(project.motion(39))
    assert mirror_values(kxr_like(), home.values) == home.values


def test_mirror_twice_gives_every_fixture_motion_back(project: hth4.Project) -> None:
    model = kxr_like()
    checks = Checks(force=True)
    once = project
    for m in project.used_motions:
        once = mirror_motion(once, m.slot, model, checks=checks)
    assert once != project
    twice = once
    for m in project.used_motions:
        twice = mirror_motion(twice, m.slot, model, checks=checks)
    assert hth4.dump_project(twice) == hth4.dump_project(project)


def test_mirror_swaps_stretch_settings(project: hth4.Project) -> None:
    slot = 42  # XL2G_302: walks with the left gripper closed, stretch per servo
    p = mirror_motion(project, slot, kxr_like(), checks=Checks(force=True))
    from rcb4hv.protocol import SetStretch, decode_command

    before = [decode_command(f) for f in project.motion(slot).frames[:1]]
    after = [decode_command(f) for f in p.motion(slot).frames[:1]]
    assert isinstance(before[0], SetStretch) and isinstance(after[0], SetStretch)
    old = dict(before[0].values)
    swapped = {r: old[lf] for r, lf, *_ in PAIRS if lf in old} | {
        lf: old[r] for r, lf, *_ in PAIRS if r in old
    }
    assert dict(after[0].values) == swapped


def test_mirror_needs_a_model_and_a_free_slot(project: hth4.Project) -> None:
    with pytest.raises(NoRobotModelError, match="no model"):
        mirror_motion(project, TURN_LEFT, None, to=73)
    with pytest.raises(EditError, match="holds 'HAC_KXR_TURN_RIGHT'"):
        mirror_motion(project, TURN_LEFT, kxr_like(), to=TURN_RIGHT)
    one = mirror_pose(project, TURN_LEFT, 0, kxr_like())
    assert motion_poses(one.motion(TURN_LEFT))[0] == motion_poses(project.motion(TURN_RIGHT))[0]
    assert motion_poses(one.motion(TURN_LEFT))[1:] == motion_poses(project.motion(TURN_LEFT))[1:]


OFFSETS = st.dictionaries(st.integers(2, 19), st.integers(-300, 300), max_size=18)
VALUES = st.dictionaries(
    st.integers(0, 34),
    st.one_of(st.integers(4000, 11000), st.sampled_from([POSITION_HOLD, POSITION_FREE])),
    min_size=1,
)


@given(offsets=OFFSETS, values=VALUES)
def test_mirror_is_an_involution_for_any_offsets(
    offsets: dict[int, int], values: dict[int, int]
) -> None:
    model = kxr_like(offsets=offsets)
    assert mirror_values(model, mirror_values(model, values)) == values


@given(values=VALUES, trims=st.dictionaries(st.integers(2, 19), st.integers(-2000, 2000)))
def test_counts_formula_is_the_models_angle_round_trip(
    values: dict[int, int], trims: dict[int, int]
) -> None:
    """The exact integer mirror equals value(mirror_angles(angle)) through the trims."""
    model = kxr_like()
    mapped = {
        k: v for k, v in values.items() if 2 <= k <= 19 and v not in (POSITION_HOLD, POSITION_FREE)
    }
    angles = {
        model.servo(k).joint: model.angle(k, v + trims.get(k, 0), trims.get(k, 0))
        for k, v in mapped.items()
    }
    mirrored = model.mirror_angles(angles)
    via_model = {}
    for joint, a in mirrored.items():
        s = model.servo_for_joint(joint)
        assert s is not None
        via_model[s.index] = model.value(s.index, a, trims.get(s.index, 0)) - trims.get(s.index, 0)
    exact = mirror_values(model, mapped)
    assert exact == via_model
    assert all(math.isfinite(a) for a in angles.values())


def test_builtin_kxr_model_mirrors_the_fixture(project: hth4.Project) -> None:
    """The built-in KXR-L2 (gripper) joint map: turn left -> turn right, twice -> original."""
    from rcb4hv.robot.builtin import load_builtin

    model = load_builtin("kxr-l2-gripper")
    p = mirror_motion(project, TURN_LEFT, model, to=73, name="r", date=DATE)
    assert motion_poses(p.motion(73)) == motion_poses(project.motion(TURN_RIGHT))
    slots = [m.slot for m in project.used_motions]
    once = project
    for s in slots:
        once = mirror_motion(once, s, model, checks=Checks(force=True))
    twice = once
    for s in slots:
        twice = mirror_motion(twice, s, model, checks=Checks(force=True))
    assert hth4.dump_project(twice) == hth4.dump_project(project)


# Left/right pairs of the fixture that Kondo and the HAC project wrote as exact mirror images:
# fast walk left/right, fast turn left/right, jump turn, HAC walk left/right, HAC turn
# left/right, throw left/right. (The other pairs differ in a few hand-tuned values.)
EXACT_PAIRS = ((11, 12), (13, 14), (64, 65), (67, 68), (69, 70), (48, 56))


@pytest.mark.parametrize(("left", "right"), EXACT_PAIRS)
def test_builtin_model_reproduces_the_fixtures_mirror_pairs(
    project: hth4.Project, left: int, right: int
) -> None:
    from rcb4hv.hth4.robotpick import project_model

    model = project_model(project)
    assert model.name == "kxr-l2-gripper"
    p = mirror_motion(project, left, model, to=73, date=DATE)
    assert motion_poses(p.motion(73)) == motion_poses(project.motion(right))
    q = mirror_motion(project, right, model, to=73, date=DATE)
    assert motion_poses(q.motion(73)) == motion_poses(project.motion(left))
