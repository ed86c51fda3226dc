"""The accuracy contract's figures (docs/embedding.md): the worst relative error of what the
consistent model serves against a 50-digit reference (python/tests/exact.py), by distance
`s = min |r_kk|` from eq 16's singularities, over random states near them; and how many
forward-dynamics calls are refused. With `--joint-plot`, the same for the joint space: the
platform's acceleration from the actuators' and the forces from them, each with its guard.

    python python/accuracy_study.py [--plot FILE.png] [--joint-plot FILE.png]
        (c5_kernels and mpmath installed; matplotlib for the plots)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent / "tests"))

import c5_kernels  # noqa: E402
from conftest import DEFAULT_ROBOT  # noqa: E402
from exact import Exact, forward_dynamics, joint_state  # noqa: E402
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
    if "--joint-plot" in sys.argv:
        joint_plot(joint_rows(robot, c5), sys.argv[sys.argv.index("--joint-plot") + 1])
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


def joint_rows(robot, c5):
    """Per state: the distance, and the relative errors of the platform acceleration from
    `(q, q̇, q̈)` (`joint_state`) and of `Γ(q, q̇, q̈)`, NaN where refused."""
    rng = np.random.default_rng(3)
    rows = []
    for _ in range(STATES):
        which, s = rng.integers(0, 3), 10 ** rng.uniform(-9, 0)
        pose = np.concatenate([rng.uniform(-0.4, 0.4, 3), rng.uniform(-0.05, 0.05, 3)])
        pose[which] = (np.pi / 2 - s) * rng.choice([-1, 1])
        exact = Exact(robot, pose, *rng.uniform(-1, 1, (4, 3)))
        q, qd, qdd = (np.array([float(x) for x in v]) for v in (exact.q, exact.qd, exact.qdd))
        try:
            found = c5.forward_kinematics(q)
        except ValueError:
            continue  # beyond the forward singularity
        pose, twist, accel = joint_state(robot, q, qd, qdd, guess=found)
        errors = [float(np.min(np.abs(np.diag(rotation(*found[:3])))))]
        try:
            served = c5.joint_state(q, qd, qdd)
            errors.append(relative(np.concatenate(served[3:]), accel))
        except ValueError:
            errors.append(np.nan)
        try:
            gamma = Exact(robot, pose, twist[:3], twist[3:], accel[:3], accel[3:]).gamma()
            errors.append(relative(c5.inverse_dynamics_joint(q, qd, qdd), gamma))
        except ValueError:
            errors.append(np.nan)
        rows.append(errors)
    return np.array(rows)


def joint_plot(rows, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    for column, marker, label in [(1, "o", "platform acceleration from (q, q̇, q̈), served"),
                                  (2, ".", "Γ(q, q̇, q̈), served")]:
        served = ~np.isnan(rows[:, column])
        ax.loglog(rows[served, 0], rows[served, column], marker, label=label, alpha=0.7)
    ax.axhline(1e-8, color="k", lw=1, ls="--", label="the f64 bound, 1e-8")
    ax.axvline(1e-3, color="C0", lw=1, label="JOINT_STATE_TOLERANCE = 1e-3")
    ax.axvline(1e-7, color="C1", lw=1, label="JOINT_DYNAMICS_TOLERANCE = 1e-7")
    s = np.logspace(-3, 0, 20)
    ax.loglog(s, 3e-18 / s**3, "C0:", lw=1, label="3e-18 / s³ (measured before the guard)")
    s = np.logspace(-7, 0, 20)
    ax.loglog(s, 2.6e-17 / s, "C1:", lw=1, label="2.6e-17 / s (measured before the guard)")
    ax.set_xlabel("s = min |r_kk|, distance from eq 16's singularities")
    ax.set_ylabel("relative error against 50 digits")
    ax.set_title("Consistent model, default robot: the joint space, what is served")
    ax.set_ylim(1e-28, 1e-6)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    refused = np.isnan(rows[:, 1:]).sum(axis=0)
    print(f"joint space: {len(rows)} states; refused: acceleration {refused[0]}, Γ {refused[1]};"
          f" worst served: acceleration {np.nanmax(rows[:, 1]):.1e}, Γ {np.nanmax(rows[:, 2]):.1e}")


if __name__ == "__main__":
    main()
