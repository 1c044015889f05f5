"""The KHR-3HV as Kondo builds it: its home pose (every servo at 7500, as Kondo's sample
project's home-position motion holds) stands with level soles and left-right symmetric, and a
side step of our own (hth4.keyframes) and its mirror image go opposite ways, and Kondo's kick
stands on one foot. Played through the public CLI (``project simulate --physics --json``)."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv import hth4
from rcb4hv.cli.main import cli
from rcb4hv.hth4.edit import mirror_motion
from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.hth4.poses import Checks
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.geometry import stance
from rcb4hv.robot.kinematics import apply
from tests.physics.conftest import PROJECT

KHR = load_builtin("khr3hv")
HOME = dict.fromkeys(KHR.indices, 7500)
STEP, MIRROR, STAND, KICK = 18, 19, 20, 38  # free slots of the fixture
DATE = "2026/11/26"


def _pose(**counts: int) -> dict[int, int]:
    """HOME with ``c14=600`` style offsets (counts from 7500 by servo index)."""
    return HOME | {int(k[1:]): 7500 + v for k, v in counts.items()}


def _side_step_left() -> list[Keyframe]:
    """Our own small step to the left: crouch, weight onto the right foot (both hip and ankle
    rolls 200 counts), lift the left foot and roll it 200 counts outward, put it down, weight
    onto the left foot, lift the right foot, bring it in, stand."""
    crouch = {"c14": 600, "c15": -600, "c16": 1200, "c17": -1200, "c18": -600, "c19": 600}
    lift_l = crouch | {"c14": 900, "c16": 1800, "c18": -900}
    lift_r = crouch | {"c15": -900, "c17": -1800, "c19": 900}
    right = {"c12": 200, "c13": 200, "c20": 200, "c21": 200}
    out = {"c12": 400, "c13": 200, "c20": 400, "c21": 200}
    mid = {"c12": 200, "c13": 0, "c20": 200, "c21": 0}
    left_out = {"c12": 0, "c13": -200, "c20": 0, "c21": -200}
    left = {"c12": -200, "c13": -200, "c20": -200, "c21": -200}
    poses = [
        _pose(**crouch),
        _pose(**crouch, **right),
        _pose(**lift_l, **out),
        _pose(**crouch, **out),
        _pose(**crouch, **mid),
        _pose(**crouch, **left_out),
        _pose(**lift_r, **left_out),
        _pose(**lift_r, **left),
        _pose(**crouch, **left),
        _pose(**crouch),
    ]
    return [Keyframe(0.4 if i == 0 else 0.6, p) for i, p in enumerate(poses)]


# Kondo's "kick the ball forward (left leg)" (Hello_KHR3(V2.3).h4p, HLO026): its poses as
# counts from 7500 by servo index, with their frame counts at its 15 ms output period. Both hip
# rolls and both ankle rolls turn the same way, so the whole robot leans over the right foot and
# the left one comes off the floor; the right sole must reach far enough outward to carry it.
# fmt: off
_KICK: list[tuple[int, dict[int, int]]] = [
    (14, {2: -500, 3: 500, 4: 200, 5: -200, 8: -1000, 9: 1000, 14: 500, 15: -500,
          16: 1000, 17: -1000, 18: -550, 19: 550}),
    (10, {2: -500, 3: 500, 4: 200, 5: -200, 8: -1000, 9: 1000, 12: -200, 13: -200, 14: 500,
          15: -500, 16: 1000, 17: -1000, 18: -550, 19: 550, 20: 300, 21: 100}),
    (13, {3: 1500, 4: 200, 5: -700, 8: -2000, 9: 2000, 12: -400, 13: -400, 15: -500,
          16: 1000, 17: -1000, 18: -700, 19: 550, 20: 100, 21: 100}),
    (5, {2: -1500, 4: 200, 5: -700, 8: -2000, 9: 2000, 12: -400, 13: -400, 14: 2000,
         15: -500, 17: -1000, 18: 400, 19: 550, 20: 100, 21: 150}),
    (4, {2: -1500, 4: 200, 5: -700, 8: -2000, 9: 2000, 12: -400, 13: -400, 14: 2300,
         15: -500, 17: -1000, 18: 400, 19: 550, 20: 150, 21: 150}),
    (14, {2: -500, 3: 500, 4: 200, 5: -700, 8: -1000, 9: 1000, 12: -250, 13: -400, 14: 1000,
          15: -500, 16: 1600, 17: -1000, 18: -750, 19: 500, 20: 300, 21: 150}),
    (20, {2: -500, 3: 500, 4: 200, 5: -200, 8: -1000, 9: 1000, 14: 500, 15: -500,
          16: 1000, 17: -1000, 18: -550, 19: 550}),
    (40, {}),
]
# fmt: on


def _kick() -> list[Keyframe]:
    return [
        Keyframe(frames * 0.015, HOME | {k: 7500 + v for k, v in counts.items()})
        for frames, counts in _KICK
    ]


@pytest.fixture(scope="module")
def khr_project(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The fixture project with the KHR-3HV's servos (trim 0, no startup motion), our step in
    slot 18, its mirror image in 19, a plain home pose in 20 and Kondo's kick in 38."""
    base = hth4.load_project(PROJECT)
    servos = tuple(
        replace(s, mode="Normal" if s.device_number in KHR.indices else "None", name=None, trim=0)
        for s in base.servos
    )
    project = replace(base, servos=servos, startup_motion_address=-1)
    step = motion_from_keyframes(_side_step_left(), slot=STEP, name="step left", date=DATE)
    home = motion_from_keyframes([Keyframe(0.5, HOME)], slot=STAND, name="home", date=DATE)
    kick = motion_from_keyframes(_kick(), slot=KICK, name="kick (left)", date=DATE)
    project = add_motion(add_motion(add_motion(project, step), home), kick)
    project = mirror_motion(project, STEP, KHR, to=MIRROR, name="step right", checks=Checks(KHR))
    path = tmp_path_factory.mktemp("khr") / "khr.h4p"
    hth4.save_project(project, path)
    return path


def _physics(path: Path, *slots: int) -> dict[int, dict[str, object]]:
    args = ["project", "simulate", str(path), "--physics", "--json", "--robot", "khr3hv"]
    result = CliRunner().invoke(cli, args + [a for s in slots for a in ("--motion", str(s))])
    data = json.loads(result.output)
    return {m["slot"]: m["physics"] for m in data["motions"]}


def test_home_pose_stands_with_level_soles_and_symmetric() -> None:
    s = stance(KHR, KHR.motion_angles(HOME))
    lf, rf = (apply(s.frames[f], (0.0, 0.0, 0.0)) for f in ("l_foot", "r_foot"))
    assert lf[1] == pytest.approx(-rf[1]) and lf[1] > 0.01  # left is +y, mirror images
    assert lf[2] == pytest.approx(rf[2]) and lf[0] == pytest.approx(rf[0])
    for foot in ("l_foot", "r_foot"):  # each sole's normal is vertical: flat on the floor
        assert s.frames[foot][2][2] == pytest.approx(1.0)
    assert s.com[1] == pytest.approx(0.0, abs=1e-9) and s.com_inside
    # the torso stands upright above the feet
    assert s.frames[KHR.root][2][2] == pytest.approx(1.0)
    assert math.isclose(s.com[0], (lf[0] + rf[0]) / 2, abs_tol=0.01)


def test_home_pose_stays_put_and_a_mirrored_step_goes_the_other_way(khr_project: Path) -> None:
    out = _physics(khr_project, STAND, STEP, MIRROR)
    home, left, right = out[STAND], out[STEP], out[MIRROR]
    assert home["end_pose"] == "upright" and not home["fell"]
    assert abs(float(str(home["dx_m"]))) < 0.002 and abs(float(str(home["dy_m"]))) < 0.002
    for o in (left, right):
        assert o["end_pose"] == "upright" and not o["fell"]
    dy_left, dy_right = float(str(left["dy_m"])), float(str(right["dy_m"]))
    assert dy_left > 0.002  # the step goes left ...
    assert dy_right == pytest.approx(-dy_left, abs=1e-3)  # ... and its mirror image right


def test_kondos_kick_stands_on_one_foot(khr_project: Path) -> None:
    """The robot leans over its right foot (both hip and ankle rolls one way), kicks with the
    left leg and comes back. With the 78 x 43 mm sole of a simplified contact model (SIP's)
    it fell over that foot's outer edge; on the foot plate as built (120 x 76.8 mm) it stands,
    as every KHR-3HV kicking with Kondo's sample does."""
    out = _physics(khr_project, KICK)[KICK]
    assert not out["fell"] and out["end_pose"] == "upright", out
    assert abs(float(str(out["dy_m"]))) < 0.03  # it stays where it stood
