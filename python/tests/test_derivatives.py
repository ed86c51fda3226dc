"""The dynamics' Jacobians and the limits' margins: to the bit what `c5 eval --derivatives`,
`c5 forward --derivatives` and `c5 eval`'s `limits` give, and checked against the physics they
stand for (central differences of the module's own primal kernels, `dΓ/dA · dA/dΓ = I`, the
strokes against the inverse kinematics)."""

from __future__ import annotations

import numpy as np
import pytest

import c5_kernels
from conftest import ROOT

N = 9
LIMITS_ROBOT = ROOT / "docs" / "limits-robot.toml"


def rows(out, key):
    return np.array([line[key] for line in out])


def central(f, x, h):
    """`∂f/∂x` at `x` (a vector) by central differences: column `j` for `x[j]`."""
    cols = []
    for j in range(x.size):
        e = np.zeros_like(x)
        e[j] = h
        cols.append((f(x + e) - f(x - e)) / (2 * h))
    return np.stack(cols, axis=-1)


def relative(a, b):
    return np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1.0)


@pytest.mark.parametrize("model", ["consistent", "paper"])
def test_bit_equal_to_c5_eval_and_forward(model, states, run_c5):
    c5 = c5_kernels.C5(model)
    s = states(N, seed=5)
    pose, omega, velocity, omega_dot, acceleration = s
    out = run_c5("eval", [{"pose": list(x), "omega": list(w), "velocity": list(v),
                           "omega_dot": list(wd), "acceleration": list(a)}
                          for x, w, v, wd, a in zip(*s)], "--model", model, "--derivatives")
    gamma, d_pose, d_twist, d_accel = c5.inverse_dynamics_derivatives(*s)
    assert gamma.shape == (N, 6) and d_pose.shape == (N, 6, 6)
    # `Γ` comes from the derivative kernel, not `eval`'s inverse dynamics: the same to rounding.
    assert relative(gamma, rows(out, "gamma")) < 1e-14
    assert np.array_equal(d_pose, rows(out, "d_gamma_d_pose"))
    assert np.array_equal(d_twist, rows(out, "d_gamma_d_twist"))
    assert np.array_equal(d_accel, rows(out, "d_gamma_d_acceleration"))

    forces = gamma * 0.9 - 2.0
    fwd = run_c5("forward", [{"pose": list(x), "omega": list(w), "velocity": list(v),
                              "gamma": list(g)}
                             for x, w, v, g in zip(pose, omega, velocity, forces)],
                 "--model", model, "--derivatives")
    wd, a, da_pose, da_twist, da_gamma = c5.forward_dynamics_derivatives(
        pose, omega, velocity, forces)
    assert np.array_equal(wd, rows(fwd, "omega_dot"))
    assert np.array_equal(a, rows(fwd, "acceleration"))
    assert np.array_equal(da_pose, rows(fwd, "d_acceleration_d_pose"))
    assert np.array_equal(da_twist, rows(fwd, "d_acceleration_d_twist"))
    assert np.array_equal(da_gamma, rows(fwd, "d_acceleration_d_gamma"))


@pytest.mark.parametrize("model", ["consistent", "paper"])
def test_jacobians_are_the_primal_kernels_derivatives(model, states):
    c5 = c5_kernels.C5(model)
    s = states(4, seed=17)
    h = 1e-6
    for k in range(4):
        x, w, v, wd, a = (arg[k] for arg in s)
        _, d_pose, d_twist, d_accel = c5.inverse_dynamics_derivatives(x, w, v, wd, a)
        fd_pose = central(lambda p: c5.inverse_dynamics(p, w, v, wd, a), x, h)
        fd_twist = central(lambda t: c5.inverse_dynamics(x, t[:3], t[3:], wd, a),
                           np.concatenate([w, v]), h)
        fd_accel = central(lambda u: c5.inverse_dynamics(x, w, v, u[:3], u[3:]),
                           np.concatenate([wd, a]), h)
        assert relative(d_pose, fd_pose) < 1e-6
        assert relative(d_twist, fd_twist) < 1e-6
        assert relative(d_accel, fd_accel) < 1e-6

        forces = c5.inverse_dynamics(x, w, v, wd, a)
        wd1, a1, da_pose, da_twist, da_gamma = c5.forward_dynamics_derivatives(x, w, v, forces)
        # The forward dynamics undoes the inverse at the same state ...
        assert relative(np.concatenate([wd1, a1]), np.concatenate([wd, a])) < 1e-9
        # ... and its Jacobian in the forces is the inverse of the inverse dynamics' in the
        # accelerations.
        assert relative(d_accel @ da_gamma, np.eye(6)) < 1e-9

        def forward(p=x, t=np.concatenate([w, v]), g=forces):
            return np.concatenate(c5.forward_dynamics(p, t[:3], t[3:], g))

        assert relative(da_pose, central(lambda p: forward(p=p), x, h)) < 1e-6
        assert relative(da_twist, central(lambda t: forward(t=t), np.concatenate([w, v]), h)) \
            < 1e-6
        assert relative(da_gamma, central(lambda g: forward(g=g), forces, h)) < 1e-6


@pytest.mark.parametrize("model", ["consistent", "paper"])
def test_joint_space_jacobians(model, states):
    c5 = c5_kernels.C5(model)
    rng = np.random.default_rng(8)
    q = c5.inverse_kinematics(states(3, seed=23)[0])
    qd, qdd = rng.normal(scale=0.2, size=(2, 3, 6))
    gamma, d_q, d_qd, d_qdd = c5.inverse_dynamics_joint_derivatives(q, qd, qdd)
    assert relative(gamma, c5.inverse_dynamics_joint(q, qd, qdd)) < 1e-14
    assert relative(d_qdd, c5.joint_inertia(q)) < 1e-12
    for k in range(3):
        fd = central(lambda u: c5.inverse_dynamics_joint(u, qd[k], qdd[k]), q[k], 1e-7)
        assert relative(d_q[k], fd) < 1e-6
        fd = central(lambda u: c5.inverse_dynamics_joint(q[k], u, qdd[k]), qd[k], 1e-6)
        assert relative(d_qd[k], fd) < 1e-6


def test_a_singular_row_is_refused_and_the_others_kept(states):
    c5 = c5_kernels.C5()
    pose = states(3)[0]
    pose[1, 1] = np.pi / 2  # beta = 90 degrees: r11 = r33 = 0
    with pytest.raises(c5_kernels.SingularPoseError, match="row 1"):
        c5.inverse_dynamics_derivatives(pose)
    gamma, d_pose, _, _, bad = c5.inverse_dynamics_derivatives(pose, errors="nan")
    assert list(bad) == [False, True, False]
    assert np.isnan(d_pose[1]).all() and np.isfinite(d_pose[[0, 2]]).all()
    assert relative(gamma[0], c5.inverse_dynamics(pose[0])) < 1e-14


def test_limit_margins_match_c5_eval_and_the_strokes(states, run_c5):
    c5 = c5_kernels.C5(robot=LIMITS_ROBOT)
    assert c5.limits["stroke"] == [[-0.15, 0.15]] * 6 and c5.limits["speed"] == 0.5
    pose = states(N, seed=31)[0]
    pose[:, 3:] *= 2.5  # some poses leave the strokes
    stroke, plate, tilt = c5.limit_margins(pose)
    assert stroke.shape == (N, 6) and plate.shape == (N, 6, 2) and tilt.shape == (N, 6)
    q = c5.inverse_kinematics(pose)
    # `q` of the margins' kernel and of the inverse kinematics' own: the same to rounding.
    assert np.max(np.abs(stroke - np.minimum(q + 0.15, 0.15 - q))) < 1e-16
    assert (stroke < 0).any() and (stroke > 0).any()
    # At rest the forces and speeds are far from their limits, so the smallest margin `eval`
    # reports is a pose's.
    out = run_c5("eval", [{"pose": list(x)} for x in pose], "--robot", str(LIMITS_ROBOT))
    smallest = np.min(np.concatenate([stroke, plate.reshape(N, 12), tilt], axis=1), axis=1)
    assert np.array_equal(smallest, [line["limits"]["margin"] for line in out])

    free = c5_kernels.C5()
    assert all(v is None for v in free.limits.values())
    assert all(np.isinf(m).all() for m in free.limit_margins(pose))
