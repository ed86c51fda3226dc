"""Shapes single and batched, inputs as numpy converts them, errors that name what is wrong
and lose nothing else, threads, the regressors and identification."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import c5_kernels

TURNED = np.array([np.radians(10), np.radians(15), np.radians(20), 0.0, 0.0, 0.0])
# r11 = cos(beta) cos(gamma) = 0: eq 16 divides by it.
SINGULAR = np.array([0.0, np.pi / 2, 0.0, 0.0, 0.0, 0.0])


@pytest.fixture(scope="module")
def c5():
    return c5_kernels.C5()


def test_shapes_single_and_batched(c5, states):
    s = states(5)
    pose = s[0]
    assert c5.inverse_kinematics(pose[0]).shape == (6,)
    assert c5.inverse_kinematics(pose).shape == (5, 6)
    assert c5.inverse_jacobian(pose[0]).shape == (6, 6)
    assert c5.jacobian(pose).shape == (5, 6, 6)
    assert c5.task_inertia(pose).shape == (5, 6, 6)
    assert c5.inverse_dynamics(*s).shape == (5, 6)
    omega_dot, acceleration = c5.forward_dynamics(pose, gamma=np.zeros((5, 6)))
    assert omega_dot.shape == acceleration.shape == (5, 3)
    q = c5.inverse_kinematics(pose)
    assert c5.forward_kinematics(q).shape == (5, 6)
    assert [a.shape for a in c5.joint_state(q[0])] == [(6,), (3,), (3,), (3,), (3,)]
    assert c5.joint_inertia(q).shape == (5, 6, 6)
    assert c5.regressor(*s).shape == (5, 6, 142)
    assert c5.base_regressor(*s).shape == (5, 6, len(c5.base_parameters))
    assert c5.inverse_dynamics(np.zeros((0, 6))).shape == (0, 6)


def test_identities(c5, states):
    s = states(9)
    pose = s[0]
    eye = np.broadcast_to(np.eye(6), (9, 6, 6))
    assert np.allclose(c5.jacobian(pose) @ c5.inverse_jacobian(pose), eye, atol=1e-12)
    q = c5.inverse_kinematics(pose)
    assert np.allclose(c5.forward_kinematics(q), pose, atol=1e-13)
    # The forces undo the forward dynamics, and Y pi is the inverse dynamics.
    gamma = c5.inverse_dynamics(*s)
    omega_dot, acceleration = c5.forward_dynamics(*s[:3], gamma)
    assert np.allclose(omega_dot, s[3], atol=1e-10) and np.allclose(acceleration, s[4], atol=1e-10)
    assert np.allclose(c5.regressor(*s) @ c5.standard_values(), gamma, atol=1e-10)
    assert np.allclose(c5.base_regressor(*s) @ c5.base_values(), gamma, atol=1e-10)
    # Joint space: the same forces from what the encoders give.
    qd = c5.joint_velocities(*s[:3])
    state = c5.joint_state(q, qd, np.zeros((9, 6)))
    assert np.allclose(state[1], s[1], atol=1e-12) and np.allclose(state[2], s[2], atol=1e-12)


def test_inputs_numpy_converts(c5, states):
    s = states(8)
    expected = c5.inverse_dynamics(*s)
    # Lists, float32, Fortran order and strided views give what the float64 arrays give.
    assert np.array_equal(c5.inverse_dynamics(*(a.tolist() for a in s)), expected)
    assert np.array_equal(c5.inverse_dynamics(*(np.asfortranarray(a) for a in s)), expected)
    wide = np.hstack([s[0], s[0]])
    assert np.array_equal(c5.inverse_dynamics(wide[:, :6], *s[1:]), expected)
    assert np.array_equal(c5.inverse_dynamics(s[0][::2]), c5.inverse_dynamics(s[0])[::2])
    as32 = c5.inverse_kinematics(s[0].astype(np.float32))
    assert np.array_equal(as32, c5.inverse_kinematics(s[0].astype(np.float32).astype(np.float64)))
    # Omitted motion is zero.
    zeros = np.zeros((8, 3))
    assert np.array_equal(c5.inverse_dynamics(s[0]), c5.inverse_dynamics(s[0], zeros, zeros,
                                                                         zeros, zeros))


@pytest.mark.parametrize("args, message", [
    ((np.zeros(5),), r"`pose` must have shape \(6,\) or \(N, 6\), got \[5\]"),
    ((np.zeros((2, 7)),), r"`pose` must have shape"),
    ((np.zeros((3, 6)), np.zeros((2, 3))), r"`omega` has 2 row\(s\) as a batch, the other "
                                           r"arguments 3 as a batch"),
    ((np.zeros(6), np.zeros((1, 3))), r"`omega` has 1 row\(s\) as a batch, the other "
                                      r"arguments 1 as a vector"),
])
def test_bad_shapes_raise_value_error(c5, args, message):
    with pytest.raises(ValueError, match=message):
        c5.inverse_dynamics(*args)


def test_bad_rows_raise_naming_the_row_or_come_back_as_nan(c5, states):
    s = states(10)
    pose = s[0].copy()
    pose[6] = SINGULAR
    omega = s[1].copy()
    omega[2, 1] = np.nan
    with pytest.raises(c5_kernels.SingularPoseError, match=r"r11 .*\(row 6\)"):
        c5.inverse_dynamics(pose, *s[1:])
    with pytest.raises(ValueError, match=r"twist\[1\] is not a finite number \(row 2\)"):
        c5.inverse_dynamics(pose, omega, *s[2:])
    with pytest.raises(c5_kernels.SingularPoseError, match="r11"):
        c5.inverse_kinematics(SINGULAR)
    assert issubclass(c5_kernels.SingularPoseError, ValueError)

    gamma, bad = c5.inverse_dynamics(pose, omega, *s[2:], errors="nan")
    assert bad.tolist() == [k in (2, 6) for k in range(10)]
    assert np.isnan(gamma[bad]).all()
    good = c5.inverse_dynamics(*s)
    assert np.array_equal(gamma[~bad], good[~bad])
    (omega_dot, acceleration, bad) = c5.forward_dynamics(pose, gamma=np.zeros((10, 6)),
                                                         errors="nan")
    assert bad.tolist() == [k == 6 for k in range(10)] and np.isnan(omega_dot[6]).all()
    with pytest.raises(ValueError, match='errors must be "raise" or "nan"'):
        c5.inverse_dynamics(pose, errors="ignore")


def test_forward_singularity_is_refused(c5):
    # Q2 - Q1 = 2L r31/r11 and its pairs: ratios a = b = c = -1 give 1 + abc = 0.
    l = 0.2
    q = np.array([0.0, -2 * l, 0.0, -2 * l, 0.0, -2 * l])
    with pytest.raises(c5_kernels.SingularPoseError, match="forward"):
        c5.forward_kinematics(q)
    pose, bad = c5.forward_kinematics(np.vstack([q, np.zeros(6)]), errors="nan")
    assert bad.tolist() == [True, False] and np.array_equal(pose[1], np.zeros(6))


def test_two_batches_at_once(c5, states):
    """The kernels run without the GIL: two threads each run a batch, and each gets what it
    would get alone."""
    batches = [states(20_000, seed=seed) for seed in (1, 2)]
    alone = [c5.inverse_dynamics(*b) for b in batches]
    results = [None, None]
    start = threading.Barrier(2)

    def work(k):
        start.wait()
        results[k] = c5.inverse_dynamics(*batches[k])

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(r, a) for r, a in zip(results, alone))


def test_models_and_robots(tmp_path):
    paper = c5_kernels.C5("paper")
    assert paper.model == "paper" and "paper" in repr(paper)
    # At rest in a turned pose the chapter's model misses the load on the horizontal legs.
    assert abs(c5_kernels.C5().inverse_dynamics(TURNED)[0]) > 5
    assert abs(paper.inverse_dynamics(TURNED)[0]) < 1e-9
    with pytest.raises(ValueError, match="model"):
        c5_kernels.C5("newton")
    with pytest.raises(ValueError, match="missing.toml"):
        c5_kernels.C5(robot=tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("half_spacing = -1.0\n")
    with pytest.raises(ValueError, match="bad.toml"):
        c5_kernels.C5(robot=bad)


def test_identify_recovers_the_base_parameters(c5, states):
    s = states(400, seed=5)
    viscous, coulomb = [3.0, 2.5, 4.0, 3.5, 2.0, 2.2], [1.0, 0.8, 1.2, 0.9, 1.1, 0.7]
    beta = c5.base_values(viscous, coulomb)
    gamma = c5.base_regressor(*s) @ beta
    estimate = c5.identify(*s, gamma)
    assert estimate["names"] == c5.base_parameters and estimate["samples"] == 400
    assert np.allclose(estimate["values"], beta, rtol=1e-7, atol=1e-8)
    with pytest.raises(ValueError, match="row 1"):
        pose = s[0].copy()
        pose[1] = SINGULAR
        c5.identify(pose, *s[1:], gamma)
