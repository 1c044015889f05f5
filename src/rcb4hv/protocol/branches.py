"""Control flow (JUMP, CALL, RETURN with their condition byte) and ICS communication (0Eh).

Each class owns its codec: ``encode()`` builds the frame, ``from_frame`` parses one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Final

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import build_frame
from rcb4hv.protocol.operands import RAM_SIZE, Op, check_ics, check_int

__all__ = ["ALWAYS", "Branch", "Call", "CommunicateDevice", "Condition", "Jump", "Return"]


@dataclass(frozen=True, slots=True)
class Condition:
    """The COND byte of JUMP/CALL: each enabled comparison must match (AND)."""

    compare_z: bool = False
    z: bool = False
    compare_c: bool = False
    c: bool = False

    @classmethod
    def from_byte(cls, value: int) -> Condition:
        check_int("condition byte", value, 0, 0x0F)
        return cls(bool(value & 4), bool(value & 1), bool(value & 8), bool(value & 2))

    def to_byte(self) -> int:
        return (
            (1 if self.z else 0)
            | (2 if self.c else 0)
            | (4 if self.compare_z else 0)
            | (8 if self.compare_c else 0)
        )

    def holds(self, z: bool, c: bool) -> bool:
        """Whether the branch is taken for flags ``z`` and ``c``."""
        if self.compare_z and z != self.z:
            return False
        return not (self.compare_c and c != self.c)

    @classmethod
    def if_zero(cls) -> Condition:
        return cls(compare_z=True, z=True)

    @classmethod
    def if_not_zero(cls) -> Condition:
        return cls(compare_z=True, z=False)

    @classmethod
    def if_carry(cls) -> Condition:
        return cls(compare_c=True, c=True)

    @classmethod
    def if_not_carry(cls) -> Condition:
        return cls(compare_c=True, c=False)

    def __str__(self) -> str:
        parts = []
        if self.compare_z:
            parts.append("Z" if self.z else "NZ")
        if self.compare_c:
            parts.append("C" if self.c else "NC")
        return "&".join(parts) if parts else "ALWAYS"


ALWAYS: Final = Condition()


@dataclass(frozen=True, slots=True)
class Branch:
    address: int
    condition: Condition = ALWAYS
    cmd: ClassVar[int] = -1

    def __post_init__(self) -> None:
        # 24 bits on the wire; HeartToHeart4 flowcharts hold FFFFFF for unresolved targets.
        check_int("branch address", self.address, 0, 0xFFFFFF)
        if not isinstance(self.condition, Condition):
            raise ValueError("condition must be a Condition")

    def encode(self) -> bytes:
        a = self.address
        return build_frame(
            self.cmd, bytes((a & 0xFF, (a >> 8) & 0xFF, a >> 16, self.condition.to_byte()))
        )

    @classmethod
    def from_frame(cls, frame: bytes) -> Branch:
        if len(frame) != 7:
            raise ProtocolError("JUMP/CALL frames are 7 bytes")
        if frame[5] & 0xF0:
            raise ProtocolError(f"condition byte {frame[5]:02X}: bits 7-4 must be 0")
        return cls(frame[2] | frame[3] << 8 | frame[4] << 16, Condition.from_byte(frame[5]))

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True)
class Jump(Branch):
    """0Bh JUMP: PC <- address if the condition holds."""

    cmd: ClassVar[int] = Op.JUMP


@dataclass(frozen=True, slots=True)
class Call(Branch):
    """0Ch CALL: push the next PC and jump if the condition holds (16 levels)."""

    cmd: ClassVar[int] = Op.CALL


@dataclass(frozen=True, slots=True)
class Return:
    """0Dh RETURN: pop the PC (``03 0D 10``)."""

    cmd: ClassVar[int] = Op.RETURN

    def encode(self) -> bytes:
        return b"\x03\x0d\x10"

    @classmethod
    def from_frame(cls, frame: bytes) -> Return:
        if len(frame) != 3:
            raise ProtocolError("RETURN is 3 bytes")
        return cls()

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True)
class CommunicateDevice:
    """0Eh ICS communication: send ``tx_count`` bytes from RAM ``tx_address`` to a device.

    The reference says this command has a specification problem and must not be used.
    """

    ics: int
    tx_count: int
    tx_address: int
    rx_address: int
    cmd: ClassVar[int] = Op.ICS_COMM

    def __post_init__(self) -> None:
        check_ics(self.ics)
        check_int("TX count", self.tx_count, 1, 64)
        check_int("TX address", self.tx_address, 0, RAM_SIZE - self.tx_count)
        check_int("RX address", self.rx_address, 0, RAM_SIZE - 1)

    def encode(self) -> bytes:
        tx, rx = self.tx_address, self.rx_address
        return build_frame(
            self.cmd, bytes((self.ics, self.tx_count, tx & 0xFF, tx >> 8, rx & 0xFF, rx >> 8))
        )

    @classmethod
    def from_frame(cls, frame: bytes) -> CommunicateDevice:
        if len(frame) != 9:
            raise ProtocolError("ICS communication frames are 9 bytes")
        return cls(frame[2], frame[3], frame[4] | frame[5] << 8, frame[6] | frame[7] << 8)

    @property
    def reply_data_size(self) -> int | None:
        return None
