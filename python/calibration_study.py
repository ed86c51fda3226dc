"""How many poses of what noise buy what accuracy: the table of docs/calibration.md.

For each instrument (its position and angle noise; encoders 1 µm) and number of planned poses,
five as-built hexapods (the example with up to 2 mm on every joint centre and 3 mm on every
offset, at random) are measured, calibrated, and judged on 100 unseen poses: the RMS error of
the predicted leg lengths, the worst position the forward kinematics finds from the true
readings, and the median of the parameters' standard deviations.

    python python/calibration_study.py      (with c5_kernels installed: docs/python.md)
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent / "tests"))

import c5_kernels  # noqa: E402
from test_calibration import as_built  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
HEXAPOD = ROOT / "docs" / "hexapod.toml"
INSTRUMENTS = {"CMM (2 µm, 5 µrad)": (2e-6, 5e-6), "laser tracker (10 µm, 20 µrad)": (10e-6, 20e-6),
               "camera (50 µm, 100 µrad)": (50e-6, 100e-6)}
POSES = [15, 30, 60, 120]
ROBOTS = 5


def trial(nominal, n, position, angle, seed, tmp: Path):
    as_built(tmp / "truth.toml", seed)
    rng = np.random.default_rng(seed + 100)
    truth = c5_kernels.C5(robot=tmp / "truth.toml")
    poses = nominal.calibration_plan(n, seed=seed)
    q = truth.inverse_kinematics(poses) + rng.normal(0, 1e-6, (n, 6))
    measured = poses + np.column_stack([rng.normal(0, angle, (n, 3)),
                                        rng.normal(0, position, (n, 3))])
    result = nominal.calibrate(measured, q, noise_position=position, noise_angle=angle)
    (tmp / "fitted.toml").write_text(result["robot_toml"])
    fitted = c5_kernels.C5(robot=tmp / "fitted.toml")
    unseen = nominal.calibration_plan(100, seed=seed + 1000)
    q_true = truth.inverse_kinematics(unseen)
    lengths = np.sqrt(np.mean((fitted.inverse_kinematics(unseen) - q_true) ** 2))
    found = fitted.forward_kinematics(q_true)
    position_error = np.max(np.linalg.norm(found[:, 3:] - unseen[:, 3:], axis=1))
    return lengths, position_error, np.nanmedian(result["std_dev"])


def main() -> None:
    nominal = c5_kernels.C5(robot=HEXAPOD)
    print("| instrument | poses | leg lengths of unseen poses (µm RMS) | worst position from "
          "the forward kinematics (µm) | median σ of a parameter (µm) |")
    print("|---|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (position, angle) in INSTRUMENTS.items():
            for n in POSES:
                rows = np.array([trial(nominal, n, position, angle, seed, Path(tmp))
                                 for seed in range(ROBOTS)])
                lengths, worst, sigma = rows[:, 0].mean(), rows[:, 1].max(), rows[:, 2].mean()
                print(f"| {name} | {n} | {lengths * 1e6:.1f} | {worst * 1e6:.1f} | "
                      f"{sigma * 1e6:.0f} |")


if __name__ == "__main__":
    main()
