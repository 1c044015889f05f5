#!/usr/bin/env python3
"""Count the program block kinds over a directory of HeartToHeart4 projects (a sweep, not a test).

    PYTHONPATH=src python tools/block_counts.py DIR [DIR ...] [--json]

For every ``*.h4p`` under the directories: each used motion is read as a program
(:func:`rcb4hv.hth4.blocks.motion_program`), sent through its JSON text and compiled back,
and through HeartToHeart4 flowchart XML and back (:mod:`rcb4hv.hth4.blocks.flowxml`). Prints
per project the motions, entries, raw blocks and round-trip failures, then the block-kind
counts over all projects and the raw-entry ratio. Exit status 1 if any round trip changed a
motion.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import load_project, parse_motion_xml
from rcb4hv.hth4.blocks import compile_program, dump_program, motion_program, program_from_json
from rcb4hv.hth4.blocks.flowxml import EXACT_NAME, motion_from_xml, motion_xml


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+", type=Path)
    ap.add_argument("--json", action="store_true", help="print the totals as JSON")
    args = ap.parse_args()
    files = sorted(f for d in args.dirs for f in d.rglob("*.h4p"))
    kinds: Counter[str] = Counter()
    totals: Counter[str] = Counter()
    failures: list[str] = []
    for f in files:
        try:
            project = load_project(f)
        except Rcb4Error as exc:
            print(f"{f}: not read: {exc}", file=sys.stderr)
            totals["unreadable"] += 1
            continue
        row: Counter[str] = Counter()
        for m in project.used_motions:
            program = motion_program(project, m.slot)
            row["motions"] += 1
            row["entries"] += len(m.frames)
            for b in program.blocks:
                kinds[b.kind] += 1
                if b.kind == "raw":
                    row["raw"] += 1
            back = program_from_json(json.loads(dump_program(program)))
            if compile_program(project, m.slot, back) != m.frames:
                failures.append(f"{f} motion {m.slot}: JSON round trip")
                row["json_fail"] += 1
            xml = motion_xml(project, m.slot)
            row["xml_exact_form"] += parse_motion_xml(xml).name == EXACT_NAME
            if motion_from_xml(project, m.slot, xml) != m.frames:
                failures.append(f"{f} motion {m.slot}: XML round trip")
                row["xml_fail"] += 1
        totals.update(row)
        totals["projects"] += 1
        print(
            f"{f.name}: {row['motions']} motions, {row['entries']} entries, {row['raw']} raw, "
            f"{row['json_fail']} JSON / {row['xml_fail']} XML round-trip failures, "
            f"{row['xml_exact_form']} flowcharts in the exact form"
        )
    ratio = totals["raw"] / totals["entries"] if totals["entries"] else 0.0
    if args.json:
        print(json.dumps({"totals": dict(totals), "kinds": dict(kinds), "raw_ratio": ratio}))
    else:
        print(
            f"\n{totals['projects']} projects, {totals['motions']} motions, "
            f"{totals['entries']} entries; raw blocks {totals['raw']} ({100 * ratio:.3f} %); "
            f"{totals['motions'] - totals['xml_exact_form']} motions drawn as HeartToHeart4 "
            "flowcharts, the others in the exact form"
        )
        for kind, n in kinds.most_common():
            print(f"  {kind:16s} {n}")
    for line in failures:
        print(line, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
