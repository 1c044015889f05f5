"""Pose edits on the fixture project: listing, changing, inserting, deleting, reordering."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rcb4hv import hth4
from rcb4hv.errors import EditError
from rcb4hv.hth4.edit import (
    bind_button,
    delete_pose,
    duplicate_pose,
    insert_pose,
    move_motion,
    move_pose,
    new_motion,
    rename_motion,
    set_home,
    set_pose,
    set_trim,
)
from rcb4hv.hth4.motioncode import branch_target, split_frames
from rcb4hv.hth4.poses import Checks, motion_blocks, motion_poses
from rcb4hv.protocol import RunConstFrameServo, decode_command
from tests.hth4._hth4_fixtures import fixture
from tests.hth4._model import kxr_like

TURN_LEFT = 69


@pytest.fixture(scope="module")
def project() -> hth4.Project:
    return hth4.load_project(fixture("HAC_KXR_HTH4_project.h4p"))


def _others_same(a: hth4.Project, b: hth4.Project, *slots: int) -> None:
    for ma, mb in zip(a.motions, b.motions, strict=True):
        if ma.slot not in slots:
            assert ma == mb, ma.slot


def _roundtrips(p: hth4.Project) -> bytes:
    data = hth4.dump_project(p)
    assert hth4.dump_project(hth4.parse_project(data)) == data
    assert hth4.parse_project(data) == p
    return data


def test_poses_and_blocks_of_turn_left(project: hth4.Project) -> None:
    m = project.motion(TURN_LEFT)
    poses = motion_poses(m)
    assert [p.speed for p in poses] == [3, 5, 20, 10]
    assert [p.entry for p in poses] == [0, 1, 2, 5]
    assert poses[0].values[10] == 8150 and poses[0].values[11] == 7000
    kinds = [b.kind for b in motion_blocks(m)]
    assert kinds == ["pose"] * 3 + ["Sub", "Jump", "pose", "Return", "Jump", "Return"]
    assert not motion_blocks(m)[3].editable
    # every pose entry is exactly one RunConstFrameServo frame
    for p in poses:
        assert decode_command(m.frames[p.entry]) == RunConstFrameServo(
            p.speed, p.positions, p.set_update_flag
        )


def test_set_pose_changes_one_entry_only(project: hth4.Project) -> None:
    edited = set_pose(project, TURN_LEFT, 1, {10: 8000}, speed=7)
    _others_same(project, edited, TURN_LEFT)
    before, after = project.motion(TURN_LEFT).frames, edited.motion(TURN_LEFT).frames
    assert [i for i in range(len(before)) if before[i] != after[i]] == [1]
    pose = motion_poses(edited.motion(TURN_LEFT))[1]
    assert pose.speed == 7 and pose.values[10] == 8000
    assert {k: v for k, v in pose.values.items() if k != 10} == {
        k: v for k, v in motion_poses(project.motion(TURN_LEFT))[1].values.items() if k != 10
    }
    old = hth4.dump_project(project)
    new = _roundtrips(edited)
    assert len(old) == len(new)  # same-length frame, same hex text length


def test_edits_check_documented_ranges_and_joint_limits(project: hth4.Project) -> None:
    # past the documented 3500..11500 only warns (Kondo's own motions command 12700)
    kept = set_pose(project, TURN_LEFT, 0, {10: 12000})
    assert motion_poses(kept.motion(TURN_LEFT))[0].values[10] == 12000
    with pytest.raises(EditError, match=r"20000 is no ICS position"):
        set_pose(project, TURN_LEFT, 0, {10: 20000})
    with pytest.raises(EditError, match="frame count 0"):
        set_pose(project, TURN_LEFT, 0, speed=0)
    forced = set_pose(project, TURN_LEFT, 0, {10: 20000}, checks=Checks(force=True))
    assert motion_poses(forced.motion(TURN_LEFT))[0].values[10] == 20000
    narrow = kxr_like(limit=0.1)  # +-5.7 degrees: 8150 counts is 21.9 degrees
    with pytest.raises(EditError, match=r"hip_pitch\): 8150 is 21.9 deg"):
        set_pose(project, TURN_LEFT, 0, {10: 8150}, checks=Checks(narrow))


def _targets(m: hth4.Motion) -> list[tuple[str, int | None]]:
    """For each branch: its kind and the entry index it lands on (None: outside)."""
    starts = [m.address]
    for e in m.frames:
        starts.append(starts[-1] + len(e))
    out = []
    for b in motion_blocks(m):
        if b.target is not None:
            out.append((b.kind, starts.index(b.target) if b.target in starts else None))
    return out


def test_insert_and_delete_move_the_branches_along(project: hth4.Project) -> None:
    slot = 1  # XL2G_101: branches into the middle of the motion
    m = project.motion(slot)
    blocks = motion_blocks(m)
    poses = motion_poses(m)
    inserted = insert_pose(project, slot, 1, poses[0].values, 4)
    mi = inserted.motion(slot)
    before = _targets(m)
    after = _targets(mi)
    # every branch lands on the same instruction, one entry later if it lay after the insert
    entry = poses[1].entry
    expected = [(k, t if t is None or t == 0 or t < entry else t + 1) for k, t in before]
    assert after == expected
    assert any(t is not None and t > entry for _, t in before)  # the test means something
    assert len(mi.frames) == len(blocks) + 1
    assert delete_pose(inserted, slot, 1) == project
    _others_same(project, inserted, slot)


def test_duplicate_and_move_pose(project: hth4.Project) -> None:
    p = duplicate_pose(project, TURN_LEFT, 0)
    poses = motion_poses(p.motion(TURN_LEFT))
    assert len(poses) == 5 and poses[0].positions == poses[1].positions
    moved = move_pose(project, TURN_LEFT, 0, 2)
    speeds = [x.speed for x in motion_poses(moved.motion(TURN_LEFT))]
    assert speeds == [5, 20, 3, 10]
    assert move_pose(moved, TURN_LEFT, 2, 0) == project
    with pytest.raises(EditError, match=r"within poses 1\.\.3"):
        move_pose(project, TURN_LEFT, 0, 3)  # pose 4 lies behind the button check
    with pytest.raises(EditError, match="no pose 9"):
        delete_pose(project, TURN_LEFT, 8)


def test_motion_level_edits(project: hth4.Project) -> None:
    p = rename_motion(project, TURN_LEFT, "turn left (edited)")
    assert p.motion(TURN_LEFT).name == "turn left (edited)"
    p = bind_button(p, TURN_LEFT, 2048 + 8)  # S3 + left: free in the fixture
    assert p.motion(TURN_LEFT).button == (2048 + 8, "Equals")
    with pytest.raises(EditError, match="already starts motion 11"):
        bind_button(project, TURN_LEFT, 8)
    # --force takes the binding: motion 11 loses it (both bound left one never playing)
    taken = bind_button(project, TURN_LEFT, 8, force=True)
    assert taken.motion(TURN_LEFT).button == (8, "Equals")
    assert taken.motion(11).button_data == 0
    assert [m.slot for m in taken.used_motions if m.button == (8, "Equals")] == [TURN_LEFT]
    assert bind_button(p, TURN_LEFT, 0).motion(TURN_LEFT).button_data == 0
    p = set_trim(p, 10, -200)
    assert p.servo(10).trim == -200
    with pytest.raises(EditError, match="trim 5000"):
        set_trim(p, 10, 5000)
    assert set_home(p, 10, 7600).servo(10).position == 7600
    p = new_motion(project, 73, "empty", date="2026-01-01T00:00:00.0000000+00:00")
    m = p.motion(73)
    assert m.name == "empty" and motion_poses(m) == ()
    p = insert_pose(p, 73, 0, {10: 7500, 11: 7500}, 10)
    assert [x.values for x in motion_poses(p.motion(73))] == [{10: 7500, 11: 7500}]
    with pytest.raises(EditError, match="holds 'HAC_KXR_TURN_LEFT'"):
        new_motion(project, TURN_LEFT, "x")


def test_move_motion_moves_every_reference(project: hth4.Project) -> None:
    startup = project.startup_motion
    assert startup is not None and startup.slot == 39
    moved = move_motion(project, 39, 80)
    assert moved.motion(39).is_empty and moved.motion(39).name == "M039"
    assert moved.startup_motion is not None and moved.startup_motion.slot == 80
    assert moved.motion(80).frames == startup.frames  # no branch inside
    low = move_motion(project, 40, 81)  # the low-battery priority motion, which loops
    ((_, prio),) = low.active_priority_motions
    assert prio.address == low.motion(81).address
    assert {t for _, t in _targets(low.motion(81))} == {t for _, t in _targets(project.motion(40))}
    _roundtrips(low)


EDITS = st.lists(
    st.tuples(
        st.sampled_from(["set", "insert", "delete", "duplicate", "move"]),
        st.sampled_from([1, 3, 17, 41, TURN_LEFT]),
        st.integers(0, 12),
        st.integers(3500, 11500),
        st.integers(1, 255),
    ),
    max_size=6,
)


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(edits=EDITS)
def test_random_edits_round_trip_and_undo(
    project: hth4.Project, edits: list[tuple[str, int, int, int, int]]
) -> None:
    from rcb4hv.hth4.session import EditSession

    session = EditSession(project)
    applied = 0
    for op, slot, index, value, speed in edits:
        n = len(motion_poses(session.project.motion(slot)))
        try:
            if op == "set":
                session.apply(set_pose, slot, index % n, {10: value}, speed)
            elif op == "insert":
                session.apply(insert_pose, slot, index % (n + 1), {10: value, 11: value}, speed)
            elif op == "delete" and n > 1:
                session.apply(delete_pose, slot, index % n)
            elif op == "duplicate":
                session.apply(duplicate_pose, slot, index % n)
            elif op == "move":
                session.apply(move_pose, slot, index % n, (index + 1) % n)
            else:
                continue
        except EditError:
            continue  # a refused edit leaves the session as it was
        applied += 1
        for m in session.project.used_motions:
            for e in m.frames:  # every entry still cuts into valid frames
                frames, tail = split_frames(e)
                assert frames and tail in (b"", b"\xff")
                for f in frames:
                    t = branch_target(f)
                    assert t is None or t == 0xFFFFFF or t >= 0x0B80
    assert len(session.history) <= applied
    final = session.project
    _roundtrips(final)
    # the lint finds nothing new: every branch still lands on an instruction
    from rcb4hv.project.check import check_project

    assert [f for f in check_project(final) if f.severity == "error"] == []
    while session.can_undo:
        session.undo()
    assert session.project == project  # the same model: the same bytes when saved
    while session.can_redo:
        session.redo()
    assert session.project == final


def test_fixture_file_is_untouched(tmp_path: Path, project: hth4.Project) -> None:
    src = fixture("HAC_KXR_HTH4_project.h4p")
    assert hth4.dump_project(project) == src.read_bytes()
