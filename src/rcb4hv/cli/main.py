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


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
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
