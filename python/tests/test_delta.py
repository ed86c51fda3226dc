"""The Delta's kernels (`c5 eval`, `c5 forward`, `eval` fed `q`) against engines that share
nothing with them: Pinocchio 4.1's `constraintDynamics` on the exported MJCF (the platform on
three slides, each rod's ball closed by a constraint; exported.py knows nothing of the
mechanism), the mechanism issue's formulas written in numpy (rus_geometry.py) and the statics
by virtual work on their potential energy. Robots: docs/delta.toml and one of other numbers
(geometry, masses, gravity off the z axis, encoder offsets), on seeded states near home.
"""

from __future__ import annotations

import json
import subprocess
import tomllib

import numpy as np
import pytest

from conftest import ROOT
from rus_geometry import RusRobot
from test_export import export, toml_text, unseen
from test_rus_hexapod import (BOUND, eval_differences, offsets, pinocchio_motor_rates,
                              pinocchio_torques, relative, task_space_differences)

pin = pytest.importorskip("pinocchio")
from exported import PinocchioExport  # noqa: E402  (needs pinocchio)


@pytest.fixture(scope="module", params=["example", "unseen"])
def delta(request, c5_program, tmp_path_factory):
    """The robot file, its geometry, its export in Pinocchio and its home position."""
    file = ROOT / "docs" / "delta.toml"
    doc = tomllib.loads(file.read_text())
    if request.param == "unseen":
        doc = unseen(doc, np.random.default_rng(31))
        file = tmp_path_factory.mktemp("delta") / "unseen-delta.toml"
        file.write_text(toml_text(doc))
    out = tmp_path_factory.mktemp("delta-export")
    path = export(c5_program, ["--robot", str(file)], "mjcf", out)
    engine = PinocchioExport(path)
    return file, RusRobot(doc), engine, np.asarray(engine.home_centre, float)


def states(home, count, seed):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield (home + rng.uniform(-0.05, 0.05, 3), rng.uniform(-0.5, 0.5, 3),
               rng.uniform(-5, 5, 3))


def line(position, velocity, acceleration=None, gamma=None):
    out = dict(pose=list(position), velocity=list(velocity))
    if acceleration is not None:
        out["acceleration"] = list(acceleration)
    if gamma is not None:
        out["gamma"] = list(gamma)
    return out


def test_eval_agrees_with_pinocchio_and_the_issues_formula(delta, run_c5):
    file, geometry, engine, home = delta
    samples = list(states(home, 8, 5))
    ours = run_c5("eval", [line(*s) for s in samples], "--robot", str(file))
    worst = eval_differences(engine, geometry, samples, ours)
    assert all(v < BOUND for v in worst.values()), worst


def test_forward_agrees_with_pinocchio_constraint_dynamics(delta, run_c5):
    file, _, engine, home = delta
    rng = np.random.default_rng(8)
    samples = [(p, v, rng.uniform(-5, 5, 3)) for p, v, _ in states(home, 10, 6)]
    ours = run_c5("forward", [line(p, v, gamma=g) for p, v, g in samples], "--robot", str(file))
    worst = 0.0
    for (position, velocity, gamma), mine in zip(samples, ours):
        theirs = engine.forward(position, velocity, gamma)
        worst = max(worst, relative(mine["acceleration"], theirs))
    print(f"forward dynamics against Pinocchio: {worst:.1e} relative")
    assert worst < BOUND


def test_the_holding_torques_are_the_statics_by_virtual_work(delta, run_c5):
    """At rest, `Γ = (∂θ/∂C)⁻ᵀ ∂U/∂C` with `U` every body's potential energy from the file."""
    file, geometry, _, home = delta
    positions = [p for p, _, _ in states(home, 5, 4)]
    ours = run_c5("eval", [line(p, np.zeros(3), np.zeros(3)) for p in positions],
                  "--robot", str(file))
    worst = max(relative(mine["gamma"], geometry.holding_torques(p))
                for p, mine in zip(positions, ours))
    print(f"statics against virtual work: {worst:.1e} relative")
    # The central differences (h = 1e-6) of the potential bound what can be seen.
    assert worst < 1e-7


def test_the_pose_from_q_has_those_arm_angles(delta, run_c5):
    file, geometry, _, home = delta
    positions = [s[0] for s in states(home, 8, 9)]
    q = [geometry.angles(p) + offsets(geometry) for p in positions]
    ours = run_c5("eval", [dict(q=list(x)) for x in q], "--robot", str(file))
    worst_q = worst_pose = 0.0
    for position, angles, mine in zip(positions, q, ours):
        found = np.asarray(mine["pose"])
        worst_q = max(worst_q, np.max(np.abs(geometry.angles(found) + offsets(geometry)
                                             - angles)))
        worst_pose = max(worst_pose, np.max(np.abs(found - position)))
    print(f"pose from q: arm angles within {worst_q:.1e} rad, position within {worst_pose:.1e}")
    assert worst_q < 1e-12
    assert worst_pose < 1e-12


def test_the_motors_motion_gives_back_the_platforms(delta, run_c5):
    """`eval` fed `q`, `qd`, `qdd` of a state gives that state, and its torques."""
    file, _, _, home = delta
    samples = list(states(home, 6, 10))
    forward = run_c5("eval", [line(*s) for s in samples], "--robot", str(file))
    back = run_c5("eval", [dict(q=m["q"], qd=m["qd"], qdd=m["qdd"]) for m in forward],
                  "--robot", str(file))
    for (position, velocity, accel), there, here in zip(samples, forward, back):
        assert relative(here["pose"], position) < 1e-12
        assert relative(here["velocity"], velocity) < 1e-10
        assert relative(here["acceleration"], accel) < 1e-9
        assert relative(here["gamma"], there["gamma"]) < 1e-9


def test_the_torques_close_the_power_balance_with_pinocchios_energies(delta, run_c5):
    """`Γ·q̇ = d/dt (T + U)` along a trajectory, `T` and `U` Pinocchio's, of every body."""
    file, _, engine, home = delta
    waves = [(0.04, 1.3, 0.0), (-0.03, 0.9, 0.4), (0.05, 1.7, 1.0)]

    def motion(t):
        x = home + np.array([a * np.sin(f * t + p) for a, f, p in waves])
        xd = np.array([a * f * np.cos(f * t + p) for a, f, p in waves])
        xdd = np.array([-a * f * f * np.sin(f * t + p) for a, f, p in waves])
        return x, xd, xdd

    def energy(t):
        x, xd, _ = motion(t)
        q, v, _ = engine.state(x, xd)
        data = engine.model.createData()
        return (pin.computeKineticEnergy(engine.model, data, q, v)
                + pin.computePotentialEnergy(engine.model, data, q))

    times = np.linspace(0.0, 3.0, 12)
    ours = run_c5("eval", [line(*motion(t)) for t in times], "--robot", str(file))
    worst = 0.0
    for t, mine in zip(times, ours):
        power = np.dot(mine["gamma"], mine["qd"])
        h = 1e-4
        rate = (energy(t + h) - energy(t - h)) / (2 * h)
        scale = max(np.sum(np.abs(np.multiply(mine["gamma"], mine["qd"]))), 1e-3)
        worst = max(worst, abs(power - rate) / scale)
    print(f"power balance against Pinocchio's energies: {worst:.1e}")
    # The central differences of the energy (h = 1e-4) bound what can be seen.
    assert worst < 1e-6


def test_bad_lines_are_refused_naming_the_term(delta, c5_program):
    """A platform beyond an arm's reach, a six-element pose and a non-finite one: each line
    refused by name, the others served."""
    file, _, _, home = delta
    far = home + np.array([0.0, 0.0, -1.5])
    rest = np.zeros(3)
    text = "".join(json.dumps(x) + "\n" for x in [
        line(far, rest, rest), line(home, rest, rest), dict(pose=[0, 0, 0, 0, 0, 0])])
    text += '{"pose": [0, 0, 1e999]}\n'
    done = subprocess.run([str(c5_program), "eval", "--robot", str(file)], input=text,
                          text=True, capture_output=True)
    out = [json.loads(x) for x in done.stdout.splitlines()]
    assert "beyond the reach of arm" in out[0]["error"], out[0]
    assert "gamma" in out[1]
    assert "3 numbers" in out[2]["error"], out[2]
    assert "error" in out[3]
    assert done.returncode != 0


def test_the_python_robot_serves_the_delta_as_pinocchio_moves_it(delta):
    """`c5_kernels.Robot` on a Delta file: batches of three columns through the one runtime
    interface, held to Pinocchio and the issue's formula as `eval`'s lines are; the forward
    dynamics and kinematics undoing the inverse ones; the joint-space forces the task-space
    ones; what needs six freedoms refused."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, geometry, engine, home = delta
    robot = c5_kernels.Robot(robot=str(file))
    assert (robot.mechanism, robot.dimension, robot.pose_names) == ("delta", 3, ["xc", "yc", "zc"])
    samples = list(states(home, 8, 5))
    x, v, a = (np.array([s[j] for s in samples]) for j in range(3))
    gamma = robot.inverse_dynamics(x, velocity=v, acceleration=a)
    assert gamma.shape == (8, 3)
    lines = [dict(q=q, qd=qd, qdd=qdd, gamma=g, jinv=ji, jacobian=j) for q, qd, qdd, g, ji, j in zip(
        robot.inverse_kinematics(x), robot.joint_velocities(x, velocity=v),
        robot.joint_accelerations(x, velocity=v, acceleration=a), gamma,
        robot.inverse_jacobian(x), robot.jacobian(x))]
    worst = eval_differences(engine, geometry, samples, lines)
    assert all(value < BOUND for value in worst.values()), worst
    back = robot.forward_dynamics(x, velocity=v, gamma=gamma)
    assert relative(back, a) < 1e-12
    position, velocity, acceleration = robot.joint_state(
        robot.inverse_kinematics(x), robot.joint_velocities(x, velocity=v),
        robot.joint_accelerations(x, velocity=v, acceleration=a))
    assert relative(position, x) < 1e-13
    assert relative(velocity, v) < 1e-12
    assert relative(acceleration, a) < 1e-10
    assert relative(robot.forward_kinematics(robot.inverse_kinematics(home)), home) < 1e-14
    with pytest.raises(ValueError, match="no `omega`"):
        robot.inverse_dynamics(home, omega=np.zeros(3))
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        robot.inverse_dynamics(np.zeros(6))
    # The joint-space forces from the motors' motion are the task-space ones, and at rest the
    # bias is the holding torque.
    q, qd, qdd = (robot.inverse_kinematics(x), robot.joint_velocities(x, velocity=v),
                  robot.joint_accelerations(x, velocity=v, acceleration=a))
    assert robot.inverse_dynamics_joint(q, qd, qdd).shape == (8, 3)
    assert relative(robot.inverse_dynamics_joint(q, qd, qdd), gamma) < 1e-10
    rest = np.zeros(3)
    holding = robot.inverse_dynamics(home, velocity=rest, acceleration=rest)
    assert relative(robot.joint_bias(robot.inverse_kinematics(home)), holding) < 1e-12
    far = home + [0.0, 0.0, -1.5]
    values, bad = robot.inverse_dynamics(np.array([home, far]), errors="nan")
    assert list(bad) == [False, True] and np.all(np.isnan(values[1]))
    # The derivatives in the platform's dimension: each Jacobian against central differences
    # of the inverse and forward dynamics (other kernels), and ∂Γ/∂a_C the inverse of ∂a_C/∂Γ.
    g, d_pose, d_twist, d_accel = robot.inverse_dynamics_derivatives(x, velocity=v, acceleration=a)
    assert (g.shape, d_pose.shape) == ((8, 3), (8, 3, 3))
    assert relative(g, gamma) < 1e-12

    def central(f, at, h):
        columns = [(f(at + h * e) - f(at - h * e)) / (2 * h) for e in np.eye(3)]
        return np.stack(columns, axis=-1)

    for k in range(len(samples)):
        by = {
            "pose": central(lambda p: robot.inverse_dynamics(p, velocity=v[k], acceleration=a[k]), x[k], 1e-6),
            "twist": central(lambda w: robot.inverse_dynamics(x[k], velocity=w, acceleration=a[k]), v[k], 1e-5),
            "accel": central(lambda b: robot.inverse_dynamics(x[k], velocity=v[k], acceleration=b), a[k], 1e-4),
        }
        for exact, numeric in [(d_pose[k], by["pose"]), (d_twist[k], by["twist"]), (d_accel[k], by["accel"])]:
            assert np.abs(exact - numeric).max() < 1e-6 * np.abs(exact).max()
    acc, da_pose, da_twist, da_gamma = robot.forward_dynamics_derivatives(x, velocity=v, gamma=gamma)
    assert relative(acc, a) < 1e-9
    assert np.abs(da_gamma @ d_accel - np.eye(3)).max() < 1e-9
    numeric = central(lambda p: robot.forward_dynamics(p, velocity=v[0], gamma=gamma[0]), x[0], 1e-6)
    assert np.abs(da_pose[0] - numeric).max() < 1e-6 * np.abs(da_pose[0]).max()


def test_the_task_space_terms_and_joint_inertia_are_pinocchios(delta):
    """`M_x`, `h` and `M_q` of Python's `Robot` (3×3, the Delta's) against Pinocchio's
    constraint dynamics; `h` refuses an angular velocity the platform cannot have."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, _, engine, home = delta
    robot = c5_kernels.Robot(robot=str(file))
    samples = [(position, velocity) for position, velocity, _ in states(home, 6, 43)]
    worst = task_space_differences(robot, engine, samples)
    print(f"task space and joint inertia against Pinocchio: {worst}")
    assert all(value < BOUND for value in worst.values()), worst
    assert robot.task_inertia(np.array([home, home])).shape == (2, 3, 3)
    with pytest.raises(ValueError, match="no `omega`"):
        robot.task_bias(home, omega=np.zeros(3))


def test_the_regressor_carries_pinocchios_torques_and_identify_finds_them(delta):
    """`Y π` (Python's `Robot`, the file's masses and a friction) is Pinocchio's torques with
    that friction on its motor rates, in the Delta's three coordinates; `identify` on forces
    of the base regressor gives back the base parameters."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, _, engine, home = delta
    robot = c5_kernels.Robot(robot=str(file))
    viscous, coulomb = np.array([0.02, 0.03, 0.025]), np.array([0.1, 0.12, 0.08])
    pi = robot.standard_values(viscous, coulomb)
    assert len(pi) == len(robot.standard_parameters) == 34
    worst = 0.0
    for position, velocity, accel in states(home, 12, 33):
        y = robot.regressor(position, velocity=velocity, acceleration=accel)
        assert y.shape == (3, 34)
        qd = pinocchio_motor_rates(engine, position, velocity)
        want = (pinocchio_torques(engine, position, velocity, accel) + viscous * qd
                + coulomb * np.sign(qd))
        worst = max(worst, relative(y @ pi, want))
    print(f"Y π against Pinocchio: {worst:.1e} relative")
    assert worst < BOUND, worst
    position, velocity, accel = (np.array(c) for c in zip(*states(home, 300, 34)))
    beta = robot.base_values(viscous, coulomb)
    gamma = robot.base_regressor(position, velocity=velocity, acceleration=accel) @ beta
    assert np.allclose(robot.regressor(position, velocity=velocity, acceleration=accel) @ pi,
                       gamma, rtol=1e-10, atol=1e-9)
    estimate = robot.identify(position, velocity=velocity, acceleration=accel, gamma=gamma)
    assert estimate["model"] == "delta" and estimate["names"] == robot.base_parameters
    assert len(estimate["residual_rms"]) == 3
    assert np.allclose(estimate["values"], beta, rtol=1e-7, atol=1e-8)
    with pytest.raises(ValueError, match="one coefficient per actuator"):
        robot.standard_values(np.zeros(6))


def test_simulate_runs_section_9s_move_on_the_delta_with_pinocchios_torques(delta, c5_program,
                                                                          tmp_path):
    """`c5 simulate --robot delta.toml`: Section 9's move of the centre from home, in the
    Delta's coordinates (`t,xc..az,q1..q3,...,gamma1..gamma3`), its torques those under which
    Pinocchio's platform takes each sample's acceleration."""
    file, _, engine, home = delta
    subprocess.run([str(c5_program), "simulate", "--robot", str(file), "--rate", "50",
                    "--out", str(tmp_path)], check=True, capture_output=True)
    header = (tmp_path / "section9.csv").read_text().splitlines()[0].split(",")
    assert header[:10] == ["t", "xc", "yc", "zc", "vx", "vy", "vz", "ax", "ay", "az"]
    assert header[-3:] == ["gamma1", "gamma2", "gamma3"] and len(header) == 22
    rows = np.loadtxt(tmp_path / "section9.csv", delimiter=",", skiprows=1)
    assert len(rows) == 51
    assert np.max(np.abs(rows[0, 1:4] - home)) < 1e-12
    assert np.max(np.abs(rows[-1, 1:4] - home - [0.04, 0.03, 0.05])) < 1e-12
    worst = max(relative(row[19:22], pinocchio_torques(engine, row[1:4], row[4:7], row[7:10]))
                for row in rows[::5])
    print(f"simulate's torques against Pinocchio: {worst:.1e} relative")
    assert worst < BOUND


def test_a_plan_is_the_motion_pinocchios_delta_makes_under_its_forces(delta):
    """`Robot.plan` on a Delta, in its three coordinates: a short move of the centre from home
    ends at the goal at rest, and at every tenth sample Pinocchio's constraint dynamics under
    the plan's forces gives the plan's acceleration (an engine that shares nothing with the
    planner's derivative kernels). Poses of another dimension are refused by name."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, _, engine, home = delta
    robot = c5_kernels.Robot(robot=str(file))
    goal = home + np.array([0.02, -0.015, 0.025])
    plan = robot.plan(home, goal, 0.3, 60)
    assert plan["pose"].shape == (61, 3) and plan["gamma"].shape == (60, 3)
    assert set(plan) >= {"times", "pose", "velocity", "acceleration", "gamma", "costs"}
    assert plan["goal_error"] <= 1e-8
    assert np.max(np.abs(plan["pose"][-1] - goal)) <= 1e-8
    assert np.max(np.abs(plan["velocity"][-1])) <= 1e-8
    for round_costs in plan["costs"]:
        assert all(b < a for a, b in zip(round_costs, round_costs[1:]))
    worst = 0.0
    for k in range(0, 60, 10):
        theirs = engine.forward(plan["pose"][k], plan["velocity"][k], plan["gamma"][k])
        worst = max(worst, relative(plan["acceleration"][k], theirs))
    assert worst <= BOUND, worst
    with pytest.raises(ValueError, match="coordinates"):
        robot.plan(np.zeros(6), np.zeros(6), 0.3, 60)


def test_a_slow_plan_keeps_the_clearance_asked_and_is_still_pinocchios_motion(delta):
    """Section 9's move in a second: the least effort lies where a crank and its rods align,
    so the plan runs along the clearance asked, not below it, and Pinocchio's constraint
    dynamics under its forces still gives its accelerations."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, geometry, engine, home = delta
    robot = c5_kernels.Robot(robot=str(file))
    goal = home + np.array([0.04, 0.03, 0.05])
    plan = robot.plan(home, goal, 1.0, 200, least_clearance=0.02)
    assert plan["goal_error"] <= 1e-8
    assert plan["least_clearance"] >= 0.02 - 1e-6
    # The reach, one of the clearance's terms, from the file's geometry (not the Rust code's).
    least_reach = min(geometry.reach_terms(pose).min() for pose in plan["pose"])
    assert least_reach >= 0.02 - 1e-6, least_reach
    worst = max(relative(plan["acceleration"][k],
                         engine.forward(plan["pose"][k], plan["velocity"][k], plan["gamma"][k]))
                for k in range(0, 200, 20))
    assert worst <= BOUND, worst
    with pytest.raises(ValueError, match="least clearance"):
        robot.plan(home, goal, 1.0, 200, least_clearance=10.0)
