"""The exception tree of rcb4hv.

::

    Rcb4Error                      base of everything this package raises on purpose
    ├── ProtocolError              bytes that are not a valid frame / command / reply
    │   ├── FrameError             framing: bad size byte, oversize or truncated frame
    │   ├── ChecksumError          a frame whose last byte is not the sum of the others
    │   └── VerifyError            memory read back after a write differs
    ├── NakError                   the board answered NAK (``04 CMD 15 SUM``)
    ├── ProgramStoppedError        the board's ROM program stopped with an error (ROMERR)
    │                              while a host waited for its motion to end
    ├── ArgumentError              a bad argument from the caller, named with the values it
    │   │                          may take; also a ValueError
    │   └── ArgumentTypeError      an argument of the wrong type; also a TypeError
    ├── TransportError             the port failed, closed or disconnected
    │   └── RomFileError           the emulator cannot write its ROM image file (``?rom=``)
    ├── Rcb4TimeoutError           no (complete) reply in time; also a builtin TimeoutError
    ├── CommandNotAllowedError     a command the client refuses unless enabled (0Eh); also
    │                              a builtin PermissionError
    ├── LayoutError                a project / image that fits no HeartToHeart4 layout;
    │                              also a ValueError
    ├── Hth4FormatError            a malformed HeartToHeart4 file; also a ValueError
    ├── AsmError                   assembler source that does not assemble; also a ValueError
    ├── EditError                  a motion edit that is refused (range, joint limit, slot in
    │   │                          use, a block that is not a pose); also a ValueError
    │   └── NoRobotModelError      an edit that needs a robot model (mirroring) without one;
    │       │                      also a RobotModelError
    │       └── AmbiguousRobotError  a project whose kit evidence fits several models: lists
    │                              the candidates (``--robot`` picks one)
    ├── SimulationError            the emulated board refused a host frame in a simulation
    ├── RobotModelError            a robot model, URDF or joint map that cannot be used (an
    │   │                          unknown robot name, a link without inertia, a joint map
    │   │                          naming an unknown joint or a servo the project lacks);
    │   │                          also a ValueError
    │   └── RobotLookupError       a link, joint or servo index the model does not have;
    │                              also a NotFoundError (so a KeyError)
    ├── NotFoundError              a lookup that finds nothing: a project's motion slot or
    │                              servo; also a KeyError
    ├── GaitError                  a walk that cannot be made (parameters out of range, no
    │                              motion slot it fits); also a ValueError
    ├── PhysicsError               the physics simulation cannot run
    │   └── PhysicsUnavailableError  MuJoCo is missing (install rcb4hv[sim]); also an
    │                              ImportError
    ├── IcsError                   an ICS servo answered wrongly, or a write did not verify
    │   └── IcsNoReply             no ICS servo answered (absent ID, wrong baud, busy);
    │                              also a builtin TimeoutError
    ├── ScaleError                 the distributed back end (Ray) is missing or unreachable
    └── FileAccessError            a user's file that cannot be read or written (names the
        │                          file, not a temporary one); also an OSError
        ├── MissingFileError       no such file, or no such directory; also a
        │                          FileNotFoundError
        ├── FileIsDirectoryError   a directory where a file was meant; also an
        │                          IsADirectoryError
        ├── FilePermissionError    a read-only file, or a directory that refuses new files;
        │                          also a PermissionError
        └── FileClashError         a file that would overwrite another the command also
                                   reads or writes; also a FileExistsError

Bad arguments given by the caller raise :class:`ValueError` before any byte is sent (in the
client, the robot API, the session and the emulator an :class:`ArgumentError`, which is one).
A ``ProtocolError`` always means "the peer (or a file) sent garbage"; anything else that
escapes is a bug.
"""

from __future__ import annotations

__all__ = [
    "AmbiguousRobotError",
    "ArgumentError",
    "ArgumentTypeError",
    "AsmError",
    "ChecksumError",
    "CommandNotAllowedError",
    "EditError",
    "EmulatedCommandError",
    "EmulatedReset",
    "FileAccessError",
    "FileClashError",
    "FileIsDirectoryError",
    "FilePermissionError",
    "FrameError",
    "GaitError",
    "Hth4FormatError",
    "IcsError",
    "IcsNoReply",
    "JointLimitError",
    "LayoutError",
    "MissingFileError",
    "NakError",
    "NoRobotModelError",
    "NotFoundError",
    "PhysicsError",
    "PhysicsUnavailableError",
    "ProgramStoppedError",
    "ProtocolError",
    "Rcb4Error",
    "Rcb4TimeoutError",
    "RobotLookupError",
    "RobotModelError",
    "RomFileError",
    "ScaleError",
    "SimulationError",
    "TransportError",
    "VerifyError",
]


class Rcb4Error(Exception):
    """Base class of every error rcb4hv raises on purpose."""


class ProtocolError(Rcb4Error):
    """Bytes that do not form a valid frame, command or reply."""


class FrameError(ProtocolError):
    """A framing problem: a size byte out of range, an oversize or truncated frame."""


class ChecksumError(ProtocolError):
    """A frame whose checksum byte does not match the sum of its other bytes."""

    def __init__(self, message: str, frame: bytes = b"") -> None:
        super().__init__(message)
        self.frame = frame


class NakError(Rcb4Error):
    """The board answered NAK to a command."""

    def __init__(self, message: str, command: int | None = None) -> None:
        super().__init__(message)
        self.command = command


class ProgramStoppedError(Rcb4Error):
    """The board's ROM program stopped with a ROM error (ROMERR: an instruction it cannot
    execute, e.g. a motion slot that holds no motion) while a host waited for a motion to end.
    ``pc`` is where it stopped, ``motion`` the slot it was in (None outside the motions)."""

    def __init__(self, message: str, pc: int, motion: int | None) -> None:
        super().__init__(message)
        self.pc = pc
        self.motion = motion


class TransportError(Rcb4Error):
    """The link failed: the port could not be opened, was closed or disconnected."""


class RomFileError(TransportError):
    """The emulator cannot write its persistent ROM image file (``rcb4emu://?rom=PATH``): the
    board keeps running with the image in memory, but it is not saved. ``path`` names the file.
    """

    def __init__(self, message: str, path: str = "") -> None:
        super().__init__(message)
        self.path = path


class ArgumentError(Rcb4Error, ValueError):
    """A bad argument from the caller (out of range, not finite, not one of the choices); the
    message names the argument and the values it may take. Raised before any byte is sent."""


class ArgumentTypeError(ArgumentError, TypeError):
    """An argument of the wrong type (``"1"`` for a number of seconds); also a TypeError."""


class Rcb4TimeoutError(Rcb4Error, TimeoutError):
    """No complete reply arrived within the timeout."""


class LayoutError(Rcb4Error, ValueError):
    """A project or image does not fit a HeartToHeart4 ROM layout: motions stored for no
    known layout, or a motion that cannot be moved to the layout asked for."""


class VerifyError(ProtocolError):
    """Reading back memory just written gave different bytes."""

    def __init__(self, message: str, address: int) -> None:
        super().__init__(message)
        self.address = address


class CommandNotAllowedError(Rcb4Error, PermissionError):
    """A command the client refuses unless explicitly enabled (ICS communication, 0Eh)."""


class Hth4FormatError(Rcb4Error, ValueError):
    """A HeartToHeart4 file that is malformed or not of the expected kind.

    ``path`` names the offending element (``Rcb4/Kri3/Count``) or CSV cell (``line 3,
    column 2``); it is also the start of the message.
    """

    def __init__(self, path: str, message: str) -> None:
        super().__init__(f"{path}: {message}" if path else message)
        self.path = path


class AsmError(Rcb4Error, ValueError):
    """A source line that does not assemble; carries the 1-based ``line`` and ``column``."""

    def __init__(self, message: str, line: int, column: int = 1, source: str | None = None):
        self.message = message
        self.line = line
        self.column = column
        self.source = source
        super().__init__(f"line {line}, column {column}: {message}")


class SimulationError(Rcb4Error):
    """The emulated board did not accept a host frame during a simulation."""


class EmulatedCommandError(Rcb4Error):
    """Inside the emulator: a command that cannot execute. The board model turns it into a
    NAK (command from COM) or a program stop (instruction from ROM); it never reaches a host.
    ``what`` names the stop (a :data:`rcb4hv.emulator.events.StopKind`)."""

    def __init__(self, why: str, what: str = "command-error") -> None:
        super().__init__(why)
        self.what = what


class EmulatedReset(Rcb4Error):
    """Inside the emulator: the command resets the board (configuration
    ``series_servo="reset"``); the board model powers on again."""


class RobotModelError(Rcb4Error, ValueError):
    """A robot model that cannot be built or used: an unknown built-in name, a URDF that is
    malformed or lacks inertia, a joint map naming an unknown joint, or a model whose servo
    indices the project does not have."""


class NotFoundError(Rcb4Error, KeyError):
    """A lookup that finds nothing (a project's motion slot, a servo); also a KeyError, so
    ``except KeyError`` keeps working. Unlike a KeyError, ``str()`` is the plain message."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class RobotLookupError(RobotModelError, NotFoundError):
    """A link, joint or servo index the robot model does not have; the message lists the
    ones it has. Also a RobotModelError, a KeyError and a ValueError."""


class EditError(Rcb4Error, ValueError):
    """A project edit that is refused: a value outside the documented range or the joint's
    limits (without the override), a slot in use, a block that is not a pose."""


class JointLimitError(EditError):
    """A pose value beyond a joint's hard (mechanical) limits, without the override. A value
    only outside the joint's advisory range is never refused: it warns."""


class NoRobotModelError(EditError, RobotModelError):
    """An edit that needs the robot's joint map (mirroring, joint angles) on a project whose
    robot has no model: name one (``--robot``)."""


class AmbiguousRobotError(NoRobotModelError):
    """A project whose title and servo names fit more than one robot model: detection stops
    and lists them (``candidates``: model names for ``--robot``) rather than guess."""

    def __init__(self, message: str, candidates: tuple[str, ...] = ()) -> None:
        super().__init__(message)
        self.candidates = candidates


class GaitError(Rcb4Error, ValueError):
    """A walk that cannot be made: parameters out of range, or no motion slot it fits."""


class PhysicsError(Rcb4Error):
    """The physics simulation cannot run: a robot model MuJoCo refuses, or no robot model."""


class PhysicsUnavailableError(PhysicsError, ImportError):
    """MuJoCo is not installed: ``pip install 'rcb4hv[sim]'``."""


class IcsError(Rcb4Error):
    """An ICS servo (or the bus in between) answered something else than the protocol says, or
    a value read back after a write differs from the value written."""


class IcsNoReply(IcsError, TimeoutError):
    """No ICS servo answered in time: no servo with that ID, a different baud rate, a servo
    still writing its EEPROM, or (through a board's 0Eh) the board's NAK for "no answer"."""


class ScaleError(Rcb4Error):
    """The distributed back end (Ray) is not installed, or its address answers nothing."""


class FileAccessError(Rcb4Error, OSError):
    """A user's file that cannot be read or written. The message names the user's path (never
    the temporary file a save writes first) and why; ``filename`` is that path and ``errno``
    the system's error number, if any. Also an :class:`OSError`, and its subclasses are also
    the builtin error of the same kind, so ``except FileNotFoundError`` keeps working."""

    def __init__(self, message: str, filename: str = "", errno: int | None = None) -> None:
        super().__init__(message)
        self.errno = errno
        self.strerror = message
        self.filename = filename

    def __str__(self) -> str:
        return str(self.strerror)


class MissingFileError(FileAccessError, FileNotFoundError):
    """No such file (reading), or no such directory (saving)."""


class FileIsDirectoryError(FileAccessError, IsADirectoryError):
    """A directory given where a file is read or written."""


class FilePermissionError(FileAccessError, PermissionError):
    """A file the caller may not read, a read-only file a save would replace, or a directory
    that does not allow a new file in it."""


class FileClashError(FileAccessError, FileExistsError):
    """An output that would overwrite a file the same command reads, or another output."""
