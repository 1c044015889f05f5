"""A project motion as instructions at ROM addresses, with its control flow (for the lint).

:func:`motion_code` cuts a :class:`rcb4hv.hth4.Motion` into its frames at their ROM addresses
(entries are laid out one after the other from ``Motion.address``, HeartToHeart4's ``FF``
end bytes included) and decodes each. :class:`MotionCode` answers which instructions a path
from the motion's start (or from other entry points) reaches and whether a path runs past the
last instruction.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rcb4hv.errors import ProtocolError
from rcb4hv.hth4 import Motion
from rcb4hv.project.image import split_frames
from rcb4hv.protocol import ALWAYS, Call, Command, Jump, Return, decode_command

__all__ = ["OFF_END", "MotionCode", "motion_code"]

OFF_END = -1
"""Successor marker: the path runs past the motion's last instruction."""


@dataclass
class MotionCode:
    """The instructions of one motion: ``items`` are (address, command or None, length)."""

    start: int
    size: int
    items: list[tuple[int, Command | None, int]] = field(default_factory=list)
    invalid: list[tuple[int, str, str]] = field(default_factory=list)

    @property
    def at(self) -> set[int]:
        """Addresses where an instruction starts."""
        return {a for a, _, _ in self.items}

    @property
    def instructions(self) -> list[tuple[int, Command]]:
        """(address, command) of every instruction that decodes, in ROM order."""
        return [(a, c) for a, c, _ in self.items if c is not None]

    def successors(self, index: int) -> list[int]:
        """Addresses the instruction ``items[index]`` can continue at (OFF_END: past the end)."""
        _, cmd, _ = self.items[index]
        nxt = self.items[index + 1][0] if index + 1 < len(self.items) else OFF_END
        if cmd is None or isinstance(cmd, Return):
            return []
        if isinstance(cmd, Jump):
            out = [] if cmd.condition == ALWAYS else [nxt]
            if cmd.address in self.at:
                out.append(cmd.address)
            return out
        if isinstance(cmd, Call) and cmd.address in self.at:
            return [nxt, cmd.address]
        return [nxt]

    def reachable(self, entries: set[int]) -> set[int]:
        """Addresses of the instructions some path from the start or ``entries`` reaches."""
        index = {a: i for i, (a, _, _) in enumerate(self.items)}
        todo = [a for a in {self.start, *entries} if a in index]
        seen: set[int] = set()
        while todo:
            a = todo.pop()
            if a in seen:
                continue
            seen.add(a)
            todo.extend(s for s in self.successors(index[a]) if s != OFF_END and s not in seen)
        return seen

    def falls_off(self, reached: set[int]) -> bool:
        """True if a reached instruction continues past the last one (into erased ROM)."""
        return any(
            OFF_END in self.successors(i) for i, (a, _, _) in enumerate(self.items) if a in reached
        )

    def unreachable_runs(self, reached: set[int]) -> list[tuple[int, int]]:
        """(first address, count) of each run of instructions no path reaches.

        A closing RETURN is not reported: HeartToHeart4 ends every motion with its own
        ``03 0D 10 FF`` after the flowchart's RETURN.
        """
        items = self.items
        if items and isinstance(items[-1][1], Return):
            items = items[:-1]
        runs: list[tuple[int, int]] = []
        previous_reached = True
        for a, _, _ in items:
            if a in reached:
                previous_reached = True
                continue
            if previous_reached:
                runs.append((a, 1))
            else:
                runs[-1] = (runs[-1][0], runs[-1][1] + 1)
            previous_reached = False
        return runs


def motion_code(motion: Motion) -> MotionCode:
    """The instructions of ``motion`` at their ROM addresses (entries that are not frames and
    frames that do not decode are listed in ``invalid`` with a reason)."""
    code = MotionCode(motion.address, len(motion.rom_bytes()))
    addr = motion.address
    for entry in motion.frames:
        try:
            frames, tail = split_frames(entry)
        except ProtocolError as exc:
            frames, tail = [], entry
            why = f"not a command frame: {exc}"
        else:
            why = "not a command frame"
        if not frames or tail.strip(b"\xff"):
            code.invalid.append((addr, entry[:16].hex(" ").upper(), why))
            code.items.append((addr, None, len(entry)))
            addr += len(entry)
            continue
        a = addr
        for f in frames:
            cmd: Command | None
            try:
                cmd = decode_command(f)
            except ProtocolError as exc:
                cmd = None
                code.invalid.append((a, f[:16].hex(" ").upper(), f"not a valid command: {exc}"))
            code.items.append((a, cmd, len(f)))
            a += len(f)
        addr += len(entry)
    return code
