"""A physics run boots and settles the robot once and gives each motion a copy of it
(``run_motions`` without ``sequence``): the copy is the same state, so it plays exactly as a
freshly booted robot does, and playing it leaves the original as it was."""

from __future__ import annotations

import copy

from rcb4hv.emulator import Board
from rcb4hv.project.physics_sim import PhysicsSimulator
from rcb4hv.project.run import run_motions
from tests.physics.test_fixture_motions import IMAGE, KXR, LAYOUT, NAMES

# the fixture's XL2G_103 (a fine step left, held on its button) and XL2G_201 (a bow)
STEP_LEFT, GREETING = 3, 21


def _booted() -> PhysicsSimulator:
    sim = PhysicsSimulator(IMAGE, KXR, motion_layout=LAYOUT)
    sim.boot()
    return sim


def _state(sim: PhysicsSimulator) -> tuple[list[float], list[float], bytes, float]:
    d = sim.world.d
    return d.qpos.tolist(), d.qvel.tolist(), bytes(sim.board.ram), sim.now


def test_a_copied_robot_plays_a_motion_exactly_as_a_freshly_booted_one() -> None:
    template = _booted()
    before = _state(template)
    copied = copy.deepcopy(template)
    assert _state(copied) == before
    fresh = _booted()
    for sim in (copied, fresh):
        sim.play(LAYOUT.address(STEP_LEFT), slot=STEP_LEFT, hold=0)
    assert copied.outcomes == fresh.outcomes
    assert _state(copied) == _state(fresh)  # to the bit: positions, speeds, RAM, clock
    assert copied.outcomes[0].dy_m > 0.005  # it stepped (a test that can fail)
    # the original did not move: the copy has its own board, MuJoCo data and servo gains
    assert _state(template) == before
    assert template.outcomes == []
    assert copied.world.m is not template.world.m and copied.board is not template.board


def test_the_copy_decodes_its_own_program() -> None:
    """The board's decoded instructions close over its RAM: a copy that kept them would run
    the motion on the original's memory (a checksum error at the first ROM fetch)."""
    template = _booted()
    copied = copy.deepcopy(template)
    res = copied.play(LAYOUT.address(GREETING), slot=GREETING, hold=0)
    assert res.status == "completed", res.error
    assert bytes(copied.board.ram) != bytes(template.board.ram)


def test_a_run_of_motions_hears_each_motion_and_reports_the_run_as_before() -> None:
    heard: list[tuple[int, float]] = []

    def listen(t: float, board: Board) -> None:
        heard.append((id(board), t))

    run = run_motions(
        IMAGE, [GREETING, STEP_LEFT], names=NAMES, robot=KXR, motion_layout=LAYOUT, hold=0,
        listener=listen,
    )  # fmt: skip
    boards = list(dict.fromkeys(b for b, _ in heard))
    assert len(boards) == 2  # each motion on its own robot
    assert [m.result.slot for m in run.motions] == [GREETING, STEP_LEFT]
    # each motion starts where the booted and settled robot stood, on the same clock
    assert run.motions[0].start_s == run.motions[1].start_s
    assert run.physics is not None and run.physics.settled_pose == "upright"
    # the run's virtual time counts each motion's own boot and settling, as before
    assert run.virtual_s > 2 * run.motions[0].start_s
