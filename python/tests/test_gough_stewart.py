"""A hexapod through the Python module: `C5(robot="hexapod.toml")` serves the Gough-Stewart
platform of the file with the conventions of the C5, to the bit of the `c5` program, and
refuses by name what is the C5's alone."""

from __future__ import annotations

import numpy as np
import pytest

import c5_kernels
from conftest import ROOT

HEXAPOD = ROOT / "docs" / "hexapod.toml"
HOME_HEIGHT = 0.425  # the example hexapod's home: its platform's height above the base


@pytest.fixture(scope="module")
def hexapod():
    return c5_kernels.C5(robot=HEXAPOD)


def hexapod_states(n, seed):
    """Seeded states about the example's home: |angles| ≤ 0.2 rad, ±0.05 m."""
    rng = np.random.default_rng(seed)
    pose = np.column_stack([rng.uniform(-0.2, 0.2, (n, 3)), rng.uniform(-0.05, 0.05, (n, 3))])
    pose[:, 5] += HOME_HEIGHT
    return (pose, rng.uniform(-1, 1, (n, 3)), rng.uniform(-0.3, 0.3, (n, 3)),
            rng.uniform(-3, 3, (n, 3)), rng.uniform(-2, 2, (n, 3)))


def test_the_file_gives_a_hexapod(hexapod):
    assert hexapod.mechanism == "gough-stewart" and hexapod.model == "gough-stewart"
    assert "gough-stewart" in repr(hexapod)


def test_the_kernels_are_the_programs(hexapod, run_c5):
    pose, omega, velocity, omega_dot, acceleration = hexapod_states(8, seed=1)
    lines = [{"pose": list(pose[k]), "omega": list(omega[k]), "velocity": list(velocity[k]),
              "omega_dot": list(omega_dot[k]), "acceleration": list(acceleration[k])}
             for k in range(8)]
    program = run_c5("eval", lines, "--robot", str(HEXAPOD))
    gamma = hexapod.inverse_dynamics(pose, omega, velocity, omega_dot, acceleration)
    assert np.array_equal(gamma, np.array([line["gamma"] for line in program]))
    assert np.array_equal(hexapod.inverse_kinematics(pose), np.array([line["q"] for line in program]))
    jinv = hexapod.inverse_jacobian(pose)
    assert np.array_equal(jinv, np.array([line["jinv"] for line in program]))
    # J J⁻¹ = I, and the forward dynamics of the forces gives the accelerations back.
    assert np.allclose(hexapod.jacobian(pose) @ jinv, np.eye(6), atol=1e-12)
    back = hexapod.forward_dynamics(pose, omega, velocity, gamma)
    assert np.allclose(np.hstack(back), np.hstack([omega_dot, acceleration]), rtol=0, atol=1e-9)


def test_leg_lengths_give_their_pose_back(hexapod):
    pose = hexapod_states(20, seed=2)[0]
    q = hexapod.inverse_kinematics(pose)
    assert np.allclose(hexapod.forward_kinematics(q), pose, rtol=0, atol=1e-11)


def test_identify_recovers_the_hexapods_base_parameters(hexapod):
    s = hexapod_states(300, seed=3)
    assert len(hexapod.base_parameters) == 46 and len(hexapod.standard_parameters) == 70
    viscous, coulomb = [3.0, 2.5, 4.0, 3.5, 2.0, 2.2], [1.0, 0.8, 1.2, 0.9, 1.1, 0.7]
    beta = hexapod.base_values(viscous, coulomb)
    # The base regressor times the base parameters is the full regressor times the standard
    # ones: both the forces with friction.
    pi = hexapod.standard_values(viscous, coulomb)
    gamma = hexapod.base_regressor(*s) @ beta
    assert np.allclose(hexapod.regressor(*s) @ pi, gamma, rtol=1e-10, atol=1e-9)
    estimate = hexapod.identify(*s, gamma)
    assert estimate["model"] == "gough-stewart" and estimate["names"] == hexapod.base_parameters
    assert np.allclose(estimate["values"], beta, rtol=1e-7, atol=1e-8)


def test_what_is_the_c5s_alone_is_refused_by_name(hexapod):
    pose = hexapod_states(1, seed=4)[0][0]
    with pytest.raises(ValueError, match="no limit margins for the gough-stewart mechanism"):
        hexapod.limit_margins(pose)
    q = hexapod.inverse_kinematics(pose)
    with pytest.raises(ValueError, match="joint-space derivatives"):
        hexapod.inverse_dynamics_joint_derivatives(q)
