"""Driver run inside a venv holding the PyPI ``rcb4`` package (0.1.6): prints JSON lines.

Usage: python rcb4_driver.py PTY_PATH. Not a test module (no test_ prefix); the test
``test_emu_rcb4_client.py`` runs it against ``rcb4hv emulate --pty``.
"""

from __future__ import annotations

import contextlib
import io
import json
import sys
import time


def main() -> int:
    path = sys.argv[1]
    from rcb4.rcb4interface import RCB4Interface

    out: dict[str, object] = {}
    ri = RCB4Interface()
    chatter = io.StringIO()
    try:
        with contextlib.redirect_stdout(chatter):
            out["open"] = bool(ri.open(path))
            out["ids"] = [int(i) for i in ri.search_servo_ids()]
            out["angles"] = [float(a) for a in ri.angle_vector()]
            ri.hold()
            ids = out["ids"]
            sent = ri.servo_angle_vector(ids, [8000] * len(ids), velocity=10)
            out["sent"] = [int(i) for i in sent]
            ri.wait_interpolation(timeout=5)
            out["angles_after_move"] = [float(a) for a in ri.angle_vector()]
            out["stretch"] = bool(ri.send_stretch(60))
            ri.free()
            out["play"] = bool(ri.play_motion(1))
            seen: list[int] = []
            peak = -1000.0
            idx = ids.index(2)  # type: ignore[attr-defined]
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline:
                n = ri.get_motion_play_number()
                seen.append(int(n))
                peak = max(peak, float(ri.angle_vector()[idx]))
                if len(seen) > 3 and seen[-1] == 0 and 1 in seen:
                    break
                time.sleep(0.02)
            out["motion_numbers"] = sorted(set(seen))
            out["motion_ended"] = seen[-1] == 0
            out["peak_ics2_deg"] = peak
    finally:
        ri.close()
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
