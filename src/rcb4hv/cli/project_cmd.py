"""``rcb4hv project``: HeartToHeart4 projects -> ROM image, simulation, upload, inspection."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import click

from rcb4hv.cli import project_check_cmd
from rcb4hv.cli._util import (
    connection_options,
    handle_errors,
    open_robot,
    print_json,
    print_table,
)
from rcb4hv.cli.project_check_cmd import build_options, current_build_options
from rcb4hv.protocol import Button
from rcb4hv.rom.layout import HTH4_22, MotionLayout

STATUS_EXIT = {"error": 1, "timeout": 2, "stalled": 2}


@contextmanager
def _progress(total: int, desc: str, enabled: bool) -> Iterator[Callable[[int, int], None]]:
    from tqdm import tqdm

    with tqdm(
        total=total, desc=desc, unit="B", unit_scale=True, disable=not enabled, file=sys.stderr
    ) as bar:

        def update(done: int, new_total: int) -> None:
            if new_total != bar.total:
                bar.total = new_total
                bar.refresh()
            bar.update(done - bar.n)

        yield update


def _parse_buttons(text: str) -> int:
    value = 0
    for part in text.replace("|", "+").replace(",", "+").split("+"):
        name = part.strip().upper()
        if not name:
            continue
        try:
            value |= int(Button[name])
        except KeyError:
            names = ", ".join(b.name for b in Button if b.name and b is not Button.NONE)
            raise click.BadParameter(f"unknown button {part!r} (one of {names})") from None
    if not value:
        raise click.BadParameter("no button named")
    return value


def _button_text(buttons: int, compare: str = "Equals") -> str:
    from rcb4hv.project.image import ButtonBinding

    names = ButtonBinding(buttons, compare, 0).button_names
    return names if compare == "Equals" else f"{compare} {names}"


LAYOUT_OPTION = click.option(
    "--layout",
    "layout_name",
    type=click.Choice(["2.2", "2.1", "2.0", "1.3"]),
    default=None,
    help="HeartToHeart4 layout [default: the one the motions' stored addresses (or the "
    "image's main loop) show; a project is moved to the layout given].",
)


def _load(
    path: Path, layout_name: str | None = None
) -> tuple[bytes, MotionLayout, dict[int, str]]:
    """(image, layout, names by slot) of a .h4p project or a raw 256 KB image file."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.relocate import image_layout, project_image

    if path.suffix.lower() == ".h4p":
        project = load_project(path)
        names = {m.slot: m.name or "" for m in project.used_motions}
        image, lay = project_image(project, layout_name, options=current_build_options())
        return image, lay, names
    data = path.read_bytes()
    from rcb4hv.rom import layout

    if len(data) != layout.ROM_SIZE:
        raise ValueError(f"{path}: not a .h4p project nor a {layout.ROM_SIZE}-byte ROM image")
    return data, image_layout(data, layout_name, default=HTH4_22), {}


def register(cli: click.Group) -> None:
    """Add the ``project`` group to ``cli``."""

    @cli.group()
    def project() -> None:
        """HeartToHeart4 projects (.h4p): build, inspect, check, simulate and upload ROM images."""

    project_check_cmd.register(project)

    # ------------------------------------------------------------------ build

    @project.command("build")
    @click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
    @click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), required=True)
    @build_options
    @LAYOUT_OPTION
    @handle_errors
    def build(file: Path, output: Path, layout_name: str | None) -> None:
        """Build the 256 KB ROM image of FILE in its HeartToHeart4 layout (or --layout)."""
        from rcb4hv.hth4 import load_project
        from rcb4hv.project.relocate import project_image

        p = load_project(file)
        image, lay = project_image(p, layout_name, options=current_build_options())
        output.write_bytes(image)
        click.echo(
            f"wrote {len(image)} bytes ({len(p.used_motions)} motions, HeartToHeart4 "
            f"{lay.version} layout) to {output}"
        )

    # ------------------------------------------------------------------ info

    @project.command("info")
    @click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
    @click.option("--json", "as_json", is_flag=True, help="Print JSON.")
    @handle_errors
    def info(file: Path, as_json: bool) -> None:
        """Motions (slot, address, name, frames, button) and servos of FILE (.h4p)."""
        from rcb4hv.hth4 import load_project

        p = load_project(file)
        startup = p.startup_motion_address
        prio = {pm.address: i for i, pm in p.active_priority_motions}
        motions: list[dict[str, Any]] = []
        for m in p.used_motions:
            motions.append(
                {
                    "slot": m.slot,
                    "address": f"{m.address:05X}",
                    "name": m.name or "",
                    "frames": len(m.frames),
                    "bytes": len(m.rom_bytes()),
                    "button": m.button_data,
                    "button_names": _button_text(m.button_data, m.compare_type)
                    if m.button_data
                    else "",
                    "compare_type": m.compare_type,
                    "startup": m.address == startup,
                    "priority": prio.get(m.address),
                }
            )
        servos: list[dict[str, Any]] = []
        for s in p.servos:
            if not s.in_use:
                continue
            servos.append(
                {
                    "ics": s.ics_number,
                    "id": s.id,
                    "name": s.name or "",
                    "port": s.port,
                    "trim": s.trim,
                    "home": s.home_position,
                    "mixing1": [s.mixing1_address, s.mixing1_rate],
                    "mixing2": [s.mixing2_address, s.mixing2_rate],
                }
            )
        settings = {
            "title": p.project_title,
            "system_register": f"{p.system_register:04X}",
            "startup_motion": None if startup < 0 else f"{startup:05X}",
            "priority_motions": [
                {
                    "check": i,
                    "name": pm.name,
                    "port": pm.port,
                    "compare_type": pm.compare_type,
                    "value": pm.value,
                    "address": None if pm.address < 0 else f"{pm.address:05X}",
                }
                for i, pm in p.active_priority_motions
            ],
            "low_power_motion": None
            if p.low_power_motion_address < 0
            else f"{p.low_power_motion_address:05X}",
            "low_power_value": p.low_power_value,
        }
        if as_json:
            print_json({"settings": settings, "motions": motions, "servos": servos})
            return
        click.echo(
            f"{file.name}: {settings['title'] or '(no title)'}, system register "
            f"{settings['system_register']}h, {len(motions)} motions, "
            f"{len(servos)} servos"
        )
        for line in project_check_cmd.settings_lines(p):
            click.echo(line)
        click.echo("")
        rows = []
        for mi in motions:
            notes = []
            if mi["startup"]:
                notes.append("startup")
            if mi["priority"] is not None:
                notes.append(f"priority {mi['priority']}")
            rows.append(
                [
                    mi["slot"],
                    mi["address"],
                    mi["name"],
                    mi["frames"],
                    mi["bytes"],
                    mi["button_names"],
                    ", ".join(notes),
                ]
            )
        print_table(("slot", "address", "name", "frames", "bytes", "button", "note"), rows)
        click.echo("")
        print_table(
            ("ICS", "ID", "name", "port", "trim", "home", "mixing1", "mixing2"),
            [
                [
                    s["ics"],
                    s["id"],
                    s["name"],
                    s["port"],
                    s["trim"],
                    s["home"],
                    "-"
                    if s["mixing1"][0] == 0xFFFF
                    else f"{s['mixing1'][0]:04X} x{s['mixing1'][1]}",
                    "-"
                    if s["mixing2"][0] == 0xFFFF
                    else f"{s['mixing2'][0]:04X} x{s['mixing2'][1]}",
                ]
                for s in servos
            ],
        )

    # ------------------------------------------------------------------ image -> data

    @project.command("image")
    @click.argument("image", type=click.Path(exists=True, dir_okay=False, path_type=Path))
    @click.option("--json", "as_json", is_flag=True, help="Print JSON.")
    @LAYOUT_OPTION
    @handle_errors
    def image_cmd(image: Path, as_json: bool, layout_name: str | None) -> None:
        """The motions and settings a HeartToHeart4 ROM IMAGE holds."""
        from rcb4hv.project.image import read_image
        from rcb4hv.project.relocate import image_layout

        data = image.read_bytes()
        c = read_image(data, image_layout(data, layout_name))
        motions: list[dict[str, Any]] = [
            {
                "slot": m.slot,
                "address": f"{m.address:05X}",
                "frames": len(m.frames),
                "bytes": m.size,
                "buttons": [_button_text(b.buttons, b.compare_type) for b in m.bindings],
                "startup": m.startup,
                "priority": list(m.priority),
            }
            for m in c.motions
        ]
        if as_json:
            print_json(
                {
                    "title": c.title,
                    "system_register": f"{c.system_register:04X}",
                    "startup_motion": None
                    if c.startup_motion_address < 0
                    else f"{c.startup_motion_address:05X}",
                    "ad_references": list(c.description.ad_references),
                    "servos": {str(k): v for k, v in c.servos.items()},
                    "priority_motions": {str(k): v for k, v in c.priority.items()},
                    "motions": motions,
                }
            )
            return
        click.echo(
            f"{image.name}: {c.title or '(no title)'}, system register "
            f"{c.system_register:04X}h, {len(motions)} motions, "
            f"{len(c.servos)} servos"
        )
        print_table(
            ("slot", "address", "frames", "bytes", "button", "note"),
            [
                [
                    m["slot"],
                    m["address"],
                    m["frames"],
                    m["bytes"],
                    ", ".join(m["buttons"]),
                    ", ".join(
                        (["startup"] if m["startup"] else [])
                        + [f"priority {i}" for i in m["priority"]]
                    ),
                ]
                for m in motions
            ],
        )

    # ------------------------------------------------------------------ simulate

    @project.command("simulate")
    @click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
    @click.option(
        "--motion",
        "motion",
        type=click.IntRange(1, 120),
        multiple=True,
        help="Motion slot to play (repeatable; default: every used slot).",
    )
    @click.option("--json", "as_json", is_flag=True, help="Print JSON.")
    @click.option(
        "--plot",
        type=click.Path(dir_okay=False, path_type=Path),
        help="Draw servo angles over virtual time into this PNG.",
    )
    @click.option(
        "--hold-button",
        "hold_button",
        metavar="NAME",
        help="Hold remote button(s) while each motion plays (UP, CIRCLE, UP+S1...).",
    )
    @click.option(
        "--for",
        "hold_for",
        type=click.FloatRange(min=0),
        default=1.0,
        show_default=True,
        help="Seconds to hold --hold-button, then release it.",
    )
    @click.option(
        "--limit",
        type=click.FloatRange(min=0.001),
        default=60.0,
        show_default=True,
        help="Virtual seconds per motion before it counts as a timeout.",
    )
    @build_options
    @LAYOUT_OPTION
    @handle_errors
    def simulate(
        file: Path,
        motion: tuple[int, ...],
        as_json: bool,
        plot: Path | None,
        hold_button: str | None,
        hold_for: float,
        limit: float,
        layout_name: str | None,
    ) -> None:
        """Boot FILE (.h4p or image) in the emulator and play its motions in virtual time.

        Each motion is played as a host does (suspend, PC to the main loop, CALL, resume). Status:
        completed (returned to the main loop), waiting (loops reading an input, e.g. a button
        or AD sensor, as its program defines), stalled (repeats itself without reading any
        input), timeout (--limit reached) or error (ROMERR, command error, call-stack
        overflow/underflow; with the PC and the instruction). A boot that fails is reported with
        its cause and the motions are still played from the host. Exit status 0 when the boot
        and every motion completed or wait, 1 if any error, 2 if any timeout or stall.
        """
        from rcb4hv.project.simulate import Simulator

        image, lay, names = _load(file, layout_name)
        hold = _parse_buttons(hold_button) if hold_button else 0
        slots = list(motion)
        if not slots:
            slots = sorted(names) if names else _image_slots(image, lay)
        samples: list[tuple[float, dict[int, int | None]]] = []
        sim: Simulator

        def record(t: float, outs: dict[int, int]) -> None:
            # free / hold outputs have no angle
            samples.append(
                (
                    t,
                    {
                        k: None
                        if (st := sim.board.servo_state(k)) is None or st.output >= 0x7FFF
                        else v
                        for k, v in outs.items()
                    },
                )
            )

        sim = Simulator(image, listener=record if plot else None, motion_layout=lay)
        boot = sim.boot()
        starts: list[tuple[float, int]] = []
        results = []
        # a failed boot is reported; every motion is still played from the host (spec 11.4)
        for slot in slots:
            starts.append((sim.now, slot))
            results.append(
                sim.play(
                    lay.address(slot),
                    slot=slot,
                    name=names.get(slot, ""),
                    hold=hold,
                    hold_for=hold_for,
                    limit=limit,
                )
            )
        summary: dict[str, int] = {}
        for r in results:
            summary[r.status] = summary.get(r.status, 0) + 1
        virtual = sum(r.duration for r in results)
        if as_json:
            print_json(
                {
                    "boot": boot.to_dict(),
                    "motions": [r.to_dict() for r in results],
                    "summary": summary,
                    "virtual_seconds": round(virtual, 6),
                }
            )
        else:
            click.echo(
                f"boot: {boot.status} after {boot.duration:.3f} s virtual"
                + (f" ({boot.detail})" if boot.detail else "")
            )
            print_table(
                ("slot", "address", "name", "status", "virtual s", "instr", "detail"),
                [
                    [
                        r.slot or "-",
                        f"{r.address:05X}",
                        r.name,
                        r.status,
                        f"{r.duration:.3f}",
                        r.instructions,
                        r.detail,
                    ]
                    for r in results
                ],
            )
            parts = ", ".join(f"{n} {s}" for s, n in sorted(summary.items()))
            click.echo(f"{len(results)} motions: {parts or 'none'}; {virtual:.3f} s virtual")
        if plot is not None:
            _plot(plot, samples, starts)
            if not as_json:
                click.echo(f"wrote {plot}")
        codes = {STATUS_EXIT.get(r.status, 0) for r in [boot, *results]}
        sys.exit(1 if 1 in codes else max(codes))

    # ------------------------------------------------------------------ upload

    @project.command("upload")
    @click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
    @connection_options
    @click.option(
        "--only-changed",
        is_flag=True,
        help="Read the board's ROM first; write only the 128-byte pages that differ.",
    )
    @click.option(
        "--verify/--no-verify",
        default=True,
        show_default=True,
        help="Read every written chunk back and compare.",
    )
    @click.option(
        "--restart/--no-restart",
        default=True,
        show_default=True,
        help="Restart the ROM program from 000000h afterwards.",
    )
    @click.option("--progress/--no-progress", default=True, show_default=True)
    @build_options
    @handle_errors
    def upload(
        file: Path,
        port: str | None,
        baud: str,
        timeout: float,
        only_changed: bool,
        verify: bool,
        restart: bool,
        progress: bool,
    ) -> None:
        """Write the ROM image of FILE (.h4p or a 256 KB image) to the board at --port."""
        from rcb4hv.project.upload import upload_image

        image, _, _ = _load(file)
        with open_robot(port, baud, timeout) as robot:
            if only_changed:
                with _progress(len(image), "read", progress) as rbar:
                    current = robot.read_rom(0, len(image), progress=rbar)
                from rcb4hv.project.upload import changed_pages

                n = len(changed_pages(current, image))
                with _progress(n * 128, "write", progress) as bar:
                    res = upload_image(
                        robot,
                        image,
                        only_changed=True,
                        verify=verify,
                        restart=restart,
                        progress=bar,
                        known=current,
                    )
            else:
                with _progress(len(image), "write", progress) as bar:
                    res = upload_image(robot, image, verify=verify, restart=restart, progress=bar)
        checked = " and verified" if verify else ""
        click.echo(
            f"wrote{checked} {res.pages_written} of {res.pages_total} pages "
            f"({res.bytes_written} bytes)"
        )


def _image_slots(image: bytes, lay: MotionLayout = HTH4_22) -> list[int]:
    from rcb4hv.project.image import read_image

    return [m.slot for m in read_image(image, lay).motions]


def _plot(
    path: Path, samples: list[tuple[float, dict[int, int | None]]], starts: list[tuple[float, int]]
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rcb4hv.protocol import position_to_degrees

    channels = sorted({k for _, outs in samples for k in outs})
    fig, ax = plt.subplots(figsize=(max(8.0, min(60.0, len(samples) / 150)), 6))
    times = [t for t, _ in samples]
    for ics in channels:
        ys = []
        for _, outs in samples:
            v = outs.get(ics)
            ys.append(float("nan") if v is None else position_to_degrees(v))
        ax.plot(times, ys, linewidth=0.8, label=f"ICS {ics}")
    for t, slot in starts:
        ax.axvline(t, color="grey", linewidth=0.5, linestyle=":")
        ax.annotate(
            str(slot), (t, 1.0), xycoords=("data", "axes fraction"), fontsize=6, va="bottom"
        )
    ax.set_xlabel("virtual time (s)")
    ax.set_ylabel("servo angle (degrees, trim included)")
    if channels:
        ax.legend(fontsize=6, ncol=2, loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
