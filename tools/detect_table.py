"""Print the robot detection table over a directory of HeartToHeart4 projects (a sweep, not a
test: the public sample projects are never part of the repository).

    python tools/detect_table.py DIR [--facts FILE.json] [--json]

For each ``*.h4p`` under DIR (and each entry of a facts file: the servo tables and titles of
projects, see :func:`_facts` for the two forms it reads) it prints the project, its title,
the detected model (or the error and candidates) and whether the family (and, for a biped,
the arm axes) matches the kit code in the project's folder or file name
(``Hello_kxrl4t/...`` -> L4T), which is the expectation.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from rcb4hv.errors import AmbiguousRobotError, RobotModelError
from rcb4hv.hth4 import Project, load_project
from rcb4hv.hth4.robotpick import detect_project
from rcb4hv.robot.kit import parse_kit_code


def _say(text: str) -> None:
    sys.stdout.write(text + "\n")


def _expected(path: str) -> Any:
    for part in reversed(Path(path).parts):
        stem = part.removeprefix("Hello_").split("(")[0].split(".")[0]
        code = parse_kit_code(stem if "kxr" in stem.lower() else "")
        if code is not None:
            return code
    return None


def _facts(data: Any) -> list[tuple[str, str, dict[int, str]]]:
    """(project, title, ICS number -> name of the slots in use) of each facts entry: a list of
    ``{file, title, servos: [{ics, name}]}``, or ``{projects: [{path, project_title, servos:
    [{device, name, mode}]}]}`` (a ServoConfigParams transcription; ``mode`` None = unused)."""
    if isinstance(data, dict):
        return [
            (
                p["path"],
                p.get("project_title") or "",
                {int(s["device"]): s["name"] or "" for s in p["servos"] if s["mode"] != "None"},
            )
            for p in data["projects"]
        ]
    return [
        (e["file"], e.get("title", ""), {int(s["ics"]): s["name"] or "" for s in e["servos"]})
        for e in data
    ]


def _row(where: str, title: str, source: Any) -> dict[str, Any]:
    expected = _expected(where)
    row: dict[str, Any] = {"project": where, "title": title, "model": None, "notes": []}
    try:
        model, det = (
            detect_project(source)
            if isinstance(source, Project)
            else detect_project(source, None, title)
        )
        row["model"] = model.name
        if det is not None:
            row["notes"] = list(det.notes) + [
                f"{c}: {'ok' if ok else 'FAILED'} ({d})" for c, ok, d in det.checks
            ]
    except AmbiguousRobotError as exc:
        row["error"], row["candidates"] = str(exc), list(exc.candidates)
    except RobotModelError as exc:
        row["error"] = str(exc)
    row["expected"] = expected.code if expected is not None else None
    got = parse_kit_code(row["model"] or "") if row["model"] else None
    if row["model"] in ("kxr-l2", "kxr-l2-gripper"):
        got = parse_kit_code("kxr:L2L5A3")
    right = None
    if expected is not None:
        right = got is not None and got.family == expected.family
        if right and expected.family == "humanoid" and got is not None:
            right = expected.arms in (None, got.arms)  # legs: see the notes
    row["right"] = right
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", type=Path, nargs="?")
    ap.add_argument("--facts", type=Path)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    rows = []
    if args.dir is not None:
        for path in sorted(args.dir.rglob("*.h4p")):
            project = load_project(path)
            rows.append(_row(str(path.relative_to(args.dir)), project.project_title or "", project))
    if args.facts is not None:
        for where, title, names in _facts(json.loads(args.facts.read_text(encoding="utf-8"))):
            rows.append(_row(where, title, names))
    if args.json:
        json.dump(rows, sys.stdout, ensure_ascii=False, indent=1)
        return 0
    right = sum(1 for r in rows if r["right"])
    judged = sum(1 for r in rows if r["right"] is not None)
    _say("| project | title | detected | expected | right |")
    _say("|---|---|---|---|---|")
    for r in rows:
        got = r["model"] or (
            "ambiguous: " + ", ".join(r["candidates"]) if "candidates" in r else "none"
        )
        mark = {True: "yes", False: "NO", None: "-"}[r["right"]]
        _say(f"| {r['project']} | {r['title']} | {got} | {r['expected'] or '-'} | {mark} |")
    _say(f"\n{right} of {judged} right ({len(rows)} projects)")
    for r in rows:
        for n in r["notes"]:
            _say(f"  {r['project']}: {n}")
        if "error" in r:
            _say(f"  {r['project']}: {r['error']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
