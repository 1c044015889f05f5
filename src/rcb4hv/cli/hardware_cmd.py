"""``rcb4hv doctor`` and ``rcb4hv udev-rule``: setting up a real board."""

from __future__ import annotations

import json
import sys

import click

from rcb4hv.hardware import all_passed, install_commands, run_doctor, udev_rule


@click.command()
@click.option(
    "--port",
    envvar="RCB4HV_PORT",
    default=None,
    metavar="URL",
    help="Port to check (default: $RCB4HV_PORT, else the Kondo USB adapter).",
)
@click.option("--json", "as_json", is_flag=True, help="One JSON object per check, as a list.")
@click.option("--timeout", type=float, default=0.5, show_default=True, help="Seconds per reply.")
def doctor(port: str | None, as_json: bool, timeout: float) -> None:
    """Check the setup step by step: adapter, permissions, latency timer, baud rate, version,
    system register, battery and servos. Prints a fix for every check that fails; exits 1
    unless every check passes."""
    checks = run_doctor(port, timeout=timeout)
    if as_json:
        click.echo(json.dumps([c.to_json() for c in checks], indent=2))
    else:
        for c in checks:
            click.echo(c.line())
    sys.exit(0 if all_passed(checks) else 1)


@click.command("udev-rule")
@click.option(
    "--group",
    default="dialout",
    show_default=True,
    help="Group given read/write access to the adapter (uucp on Arch).",
)
def udev_rule_cmd(group: str) -> None:
    """Print a udev rule for the Kondo USB adapters: a stable /dev/rcb4-<serial> symlink,
    group access and a 1 ms latency timer. Install it with the two commands it starts with."""
    click.echo(udev_rule(group), nl=False)
    click.echo("\nTo install (Linux):", err=True)
    for command in install_commands(group):
        click.echo(f"  {command}", err=True)


def register(cli: click.Group) -> None:
    cli.add_command(doctor)
    cli.add_command(udev_rule_cmd)
