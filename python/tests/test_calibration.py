"""Kinematic calibration from Python: `C5.calibration_plan` and `C5.calibrate` on a hexapod whose
true geometry the tests draw at random, measured with a laser tracker's noise."""

from __future__ import annotations

import re
import tomllib

import numpy as np
import pytest

import c5_kernels
from conftest import ROOT

HEXAPOD = ROOT / "docs" / "hexapod.toml"


def as_built(path, seed):
    """The example with every joint centre moved by up to 2 mm per component and every
    encoder offset by up to 3 mm; returns the true parameters in the report's order."""
    rng = np.random.default_rng(seed)
    text = HEXAPOD.read_text()

    def jig(m):
        values = [float(v) + rng.uniform(-2e-3, 2e-3) for v in m.group(2).split(",")]
        return m.group(1) + "[" + ", ".join(f"{v:.9f}" for v in values) + "]"

    text = re.sub(r"^(base = |platform = )\[([^\]]*)\]", jig, text, flags=re.M)
    text = re.sub(r"^(rod = .*)$",
                  lambda m: m.group(1) + f"\nencoder_offset = {rng.uniform(-3e-3, 3e-3):.9f}",
                  text, flags=re.M)
    path.write_text(text)
    legs = tomllib.loads(text)["legs"]
    return np.array([v for leg in legs for v in [*leg["base"], *leg["platform"],
                                                  leg["encoder_offset"]]])


def test_calibrate_recovers_an_unseen_hexapod(tmp_path):
    nominal = c5_kernels.C5(robot=HEXAPOD)
    truth_values = as_built(tmp_path / "truth.toml", seed=5)
    truth = c5_kernels.C5(robot=tmp_path / "truth.toml")
    poses = nominal.calibration_plan(60, seed=2)
    assert poses.shape == (60, 6)
    rng = np.random.default_rng(6)
    q = truth.inverse_kinematics(poses) + rng.normal(0, 1e-6, (60, 6))
    measured = poses + np.column_stack([rng.normal(0, 20e-6, (60, 3)),
                                        rng.normal(0, 10e-6, (60, 3))])
    result = nominal.calibrate(measured, q)

    assert len(result["names"]) == 42 and result["names"][:2] == ["A1.x", "A1.y"]
    assert result["unobservable"] == []
    z = (result["values"] - truth_values) / result["std_dev"]
    assert np.all(np.abs(z) < 4), z
    assert 0.6 < result["variance_factor"] < 1.5
    assert np.sqrt(np.mean(result["residuals_after"] ** 2)) < 3e-5
    assert np.sqrt(np.mean(result["residuals_before"] ** 2)) > 5e-4

    (tmp_path / "calibrated.toml").write_text(result["robot_toml"])
    fitted = c5_kernels.C5(robot=tmp_path / "calibrated.toml")
    unseen = nominal.calibration_plan(30, seed=9)
    error = fitted.inverse_kinematics(unseen) - truth.inverse_kinematics(unseen)
    assert np.sqrt(np.mean(error ** 2)) < 10e-6


def test_calibration_is_the_hexapods():
    with pytest.raises(ValueError, match="calibration"):
        c5_kernels.C5().calibrate(np.zeros((10, 6)), np.zeros((10, 6)))


def test_too_few_poses_are_refused():
    nominal = c5_kernels.C5(robot=HEXAPOD)
    poses = nominal.calibration_plan(8, seed=1)[:5]
    with pytest.raises(ValueError, match="at least 8"):
        nominal.calibrate(poses, nominal.inverse_kinematics(poses))


@pytest.mark.parametrize("name, width", [("rus-hexapod.toml", 6), ("delta.toml", 3)])
def test_calibrate_serves_the_rotary_mechanisms(tmp_path, name, width):
    """A rotary hexapod's and a Delta's crank and rod lengths: a file built 1 mm off its
    rods, found again from its own readings, the residuals in rad."""
    path = ROOT / "docs" / name
    text = path.read_text()
    built = re.sub(r"^(rod = \{ length = )([0-9.]+)",
                   lambda m: m.group(1) + f"{float(m.group(2)) + 1e-3:.6f}", text, flags=re.M)
    (tmp_path / "truth.toml").write_text(built)
    nominal = c5_kernels.Robot(robot=path)
    truth = c5_kernels.Robot(robot=tmp_path / "truth.toml")
    poses = nominal.calibration_plan(40, seed=3)
    assert poses.shape == (40, width)
    result = nominal.calibrate(poses, truth.inverse_kinematics(poses))
    assert set(result["units"]) == {"m", "rad"}
    rods = [v for n, v in zip(result["names"], result["values"]) if n.startswith("L")]
    lengths = [leg["rod"]["length"] for leg in tomllib.loads(built)[
        "arms" if width == 3 else "legs"]]
    assert np.allclose(rods, lengths, atol=1e-6), (rods, lengths)
    assert np.max(np.abs(result["residuals_after"])) < 1e-6
