"""Hard limits refuse, advisory ranges only warn: the editor, the mirror and ``project check``
on the built-in models, with motions of our own (hth4.keyframes)."""

from __future__ import annotations

import logging
import math
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv import hth4
from rcb4hv.cli.main import cli
from rcb4hv.errors import EditError, JointLimitError
from rcb4hv.hth4.edit import mirror_motion, set_pose
from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.hth4.poses import Checks, motion_poses
from rcb4hv.project.check import check_project
from rcb4hv.robot.builtin import load_builtin
from tests.hth4._hth4_fixtures import fixture

KHR = load_builtin("khr3hv")
KXR = load_builtin("kxr-l2-gripper")
SLOT = 18  # empty in the fixture
DATE = "2026-11-26T12:00:00.0000000+00:00"
L_HIP_ROLL, R_HIP_ROLL = 12, 13  # KHR-3HV: side 0 (even) is the left


def _khr_walk_step() -> list[Keyframe]:
    """A sway of our own, both hips rolled 100 counts one way as a lateral sway does: the left
    hip roll at 7400 is 3.4 deg inward, past robotlearn's 0 deg; then a wide stance with the
    left hip 40 deg inward (6315), past anything robotlearn or Kondo's samples use."""
    home = dict.fromkeys(KHR.indices, 7500)
    sway = home | {L_HIP_ROLL: 7400, R_HIP_ROLL: 7400, 20: 7600, 21: 7600}
    step = sway | {14: 7300, 16: 7900, 18: 7300}  # lift the left leg a little
    cross = home | {L_HIP_ROLL: 6315}
    return [Keyframe(0.3, sway), Keyframe(0.3, step), Keyframe(0.3, cross), Keyframe(0.3, home)]


@pytest.fixture(scope="module")
def project() -> hth4.Project:
    """The fixture with our motion in slot 18 and the KHR-3HV's servos in its servo table."""
    base = hth4.load_project(fixture("HAC_KXR_HTH4_project.h4p"))
    motion = motion_from_keyframes(_khr_walk_step(), slot=SLOT, name="sway left", date=DATE)
    servos = tuple(
        replace(s, mode="Normal" if s.device_number in KHR.indices else "None", name=None)
        for s in base.servos
    )
    return add_motion(replace(base, servos=servos), motion)


def test_khr_hip_roll_past_robotlearn_is_neither_refused_nor_warned() -> None:
    angle = KHR.motion_angle(L_HIP_ROLL, 7400)
    assert math.degrees(angle) == pytest.approx(-3.375)  # past robotlearn's 0 deg: Kondo's own
    assert KHR.limit_check("l_hip_roll", angle) == "ok"
    assert math.degrees(KHR.joint("l_hip_roll").lower) == pytest.approx(-180.0)
    far = math.radians(-40.0)  # inward, past everything robotlearn and Kondo's samples use
    assert KHR.limit_check("l_hip_roll", far) == "advisory"
    assert KHR.out_of_limits({"l_hip_roll": far}) == []
    assert KHR.outside_advisory({"l_hip_roll": far, "r_hip_roll": 0.0}) == ["l_hip_roll"]
    assert KHR.out_of_limits({"l_hip_roll": math.radians(-181.0)}) == ["l_hip_roll"]


def test_mirroring_a_walk_with_hip_roll_at_7400_works_and_warns(
    project: hth4.Project, caplog: pytest.LogCaptureFixture
) -> None:
    with caplog.at_level(logging.WARNING, logger="rcb4hv.hth4.poses"):
        mirrored = mirror_motion(project, SLOT, KHR, to=SLOT + 1, checks=Checks(KHR), date=DATE)
    poses = motion_poses(mirrored.motion(SLOT + 1))
    # the left hip's 7400 is now the right hip's 7600 (roll: the counts change sign)
    assert poses[0].values[R_HIP_ROLL] == 7600 and poses[0].values[L_HIP_ROLL] == 7600
    assert poses[1].values[15] == 7700 and poses[1].values[17] == 7100  # the right leg lifts
    warned = [r.getMessage() for r in caplog.records]
    assert any("advisory range" in w and "kept" in w for w in warned), warned
    # mirroring back gives the motion again
    twice = mirror_motion(mirrored, SLOT + 1, KHR, checks=Checks(KHR), date=DATE)
    assert motion_poses(twice.motion(SLOT + 1)) == motion_poses(project.motion(SLOT))


def test_a_value_beyond_the_hard_limit_is_refused_with_a_typed_error(
    project: hth4.Project,
) -> None:
    # the KXR-L2's left shoulder roll stops at -30 deg (kxreus frame limit: its bracket)
    s = KXR.servo_for_joint("l_shoulder_roll")
    assert s is not None
    beyond = KXR.motion_value(s.index, math.radians(-37.0))
    with pytest.raises(JointLimitError, match=r"l_shoulder_roll\).*hard \(mechanical\) limits"):
        set_pose(project, SLOT, 0, {s.index: beyond}, checks=Checks(KXR))
    assert issubclass(JointLimitError, EditError)
    kept = set_pose(project, SLOT, 0, {s.index: beyond}, checks=Checks(KXR, force=True))
    assert motion_poses(kept.motion(SLOT))[0].values[s.index] == beyond


def test_checks_split_refusals_from_advisories() -> None:
    checks = Checks(KHR)
    assert checks.problems({L_HIP_ROLL: 7400}, 10) == checks.advisories({L_HIP_ROLL: 7400}) == []
    values = {L_HIP_ROLL: 6315, 16: 7500}
    assert checks.problems(values, 10) == []
    (advice,) = checks.advisories(values)
    assert advice.startswith("ICS 12 (l_hip_roll): 6315 is -40.0 deg, outside the joint's advisory")
    assert checks.check(values, 10, "pose") == [advice]


def test_project_check_warns_of_advisory_ranges_only_with_the_robot(
    project: hth4.Project, tmp_path: Path
) -> None:
    found = [f for f in check_project(project, KHR) if f.slot == SLOT]
    codes = {(f.code, f.severity) for f in found}
    assert codes == {("joint-advisory", "warning")}
    assert [f.reason.split(",")[0] for f in found] == ["l_hip_roll at -40.0 deg (value 6315)"]
    assert not [f for f in check_project(project) if f.slot == SLOT]
    path = tmp_path / "p.h4p"
    hth4.save_project(project, path)
    result = CliRunner().invoke(cli, ["project", "check", str(path), "--json", "--robot", "khr3hv"])
    assert '"joint-advisory"' in result.output


def test_every_builtin_has_its_advisory_range_inside_its_hard_limits() -> None:
    for name in ("khr3hv", "khr3hv-22", "kxr-l2", "kxr-l2-gripper"):
        model = load_builtin(name)
        for j in model.joints:
            lo, hi = j.advisory_range
            assert j.lower <= lo <= hi <= j.upper, (name, j.name)
            mirror = model.joint(j.mirror) if j.mirror else j
            m_lo, m_hi = mirror.advisory_range
            if j.kind in ("roll", "yaw"):
                m_lo, m_hi = -m_hi, -m_lo
            assert (m_lo, m_hi) == pytest.approx((lo, hi)), (name, j.name)
