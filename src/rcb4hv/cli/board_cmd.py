"""``rcb4hv`` commands that talk to a board: ping, version, info, ram, rom, servo (``motion``
and ``button`` are in :mod:`rcb4hv.cli.motion_cmd`, ``rcb4hv demo`` in
:mod:`rcb4hv.cli.demo_cmd`)."""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

import click

from rcb4hv.cli import _output
from rcb4hv.cli._util import (
    ADDRESS,
    INTEGER,
    Connection,
    handle_errors,
    output_option,
    parse_int,
    pass_connection,
    print_json,
    print_table,
)
from rcb4hv.client import Robot, ServoInfo
from rcb4hv.client.args import servo_targets
from rcb4hv.files import write_atomic
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, ROM_SIZE


def _hexdump(address: int, data: bytes) -> None:
    for i in range(0, len(data), 16):
        row = data[i : i + 16]
        text = "".join(chr(b) if 0x20 <= b < 0x7F else "." for b in row)
        click.echo(f"{address + i:06X}  {row.hex(' '):<47}  {text}")


def _output_text(output: int) -> object:
    """A servo block's output (+6) for the table: a position, or the word of a marker value
    (8000h reads as a position beside the decimal ones)."""
    if output == POSITION_FREE:
        return "free"
    if output == POSITION_HOLD:
        return "hold"
    return f"{output:04X}h" if output > POSITION_HOLD else output


def servo_rows(servos: list[ServoInfo], robot: Robot) -> list[list[object]]:
    rows: list[list[object]] = []
    for s in servos:
        b = s.block
        deg = robot.to_degrees(s.ics, b.measured)
        rows.append(
            [
                s.ics,
                s.servo_id,
                s.port,
                f"{s.block_address:04X}",
                b.base,
                b.measured,
                f"{deg:+.1f}",
                _output_text(b.output),
                s.state,
            ]
        )
    return rows


SERVO_HEADERS = ("ICS", "ID", "port", "block", "trim", "measured", "deg", "output", "state")


@click.command()
@pass_connection
@click.option("-n", "--count", type=click.IntRange(min=1), default=1, show_default=True)
@handle_errors
def ping(conn: Connection, count: int) -> None:
    """ACK check: is a board there? Prints the round-trip time.

    With -n N it sends N checks and goes on past a lost or damaged reply, as ping does:
    the times of those answered and how many were lost; exit status 1 when none was."""
    from rcb4hv.errors import ProtocolError, Rcb4TimeoutError

    times: list[float] = []
    last: Exception | None = None
    with conn.open() as robot:
        for _ in range(count):
            try:
                times.append(robot.ping())
            except (Rcb4TimeoutError, ProtocolError) as exc:
                if count == 1:
                    raise
                last = exc
    url = robot.client.transport.url
    lost = count - len(times)
    if not times:
        raise Rcb4TimeoutError(f"no ACK from {url} in {count} checks (last: {last})")
    if count == 1:
        click.echo(f"ACK from {url} in {times[0] * 1000:.2f} ms")
    else:
        click.echo(
            f"{len(times)} ACKs from {url}: min {min(times) * 1000:.2f} ms, "
            f"median {statistics.median(times) * 1000:.2f} ms, max {max(times) * 1000:.2f} ms"
            + (f"; {lost} of {count} lost" if lost else "")
        )


@click.command()
@pass_connection
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def version(conn: Connection, as_json: bool) -> None:
    """The board's version string."""
    with conn.open() as robot:
        v = robot.version()
    if as_json:
        print_json({"text": v.text, "raw": v.version.hex()})
    else:
        click.echo(v.text)


@click.command()
@pass_connection
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def info(conn: Connection, as_json: bool) -> None:
    """System register, ROM program state and servo table."""
    with conn.open() as robot:
        board = robot.info()
        if as_json:
            print_json(board.describe())
            return
        click.echo(f"version        {board.version}")
        sysreg = board.system.describe()
        flags = [k for k in ("ics_output", "rom_run", "message", "vector_jump") if sysreg[k]]
        click.echo(
            f"system         {sysreg['word']}h  flags: {' '.join(flags) or '-'}  "
            f"frame {sysreg['frame_period_ms']} ms  baud {sysreg['baud']}  "
            f"ICS baud {sysreg['ics_baud']}  Z={int(board.system.zero)} "
            f"C={int(board.system.carry)}  ROMERR={int(board.system.rom_error)}"
        )
        motion = robot.board_layout().motion_at(board.pc)
        where = f" (motion {motion})" if motion is not None else ""
        click.echo(f"PC             {board.pc:06X}{where}")
        click.echo(f"call depth     {board.call_depth}")
        click.echo(f"update flags   {board.update_flags.hex(' ')}")
        click.echo(f"servos         {len(board.servos)}")
        if board.servos:
            click.echo()
            print_table(SERVO_HEADERS, servo_rows(board.servos, robot))


@click.group()
def ram() -> None:
    """Read and write board RAM (0000h-048Fh)."""


@ram.command("read")
@click.argument("address", type=ADDRESS)
@click.argument("size", type=INTEGER, default=16)
@pass_connection
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def ram_read(conn: Connection, address: int, size: int, as_json: bool) -> None:
    """Read SIZE bytes at ADDRESS (decimal, 0x.., ..h or $..)."""
    with conn.open() as robot:
        data = robot.read_ram(address, size)
    if as_json:
        print_json({"address": address, "size": size, "hex": data.hex()})
    else:
        _hexdump(address, data)


@ram.command("write")
@click.argument("address", type=ADDRESS)
@click.argument("data")
@pass_connection
@handle_errors
def ram_write(conn: Connection, address: int, data: str) -> None:
    """Write hex DATA (e.g. "0a ff 10") at ADDRESS."""
    try:
        raw = bytes.fromhex(data.replace(":", " "))
    except ValueError as exc:
        raise click.BadParameter(f"not hex bytes ({exc})", param_hint="DATA") from None
    with conn.open() as robot:
        robot.write_ram(address, raw)
    click.echo(f"wrote {len(raw)} byte(s) at {address:04X}")


@click.group()
def rom() -> None:
    """Read, write and dump the 256 KB ROM (EEPROM)."""


@rom.command("read")
@click.argument("address", type=ADDRESS)
@click.argument("size", type=INTEGER, default=64)
@pass_connection
@output_option("Write the raw bytes here (default: a hex dump).", required=False)
@handle_errors
def rom_read(conn: Connection, address: int, size: int, output: Path | None) -> None:
    """Read SIZE bytes of ROM at ADDRESS (hex dump, or raw bytes to --output)."""
    with conn.open() as robot:
        data = robot.read_rom(address, size)
    if output is not None:
        write_atomic(output, data)
        click.echo(f"wrote {len(data)} bytes to {output}")
    else:
        _hexdump(address, data)


@rom.command("write")
@click.argument("address", type=ADDRESS)
@click.argument("image", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@pass_connection
@click.option("--verify/--no-verify", default=True, show_default=True)
@_output.PROGRESS_OPTION
@handle_errors
def rom_write(
    conn: Connection, address: int, image: Path, verify: bool, progress: bool | None
) -> None:
    """Write the bytes of IMAGE to ROM at ADDRESS (64-byte chunks, read back)."""
    data = image.read_bytes()
    if not data:
        raise ValueError(f"{image} is empty")
    try:
        with conn.open() as robot, _output.progress(len(data), "rom write", progress) as bar:
            robot.write_rom(address, data, verify=verify, progress=bar)
    except KeyboardInterrupt:
        click.echo(
            f"interrupted: the ROM from {address:06X} is partly written "
            f"(up to {len(data)} bytes); run the command again to write it whole",
            err=True,
        )
        sys.exit(130)
    checked = " and verified" if verify else ""
    click.echo(f"wrote{checked} {len(data)} bytes at {address:06X}")


@rom.command("dump")
@output_option("Where to write the image.")
@click.option("--start", type=ADDRESS, default=0, show_default=True)
@click.option("--size", type=INTEGER, default=ROM_SIZE, show_default=True)
@pass_connection
@_output.PROGRESS_OPTION
@handle_errors
def rom_dump(conn: Connection, output: Path, start: int, size: int, progress: bool | None) -> None:
    """Save ROM (default: all 256 KB) to an image file."""
    with conn.open() as robot, _output.progress(size, "rom dump", progress) as bar:
        data = robot.read_rom(start, size, progress=bar)
    write_atomic(output, data)
    click.echo(f"wrote {len(data)} bytes ({start:06X}-{start + size - 1:06X}) to {output}")


@click.group()
def servo() -> None:
    """List, move, free and hold servos (by ICS number = ID x 2 + port group)."""


@servo.command("list")
@pass_connection
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def servo_list(conn: Connection, as_json: bool) -> None:
    """Servos found through the ICS allocation table."""
    with conn.open() as robot:
        servos = robot.discover_servos()
        if as_json:
            print_json([s.describe() for s in servos])
        elif not servos:
            click.echo("no servo allocated")
        else:
            print_table(SERVO_HEADERS, servo_rows(servos, robot))


@servo.command("move")
@click.argument("targets", nargs=-1, required=True, metavar="ICS=VALUE...")
@click.option("--deg", is_flag=True, help="VALUEs are degrees, not raw positions.")
@click.option("-d", "--duration", type=click.FloatRange(min=0), default=0.5, show_default=True)
@click.option("--wait/--no-wait", default=True, show_default=True)
@click.option("--unchecked", is_flag=True, help="Send positions outside 3500..11500 too.")
@pass_connection
@handle_errors
def servo_move(
    conn: Connection,
    targets: tuple[str, ...],
    deg: bool,
    duration: float,
    wait: bool,
    unchecked: bool,
) -> None:
    """Move servos, e.g. `servo move 2=8000 4=7000` or `servo move --deg 2=30`.

    A position outside 3500..11500 (hold 32767 and free 32768 aside) is refused unless
    --unchecked is given."""
    values: dict[int, float] = {}
    for t in targets:
        k, sep, v = t.partition("=")
        if not sep:
            raise click.BadParameter(f"{t!r} is not ICS=VALUE")
        try:
            ics, value = parse_int(k), float(v)
        except ValueError as exc:
            raise click.BadParameter(f"{t!r}: {v!r} is not a number") from exc
        if not deg and not value.is_integer():
            raise click.BadParameter(f"{t!r}: a position is a whole number of counts")
        values[ics] = value

    def checked(positions: dict[int, int]) -> dict[int, int]:
        """The robot API's check; its message names --unchecked, not check_range=False."""
        return servo_targets(positions, not unchecked, override="--unchecked")

    raw = None if deg else checked({k: round(v) for k, v in values.items()})  # no link needed
    with conn.open() as robot:
        degrees = {k: robot.to_position(k, a) for k, a in values.items()} if deg else {}
        positions = checked(degrees) if raw is None else raw
        robot.move(positions, duration, check_range=not unchecked)
        if wait:
            robot.wait_interpolation(positions, timeout=duration + 2.0)
    click.echo("moved " + ", ".join(f"ICS {k} -> {p}" for k, p in sorted(positions.items())))


@servo.command("free")
@click.argument("ics", nargs=-1, type=INTEGER)
@pass_connection
@handle_errors
def servo_free(conn: Connection, ics: tuple[int, ...]) -> None:
    """Torque off (all servos if no ICS number is given)."""
    with conn.open() as robot:
        robot.free(ics or None)
        click.echo(f"freed {len(ics) if ics else len(robot.servo_ids())} servo(s)")


@servo.command("hold")
@click.argument("ics", nargs=-1, type=INTEGER)
@pass_connection
@handle_errors
def servo_hold(conn: Connection, ics: tuple[int, ...]) -> None:
    """Torque on at the current position (all servos if no ICS number is given)."""
    with conn.open() as robot:
        robot.hold(ics or None)
        click.echo(f"holding {len(ics) if ics else len(robot.servo_ids())} servo(s)")


def register(cli: click.Group) -> None:
    """Add this module's commands to ``cli``."""
    cli.add_command(ping)
    cli.add_command(version)
    cli.add_command(info)
    cli.add_command(ram)
    cli.add_command(rom)
    cli.add_command(servo)
