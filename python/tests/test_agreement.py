"""The module computes what the Rust kernels compute, to the bit (through the JSON of `c5 eval`
and `c5 forward`, whose numbers round-trip exactly), and what an independent numpy
implementation of the mechanism computes, to 1e-12 relative, on states no Rust test uses."""

from __future__ import annotations

import numpy as np
import pytest

import c5_kernels
from conftest import DEFAULT_ROBOT
from reference import Model, Robot, forward_dynamics

N = 37  # nine groups of four through the batch kernels and a remainder of one


def lines(pose, omega, velocity, omega_dot, acceleration):
    return [{"pose": list(x), "omega": list(w), "velocity": list(v), "omega_dot": list(wd),
             "acceleration": list(a)}
            for x, w, v, wd, a in zip(pose, omega, velocity, omega_dot, acceleration)]


def rows(out, key):
    return np.array([line[key] for line in out])


@pytest.mark.parametrize("model", ["consistent", "paper"])
@pytest.mark.parametrize("robot", [None, "unseen"])
def test_bit_equal_to_c5_eval(model, robot, states, run_c5, unseen_robot):
    robot_file = unseen_robot if robot else None
    c5 = c5_kernels.C5(model, robot_file)
    args = ["--model", model] + (["--robot", str(robot_file)] if robot_file else [])
    s = states(N)
    out = run_c5("eval", lines(*s), *args)
    pose, omega, velocity = s[:3]
    assert np.array_equal(c5.inverse_dynamics(*s), rows(out, "gamma"))
    assert np.array_equal(c5.inverse_kinematics(pose), rows(out, "q"))
    assert np.array_equal(c5.joint_velocities(pose, omega, velocity), rows(out, "qd"))
    assert np.array_equal(c5.inverse_jacobian(pose), rows(out, "jinv"))
    assert np.array_equal(c5.jacobian(pose), rows(out, "jacobian"))
    # One state at a time gives each row of the batch.
    for k in (0, N - 1):
        assert np.array_equal(c5.inverse_dynamics(*(a[k] for a in s)), rows(out, "gamma")[k])

    gamma = rows(out, "gamma") * 1.1 + 3.0
    forward = run_c5("forward", [{"pose": list(x), "omega": list(w), "velocity": list(v),
                                  "gamma": list(g)}
                                 for x, w, v, g in zip(pose, omega, velocity, gamma)], *args)
    omega_dot, acceleration = c5.forward_dynamics(pose, omega, velocity, gamma)
    assert np.array_equal(omega_dot, rows(forward, "omega_dot"))
    assert np.array_equal(acceleration, rows(forward, "acceleration"))


@pytest.mark.parametrize("model", ["consistent", "paper"])
def test_joint_space_bit_equal_to_c5_eval(model, states, run_c5):
    c5 = c5_kernels.C5(model)
    s = states(N, seed=11)
    q, qd, qdd = c5.inverse_kinematics(s[0]), *np.random.default_rng(3).normal(size=(2, N, 6))
    out = run_c5("eval", [{"q": list(a), "qd": list(b), "qdd": list(c)}
                          for a, b, c in zip(q, qd, qdd)], "--model", model)
    assert np.array_equal(c5.inverse_dynamics_joint(q, qd, qdd), rows(out, "gamma"))
    state = c5.joint_state(q, qd, qdd)
    for value, key in zip(state, ["pose", "omega", "velocity", "omega_dot", "acceleration"]):
        assert np.array_equal(value, rows(out, key)), key
    # The forward kinematics alone is another kernel (its own common subexpressions).
    assert np.allclose(c5.forward_kinematics(q), state[0], rtol=0, atol=1e-15)
    assert np.allclose(state[0], s[0], rtol=0, atol=1e-14)


def relative(a, b):
    return np.max(np.abs(np.asarray(a) - b)) / max(np.max(np.abs(b)), 1.0)


@pytest.mark.parametrize("robot", [None, "unseen"])
def test_consistent_model_agrees_with_an_independent_implementation(robot, states,
                                                                    unseen_robot):
    robot_file = unseen_robot if robot else DEFAULT_ROBOT
    reference = Robot.load(robot_file)
    c5 = c5_kernels.C5("consistent", robot_file)
    s = states(N, seed=2026)
    gamma = c5.inverse_dynamics(*s)
    q = c5.inverse_kinematics(s[0])
    jinv = c5.inverse_jacobian(s[0])
    omega_dot, acceleration = c5.forward_dynamics(*s[:3], gamma)
    for k in range(N):
        row = [a[k] for a in s]
        model = Model(reference, *row)
        assert relative(q[k], model.q) < 1e-12
        assert relative(jinv[k], model.jinv) < 1e-12
        assert relative(gamma[k], model.gamma()) < 1e-12
        # Single states agree as well as batched ones.
        assert relative(c5.inverse_dynamics(*row), model.gamma()) < 1e-12
        expected = forward_dynamics(reference, *row[:3], gamma[k])
        assert relative(np.r_[omega_dot[k], acceleration[k]], expected) < 1e-12
        assert relative(np.r_[omega_dot[k], acceleration[k]], np.r_[row[3], row[4]]) < 1e-12
