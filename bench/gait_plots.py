"""The plots of docs/gait.md: a generated walk's CoM and ZMP, and the fall probability
against the step length (``make gait-plots``; writes docs/gait-com-zmp.png and
docs/gait-fall-stride.png).

``python -m bench.gait_plots [--robot kxr-l2] [--trials 12] [--out docs]``. Slow (a few
minutes on 2 cores): it plays every stride ``--trials`` times in MuJoCo.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

STRIDES = (0.03, 0.06, 0.08, 0.10, 0.12, 0.14)


def com_zmp(robot: str, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.robot.builtin import load_builtin

    model = load_builtin(robot)
    w = walk(model, default_params(model, "forward", steps=4))
    p = w.pattern
    fig, axes = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for k, (ax, label) in enumerate(zip(axes, ("x (forward)", "y (left)"), strict=True)):
        ax.plot(p.t, p.zmp_ref[:, k] * 1000, "k--", lw=1, label="ZMP reference")
        ax.plot(p.t, p.zmp[:, k] * 1000, lw=1.2, label="ZMP of the model")
        ax.plot(p.t, p.com[:, k] * 1000, lw=1.8, label="centre of mass")
        ax.set_ylabel(f"{label}, mm")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper left", fontsize=8)
    axes[1].set_xlabel("time, s")
    fig.suptitle(f"{robot}: 4 steps forward, stride {w.params.stride * 1000:.0f} mm")
    fig.tight_layout()
    fig.savefig(out / "gait-com-zmp.png", dpi=90)
    plt.close(fig)


def fall_vs_stride(robot: str, trials: int, out: Path) -> list[dict[str, float]]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.gait.motion import walk_motion
    from rcb4hv.hth4.keyframes import add_motion
    from rcb4hv.hth4.newproject import new_project
    from rcb4hv.project.relocate import project_image
    from rcb4hv.project.robust import robust
    from rcb4hv.robot.builtin import load_builtin

    model = load_builtin(robot)
    rows = []
    for stride in STRIDES:
        params = replace(default_params(model, "forward", steps=4), stride=stride)
        motion = walk_motion(model, walk(model, params), slot=2, name="walk").motion
        image, layout = project_image(add_motion(new_project(model), motion))
        (m,) = robust(image, [2], layout=layout, robot=model, trials=trials, seed=0)
        rows.append({"stride_m": stride, "p": m["fall_probability"], "lo": m["ci"][0],
                     "hi": m["ci"][1], "dx_m": m["dx_m"]["median"]})  # fmt: skip
        print(json.dumps(rows[-1]), flush=True)
    fig, ax = plt.subplots(figsize=(7, 4))
    xs = [r["stride_m"] * 1000 for r in rows]
    ys = [r["p"] for r in rows]
    err = [[r["p"] - r["lo"] for r in rows], [r["hi"] - r["p"] for r in rows]]
    ax.errorbar(xs, ys, yerr=err, fmt="o-", capsize=4)
    ax.set_xlabel("stride (body travel per step), mm")
    ax.set_ylabel("fall probability (Wilson 95 %)")
    ax.set_ylim(-0.05, 1.05)
    ax.grid(alpha=0.3)
    ax.set_title(f"{robot}: 4 steps forward, {trials} trials per stride")
    fig.tight_layout()
    fig.savefig(out / "gait-fall-stride.png", dpi=90)
    plt.close(fig)
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.gait_plots", description=__doc__)
    parser.add_argument("--robot", default="kxr-l2")
    parser.add_argument("--trials", type=int, default=12)
    parser.add_argument("--out", type=Path, default=Path("docs"))
    args = parser.parse_args(argv)
    com_zmp(args.robot, args.out)
    fall_vs_stride(args.robot, args.trials, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
