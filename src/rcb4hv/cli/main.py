"""Entry point of the ``rcb4hv`` command line.

Each command group lives in its own module with a ``register(group)`` function, so the
modules stay independent of each other.
"""

from __future__ import annotations

import importlib
import logging
import os
import sys

import click

from rcb4hv import __version__
from rcb4hv.cli._util import error_line
from rcb4hv.errors import Rcb4Error

# Modules that contribute commands; each defines ``register(cli: click.Group) -> None``.
COMMAND_MODULES = (
    "rcb4hv.cli.decode_cmd",
    "rcb4hv.cli.emulate_cmd",
    "rcb4hv.cli.board_cmd",
    "rcb4hv.cli.motion_cmd",
    "rcb4hv.cli.demo_cmd",
    "rcb4hv.cli.project_cmd",
    "rcb4hv.cli.asm_cmd",
    "rcb4hv.cli.teach_cmd",
    "rcb4hv.cli.ui_cmd",
    "rcb4hv.cli.hardware_cmd",
    "rcb4hv.cli.trim_cmd",
    "rcb4hv.cli.robot_cmd",
    "rcb4hv.cli.robot_pose_cmd",  # adds fk and ik to the robot group: after robot_cmd
    "rcb4hv.cli.ics_cmd",
    "rcb4hv.cli.gait_cmd",
    "rcb4hv.cli.project_robust_cmd",
)


def repeat_hint(exc: click.UsageError, argv: list[str]) -> str | None:
    """How to give a repeatable option several values, when they were given as one list.

    ``--motion 9 10`` leaves ``10`` over ("Got unexpected extra argument (10)"); click's
    repeatable options take one value each (``--motion 9 --motion 10``).
    """
    if exc.ctx is None or not exc.message.startswith("Got unexpected extra argument"):
        return None
    extra = exc.message.rpartition("(")[2].rstrip(")").split()
    if not extra:
        return None
    for at in range(1, len(argv) - len(extra) + 1):
        if argv[at : at + len(extra)] != extra:
            continue
        name = argv[at - 2] if at >= 2 else ""
        for param in exc.ctx.command.params:
            if isinstance(param, click.Option) and param.multiple and name in param.opts:
                values = [argv[at - 1], *extra]
                spelled = " ".join(f"{name} {value}" for value in values)
                return f"{name} takes one value; repeat it for each: {spelled}"
    return None


INTERRUPTED = 130
"""Exit status after Ctrl-C (128 + SIGINT), as shells report an interrupted command."""


class _Cli(click.Group):
    """The root group: a usage error of a repeatable option given a list says how to repeat."""

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        ctx.meta["rcb4hv.argv"] = list(args)
        return super().parse_args(ctx, args)

    def invoke(self, ctx: click.Context) -> object:
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            # Ctrl-C: one word and the shell's status for SIGINT (130), as `project upload`
            # and `gait tune` say more; click's "Aborted!" and status 1 read as a failure
            click.echo("interrupted", err=True)
            sys.exit(INTERRUPTED)
        except click.UsageError as exc:
            hint = repeat_hint(exc, ctx.meta.get("rcb4hv.argv", []))
            if hint is None:
                raise
            raise click.UsageError(f"{exc.message}\n{hint}", exc.ctx) from None


@click.group(cls=_Cli, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rcb4hv")
@click.option("-v", "--verbose", count=True, help="Log more (-v info, -vv debug).")
def cli(verbose: int) -> None:
    """Drive a Kondo RCB-4HV board, or its emulator, from the shell."""
    level = logging.WARNING - 10 * min(verbose, 2)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")


for _name in COMMAND_MODULES:
    importlib.import_module(_name).register(cli)


def main() -> None:
    """Console-script entry point."""
    try:
        cli()
    except BrokenPipeError:
        # stdout was closed by its reader (`rcb4hv ... | head`): stop quietly, as Unix tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        sys.exit(1)
    except Rcb4Error as exc:
        # every rcb4hv error is one line, also from a command without @handle_errors
        click.echo(error_line(exc), err=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
