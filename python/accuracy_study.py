"""The accuracy contract's figures (docs/embedding.md): the worst relative error of what the
consistent model serves against a 50-digit reference (python/tests/exact.py), by distance
`s = min |r_kk|` from eq 16's singularities, over random states near them; and how many
forward-dynamics calls are refused.

    python python/accuracy_study.py [--plot FILE.png]   (c5_kernels and mpmath installed;
                                                         matplotlib for the plot)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent / "tests"))

import c5_kernels  # noqa: E402
from conftest import DEFAULT_ROBOT  # noqa: E402
from exact import Exact, forward_dynamics  # noqa: E402
from reference import Robot, rotation  # noqa: E402

STATES = 400


def relative(served, exact) -> float:
    exact = np.array([float(v) for v in exact])
    return float(np.max(np.abs(np.ravel(served) - exact)) / np.max(np.abs(exact)))


def main() -> None:
    robot = Robot.load(DEFAULT_ROBOT)
    c5 = c5_kernels.C5("consistent")
    rng = np.random.default_rng(2)
    rows = []
    for _ in range(STATES):
        which, s = rng.integers(0, 3), 10 ** rng.uniform(-7, 0)
        pose = np.concatenate([rng.uniform(-0.4, 0.4, 3), rng.uniform(-0.05, 0.05, 3)])
        pose[which] = (np.pi / 2 - s) * rng.choice([-1, 1])
        distance = np.min(np.abs(np.diag(rotation(*pose[:3]))))
        w, v = rng.uniform(-1, 1, 3), rng.uniform(-0.3, 0.3, 3)
        wd, a = rng.uniform(-3, 3, 3), rng.uniform(-2, 2, 3)
        exact = Exact(robot, pose, w, v, wd, a)
        try:
            gamma = c5.inverse_dynamics(pose, w, v, wd, a)
            qd = c5.joint_velocities(pose, w, v)
        except ValueError:
            continue
        try:
            served = np.concatenate(c5.forward_dynamics(pose, w, v, gamma))
            forward = relative(served, forward_dynamics(robot, pose, w, v, gamma))
        except ValueError:
            forward = np.nan
        rows.append([distance, relative(gamma, exact.gamma()), relative(qd, exact.qd), forward])
    rows = np.array(rows)
    if "--plot" in sys.argv:
        plot(rows, sys.argv[sys.argv.index("--plot") + 1])
    print("| s = min \\|r_kk\\| | states | Γ | q̇ | forward dynamics served | refused |")
    print("|---|---:|---:|---:|---:|---:|")
    for lo in range(-7, 0):
        band = rows[(rows[:, 0] >= 10.0 ** lo) & (rows[:, 0] < 10.0 ** (lo + 1))]
        if len(band) == 0:
            continue
        served = band[~np.isnan(band[:, 3]), 3]
        worst = f"{served.max():.1e}" if len(served) else "—"
        print(f"| [1e{lo}, 1e{lo + 1}) | {len(band)} | {band[:, 1].max():.1e} | "
              f"{band[:, 2].max():.1e} | {worst} | {int(np.isnan(band[:, 3]).sum())} |")


def plot(rows, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    ax.loglog(rows[:, 0], rows[:, 1], ".", label="Γ (inverse dynamics)", alpha=0.7)
    ax.loglog(rows[:, 0], rows[:, 2], "x", label="q̇", alpha=0.7)
    served = ~np.isnan(rows[:, 3])
    ax.loglog(rows[served, 0], rows[served, 3], "o", label="forward dynamics, served",
              alpha=0.8)
    ax.axhline(1e-8, color="k", lw=1, ls="--", label="the f64 bound, 1e-8")
    ax.axvspan(1e-7, 1e-2, color="0.85", label="forward dynamics refused (s < 1e-2)")
    s = np.logspace(-2, 0, 20)
    ax.loglog(s, 1.2e-15 / s**3, "k:", lw=1, label="1.2e-15 / s³")
    ax.set_xlabel("s = min |r_kk|, distance from eq 16's singularities")
    ax.set_ylabel("relative error against 50 digits")
    ax.set_title("Consistent model, default robot: what is served")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(0.01, 0.92))
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
