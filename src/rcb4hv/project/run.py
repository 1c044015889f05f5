"""The one way to run a project's motions in simulation: :func:`run_motions`.

The CLI (``project simulate``, ``project check --physics``), the dashboard (the Project page's
simulation and the 3D preview), the benchmarks and the tests all call it, so one set of
defaults holds everywhere:

* ``limit=None`` (the default): a plain run lets a motion go on while it makes progress
  (:data:`~rcb4hv.project.simulate.PROGRESS_WINDOW`, at most
  :data:`~rcb4hv.project.simulate.MAX_LIMIT`); a physics run stops each motion after
  :data:`~rcb4hv.project.simulate.DEFAULT_LIMIT` (a robot in physics never stops changing its
  measured positions and sensors for certain, so the motion's own progress cannot end it);
* the board boots once (``Simulator.boot``) and the motions play one after another on it; with
  physics (``robot``) each motion gets a freshly booted robot stood on the floor in ``start``
  unless ``sequence`` (one robot for all, as a user plays them). The robot is booted and
  settled once and each motion plays on a copy of it (the same state to the bit, so the same
  outcomes as booting it again, in about four fifths of the time);
* ``hold="bound"`` (the default): each motion that reads the remote plays with the button it
  loops on held for :data:`HOLD_S` seconds, as a user drives the robot
  (:func:`bound_buttons`; Kondo's remote-driven walks stop at once when their button is not
  held);
* ``listener(board_time_s, board)`` hears every output period of the run and each motion's
  start: ask the board what it sends (:meth:`~rcb4hv.emulator.Board.sent_angles`, the one
  free/hold/angle rule). With physics and without ``sequence`` it hears each motion from its
  start on that motion's own board (the shared boot and settling before it are not replayed);
* ``progress`` hears each motion as it ends;
* ``stride``: a robot model whose no-slip travel (:mod:`rcb4hv.robot.stride`) each motion's
  sent poses are followed through, from the motion's start (``MotionRun.stride``); it needs
  no physics, and with physics it is the motion's design beside what the robot did.

The answer, :class:`~rcb4hv.project.runresult.SimulationRun`, has one JSON form (``--json``).
"""

from __future__ import annotations

import copy
import dataclasses
import math
import time
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Final, Literal

from rcb4hv.emulator import Board
from rcb4hv.errors import ProtocolError
from rcb4hv.project.runresult import MotionRun, SimulationRun
from rcb4hv.project.simulate import DEFAULT_LIMIT, Simulator
from rcb4hv.robot.stride import StrideTracker
from rcb4hv.rom.layout import MotionLayout
from rcb4hv.rom.older import play_layout

if TYPE_CHECKING:
    from rcb4hv.physics import PhysicsOptions
    from rcb4hv.project.physics_sim import PhysicsSimulator, StartPose
    from rcb4hv.robot.model import RobotModel

__all__ = ["HOLD_S", "Hold", "RunListener", "bound_buttons", "run_motions"]

Hold = int | Mapping[int, int] | Literal["bound"]
"""What is held as each motion starts: a button word for every motion, one per slot (a slot
not named: none), or ``"bound"``: each motion's own button (:func:`bound_buttons`)."""

HOLD_S: Final = 3.0
"""Seconds a bound button is held by default: a chosen figure, a few steps of a walk, as a
user holds the remote's button to walk."""

RunListener = Callable[[float, Board], None]
"""Called with the board time (s) and the board after every output period, and at each
motion's start."""


def run_motions(
    image: bytes,
    slots: Sequence[int],
    *,
    names: Mapping[int, str] | None = None,
    motion_layout: MotionLayout | None = None,
    limit: float | None = None,
    hold: Hold = "bound",
    hold_for: float = HOLD_S,
    robot: RobotModel | None = None,
    sequence: bool = False,
    start: StartPose = "upright",
    track: bool = False,
    listener: RunListener | None = None,
    progress: Callable[[MotionRun], None] | None = None,
    options: PhysicsOptions | None = None,
    stride: RobotModel | None = None,
) -> SimulationRun:
    """Boot ``image`` and play motion ``slots`` (see the module docstring for the defaults).

    ``names``: motion names by slot; ``hold``: held for ``hold_for`` seconds as each motion
    starts (:data:`Hold`; by default each motion's own remote button, as a user drives it);
    ``robot``: play on this robot in MuJoCo (``start``, ``sequence``, ``track``: keep the
    robot's path and pictures; ``options``: factors on the physics' chosen figures,
    :class:`~rcb4hv.physics.PhysicsOptions`). A boot that fails is reported in the
    answer and the motions are still played from the host (spec 11.4).
    """
    names = names or {}
    t0 = time.perf_counter()
    if stride is not None:
        listener = _StrideWatch(stride, listener)
    if hold == "bound":
        hold = bound_buttons(image, play_layout(image, motion_layout))
    if robot is None:
        if sequence or track or start != "upright" or options is not None:
            raise ValueError("sequence, track and start set up the robot of a physics run")
        sim = Simulator(image, motion_layout=motion_layout)
        return _play(sim, slots, names, limit, hold, hold_for, listener, progress, t0)
    return _run_physics(
        image, slots, names, motion_layout, robot, limit if limit is not None else DEFAULT_LIMIT,
        hold, hold_for, sequence, start, track, listener, progress, t0, options,
    )  # fmt: skip


def bound_buttons(image: bytes, motion_layout: MotionLayout) -> dict[int, int]:
    """``{slot: button word}``: the remote button(s) a user holds to drive each motion of
    ``image`` that reads the remote; motions that read no button are left out.

    A motion reads the remote with a button branch (HeartToHeart4's button compare box); it
    gets its table binding when one of its "buttons *equal*" branches tests that word (the
    KXR-L4R's slalom goes straight on UP+S3, its binding, and curves with CIRCLE or SQUARE
    added, tested first), else the word of its first such branch. Kondo's
    remote-driven walks loop while that word is held and stop at once without it, whatever
    starts them: the main loop's button table (which may name another word, e.g. S1 for a
    walk that loops on UP+S1) or another motion (a carrying walk, bound to no button of its
    own). A motion whose branches test for no word in particular (the KHR-3HV's remote walks
    go on while the buttons are *not equal* to none) gets its table binding. A motion that
    reads no button is not held: its table binding would only start it again from the main
    loop while the button is still down."""
    from rcb4hv.hth4.blocks.kinds import button_tests
    from rcb4hv.project.image import read_image

    try:
        motions = read_image(image, motion_layout).motions
    except ProtocolError:  # not a HeartToHeart4 image: no motions to read
        return {}
    out: dict[int, int] = {}
    for m in motions:
        tests = button_tests(m.frames)
        loop = [w for w, cond in tests if w and cond == "equal"]
        binding = m.bindings[0].buttons if m.bindings else 0
        if binding and binding in loop:
            out[m.slot] = binding  # the word that starts it is one it goes on with
        elif loop:
            out[m.slot] = loop[0]
        elif tests and binding:
            out[m.slot] = binding  # e.g. "while any button is down"
    return out


def _play(
    sim: Simulator,
    slots: Sequence[int],
    names: Mapping[int, str],
    limit: float | None,
    hold: int | Mapping[int, int],
    hold_for: float,
    listener: RunListener | None,
    progress: Callable[[MotionRun], None] | None,
    t0: float,
) -> SimulationRun:
    if listener is not None:
        _attach(listener, sim.board)
    boot = sim.boot()
    runs = []
    for slot in slots:
        run = _one(sim, slot, names, limit, hold, hold_for, listener)
        runs.append(run)
        if progress is not None:
            progress(run)
    return SimulationRun(boot, tuple(runs), sim.now, time.perf_counter() - t0)


class _StrideWatch:
    """A run listener that follows each motion's no-slip travel through the poses the board
    sends (motion space: the trim left out, hold and free keeping the last angle), then
    passes the period on to the caller's ``listener``."""

    def __init__(self, model: RobotModel, listener: RunListener | None) -> None:
        self._model = model
        self._listener = listener
        self._tracker: StrideTracker | None = None

    def begin(self) -> None:
        """A motion starts: its travel counts from here."""
        self._tracker = StrideTracker(self._model)

    def __call__(self, t: float, board: Board) -> None:
        if self._tracker is not None:
            sent = board.sent_angles(trim=False)
            values = {i: v for i, v in sent.items() if v is not None}
            self._tracker.update(self._model.motion_angles(values))  # unmapped: ignored
        if self._listener is not None:
            self._listener(t, board)

    def finish(self, run: MotionRun) -> MotionRun:
        """``run`` with the travel since :meth:`begin`."""
        tracker, self._tracker = self._tracker, None
        return run if tracker is None else dataclasses.replace(run, stride=tracker.stride)


def _attach(listener: RunListener, board: Board) -> None:
    """Let ``listener`` hear every output period of ``board``."""

    def relay(t: float, _outs: dict[int, int]) -> None:
        listener(t, board)

    board.add_output_listener(relay)


def _one(
    sim: Simulator,
    slot: int,
    names: Mapping[int, str],
    limit: float | None,
    hold: int | Mapping[int, int],
    hold_for: float,
    listener: RunListener | None,
) -> MotionRun:
    """Play ``slot`` on ``sim``: a :class:`MotionRun` (with physics: the simulator's own)."""
    from rcb4hv.project.physics_sim import PhysicsSimulator  # no MuJoCo needed to import

    start_s = sim.now
    if isinstance(listener, _StrideWatch):
        listener.begin()
    if listener is not None:
        listener(start_s, sim.board)
    address = sim.layout.address(slot)
    name = names.get(slot, "")
    word = hold.get(slot, 0) if isinstance(hold, Mapping) else hold
    r = sim.play(address, slot=slot, name=name, hold=word, hold_for=hold_for, limit=limit)
    run = sim.runs[-1] if isinstance(sim, PhysicsSimulator) else MotionRun(r, start_s=start_s)
    return listener.finish(run) if isinstance(listener, _StrideWatch) else run


def _run_physics(
    image: bytes,
    slots: Sequence[int],
    names: Mapping[int, str],
    motion_layout: MotionLayout | None,
    robot: RobotModel,
    limit: float,
    hold: int | Mapping[int, int],
    hold_for: float,
    sequence: bool,
    start: StartPose,
    track: bool,
    listener: RunListener | None,
    progress: Callable[[MotionRun], None] | None,
    t0: float,
    options: PhysicsOptions | None,
) -> SimulationRun:
    from rcb4hv.physics import engine_version
    from rcb4hv.project.physics_sim import SETTLE_S, PhysicsSimulator, pose_name
    from rcb4hv.project.physicsresult import PhysicsSetup

    engine = engine_version()
    runs: list[MotionRun] = []
    virtual = 0.0
    first: PhysicsSimulator | None = None
    sim: PhysicsSimulator | None = None
    for slot in slots:
        if first is None:
            first = PhysicsSimulator(image, robot, motion_layout=motion_layout, track=track,
                                     start=start, options=options)  # fmt: skip
            if sequence and listener is not None:
                _attach(listener, first.board)
            first.boot()
        if sequence:
            sim = first
        else:
            # every motion starts from the same booted and settled robot: a copy of the first
            # (the same state, so the same outcomes as booting it again; the robot model is
            # shared, never changed)
            if sim is not None:
                virtual += sim.now
            sim = copy.deepcopy(first, {id(robot): robot})
            if listener is not None:
                _attach(listener, sim.board)
        run = _one(sim, slot, names, limit, hold, hold_for, listener)
        runs.append(run)
        if progress is not None:
            progress(run)
    if sim is None or first is None or first.boot_result is None or first.settled is None:
        raise ValueError("no motions to play")
    virtual += sim.now
    settled = first.settled
    setup = PhysicsSetup(
        robot.name, engine, start, SETTLE_S, pose_name(settled), math.degrees(settled.tilt),
        options.changed() if options is not None else (),
    )  # fmt: skip
    wall = time.perf_counter() - t0
    return SimulationRun(first.boot_result, tuple(runs), virtual, wall, setup)
