"""The emulator's frozen, validated configuration (separate from the board's runtime state).

Every conflict of spec section 13 is a field here, with the spec's project default (one
exception, #4, where HeartToHeart4's own programs are the evidence):

====  ==============================  =========================================================
 #    field                           meaning (default first)
====  ==============================  =========================================================
 1    ``shift_direction``             ``"reference"``: count 1-127 shifts right; ``"inverted"``
 2    ``logic_reply``                 ``"data"``: logic/arith from COM answer the result;
                                      ``"ack"``
 3    ``logic_carry``                 ``"unchanged"``: AND/OR/XOR/NOT leave C; ``"clear"``
 4    ``branch_condition``            ``"or"``: one enabled Z/C comparison that matches is
                                      enough (HeartToHeart4's own >=/<= tests, see
                                      docs/spec-notes.md); ``"and"`` (the spec's inference)
 5    ``position_7fff``               ``"hold"``: 7FFF keeps torque on; ``"free"``
 6    ``unselected_update_flags``     ``"unchanged"`` on 10h/11h; ``"clear"``
 7    ``speed_zero``                  ``"one"``: speed 0 behaves as 1; ``"immediate"`` (jump)
 8    ``division_by_zero``            ``"error"`` (NAK / program stop); ``"zero"`` (result 0)
 9    ``version_string``              the captured RCB-4 string (32 bytes)
10    ``msg_f_messages``              ``False``: MSG_F never sends anything (the format is
                                      undocumented; ``True`` is rejected: a documented gap)
11    ``series_servo``                ``"execute"`` 11h as documented; ``"nak"``; ``"reset"``
                                      (the board resets without a reply, like one report)
12    ``frame_timeout_s`` and         a partial frame is dropped after this many seconds of
      ``partial_frame_reply``         silence (scaled by the clock speed) with ``"nak"``
                                      echoing its CMD byte if one arrived; or ``"silent"``
13    ``oversize_frame``              ``"nak"``: a SIZE byte above 128 swallows that many bytes
                                      and answers NAK, nothing executed; ``"silent"``
14    ``free_hold_base``              ``"include"``: the value sent for free/hold includes the
                                      base (+2) and mixing; ``"omit"``
====  ==============================  =========================================================

``ics_comm`` (default ``False``): 0Eh ICS communication is answered by emulated ICS servos on
the SIO lines (:mod:`rcb4hv.emulator.icslines`) instead of the NAK "no device answers". The
reference says 0Eh must not be used ("a problem in the specification"), so it is opt-in.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final, Literal

from rcb4hv.emulator.adc import check_input

__all__ = ["DEFAULT_SERVOS", "DEFAULT_VERSION", "EmulatorConfig", "ad_inputs_from"]

DEFAULT_VERSION: Final = b"CB-4 V1.0      090715          \xc7"
DEFAULT_SERVOS: Final = (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19)
"""The default humanoid's servos (:data:`rcb4hv.rom.default.DEFAULT_ICS`): the board's when its
image configures none."""


def _choice(name: str, value: object, allowed: tuple[str, ...]) -> None:
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, not {value!r}")


def _positive(name: str, value: float, *, allow_zero: bool = False) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number")
    if value < 0 or (value == 0 and not allow_zero):
        raise ValueError(f"{name} must be {'>= 0' if allow_zero else '> 0'}")


@dataclass(frozen=True, slots=True)
class EmulatorConfig:
    """How the emulated board behaves. Frozen; every field is validated on construction."""

    # --- spec section 13 conflicts
    shift_direction: Literal["reference", "inverted"] = "reference"
    logic_reply: Literal["data", "ack"] = "data"
    logic_carry: Literal["unchanged", "clear"] = "unchanged"
    # spec 13 #4 says "inferred AND"; HeartToHeart4 compiles a <= or >= test into one JUMP with
    # both Z and C enabled (Z&NC after SUB: "<="), which under AND could never branch
    branch_condition: Literal["and", "or"] = "or"
    position_7fff: Literal["hold", "free"] = "hold"
    unselected_update_flags: Literal["unchanged", "clear"] = "unchanged"
    speed_zero: Literal["one", "immediate"] = "one"
    division_by_zero: Literal["error", "zero"] = "error"
    version_string: bytes = DEFAULT_VERSION
    msg_f_messages: bool = False
    series_servo: Literal["execute", "nak", "reset"] = "execute"
    frame_timeout_s: float = 0.02
    partial_frame_reply: Literal["nak", "silent"] = "nak"
    oversize_frame: Literal["nak", "silent"] = "nak"
    free_hold_base: Literal["include", "omit"] = "include"
    # --- board model
    power_on_system_register: int = 0x0002
    instructions_per_ms: float = 5.0
    # None: the servos the ROM image's allocation table configures at power-on (the robot the
    # project was made for), or the default humanoid's when the image configures none
    virtual_servos: tuple[int, ...] | None = None
    servo_initial_position: int = 7500
    supply_voltage: float = 11.1
    # AD1-AD10 inputs (counts of 0-5 V); the measured registers read input - reference (10.4)
    ad_inputs: tuple[int, ...] = (0,) * 10
    ics_comm: bool = False
    # --- serving
    min_reply_latency_s: float = 0.001
    pace_replies: bool = False
    rom_flush_delay_s: float = 0.25
    max_pending_output: int = 65536

    def __post_init__(self) -> None:
        _choice("shift_direction", self.shift_direction, ("reference", "inverted"))
        _choice("logic_reply", self.logic_reply, ("data", "ack"))
        _choice("logic_carry", self.logic_carry, ("unchanged", "clear"))
        _choice("branch_condition", self.branch_condition, ("and", "or"))
        _choice("position_7fff", self.position_7fff, ("hold", "free"))
        _choice("unselected_update_flags", self.unselected_update_flags, ("unchanged", "clear"))
        _choice("speed_zero", self.speed_zero, ("one", "immediate"))
        _choice("division_by_zero", self.division_by_zero, ("error", "zero"))
        _choice("series_servo", self.series_servo, ("execute", "nak", "reset"))
        _choice("partial_frame_reply", self.partial_frame_reply, ("nak", "silent"))
        _choice("oversize_frame", self.oversize_frame, ("nak", "silent"))
        _choice("free_hold_base", self.free_hold_base, ("include", "omit"))
        if not isinstance(self.version_string, (bytes, bytearray)):
            raise ValueError("version_string must be bytes")
        vs = bytes(self.version_string)
        if len(vs) > 32:
            raise ValueError("version_string is at most 32 bytes")
        object.__setattr__(self, "version_string", vs.ljust(32, b" "))
        if self.msg_f_messages is not False:
            raise ValueError("MSG_F messages are not supported (their format is undocumented)")
        _positive("frame_timeout_s", self.frame_timeout_s)
        _positive("instructions_per_ms", self.instructions_per_ms)
        _positive("supply_voltage", self.supply_voltage, allow_zero=True)
        _positive("min_reply_latency_s", self.min_reply_latency_s, allow_zero=True)
        _positive("rom_flush_delay_s", self.rom_flush_delay_s, allow_zero=True)
        if not isinstance(self.power_on_system_register, int) or not (
            0 <= self.power_on_system_register <= 0xFFFF
        ):
            raise ValueError("power_on_system_register must be 0..FFFF")
        if self.virtual_servos is not None:
            servos = tuple(self.virtual_servos)
            if any(not isinstance(k, int) or not 0 <= k <= 35 for k in servos):
                raise ValueError("virtual_servos are ICS numbers 0..35")
            if len(set(servos)) != len(servos):
                raise ValueError("virtual_servos lists an ICS number twice")
            object.__setattr__(self, "virtual_servos", tuple(sorted(servos)))
        if not isinstance(self.servo_initial_position, int) or not (
            0 <= self.servo_initial_position <= 0xFFFF
        ):
            raise ValueError("servo_initial_position must be 0..65535")
        ads = tuple(self.ad_inputs)
        if len(ads) != 10 or any(not isinstance(v, int) or not 0 <= v <= 1023 for v in ads):
            raise ValueError("ad_inputs are 10 values (AD1-AD10) of 0..1023")
        object.__setattr__(self, "ad_inputs", ads)
        if round(self.supply_voltage * 1024 / 25) > 1023:
            raise ValueError("supply_voltage above the AD0 range (< 25 V)")
        if not isinstance(self.ics_comm, bool):
            raise ValueError("ics_comm must be True or False")
        if not isinstance(self.max_pending_output, int) or self.max_pending_output < 256:
            raise ValueError("max_pending_output must be >= 256")

    @property
    def ad0(self) -> int:
        """The AD0 reading of ``supply_voltage`` (volts = AD0 x 25 / 1024)."""
        return round(self.supply_voltage * 1024 / 25)


def ad_inputs_from(settings: Iterable[tuple[int, int]]) -> tuple[int, ...]:
    """``EmulatorConfig.ad_inputs`` from (channel 1-10, counts 0-1023) pairs (the rest 0), as
    ``rcb4hv emulate --ad CH=COUNTS`` and ``rcb4emu://?adCH=COUNTS`` give them. AD0 is the
    supply: its input follows ``supply_voltage``."""
    inputs = [0] * 10
    for ch, v in settings:
        channel, counts = check_input(ch, v, first=1)  # typed: ArgumentError / ArgumentTypeError
        inputs[channel - 1] = counts
    return tuple(inputs)
