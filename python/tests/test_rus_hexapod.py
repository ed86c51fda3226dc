"""The rotary hexapod's kernels (`c5 eval`, `c5 forward`, `eval` fed `q`) against engines that
share nothing with them: Pinocchio 4.1's `constraintDynamics` on the exported MJCF (the loops
closed by its welds; exported.py knows nothing of the mechanism) and the mechanism issue's
formulas written in numpy (rus_geometry.py). Robots: docs/rus-hexapod.toml and one of other
numbers (geometry, masses, gravity off the z axis, encoder offsets), on seeded states near
home.

What each side gives:
- `q`: the issue's `θ = atan2(e2, e1) + b acos(K/ρ)` plus the offset;
- `J⁻¹` and `q̇`: the motors' rates Pinocchio's welds allow for each unit twist;
- `Γ`: the torques under which Pinocchio's platform takes the state's acceleration (its
  acceleration is affine in them: seven forward solves);
- `q̈`: the motors' accelerations of Pinocchio's forward solve under our `Γ`;
- the forward dynamics: Pinocchio's platform acceleration under the same torques;
- the power balance: `Γ·q̇ = d/dt (T + U)` with `T` and `U` Pinocchio's energies of the
  whole tree, along a moving trajectory;
- identification: the regressor times the standard parameters is Pinocchio's torques plus
  friction on its motor rates.
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

pin = pytest.importorskip("pinocchio")
from exported import PinocchioExport  # noqa: E402  (needs pinocchio)

# The issue's bound for agreement with an independent engine, relative.
BOUND = 1e-9


@pytest.fixture(scope="module", params=["example", "unseen"])
def hexapod(request, c5_program, tmp_path_factory):
    """The robot file, its geometry, its export in Pinocchio and its home pose."""
    file = ROOT / "docs" / "rus-hexapod.toml"
    doc = tomllib.loads(file.read_text())
    if request.param == "unseen":
        doc = unseen(doc, np.random.default_rng(29))
        file = tmp_path_factory.mktemp("rus") / "unseen-rus-hexapod.toml"
        file.write_text(toml_text(doc))
    out = tmp_path_factory.mktemp("rus-export")
    path = export(c5_program, ["--robot", str(file)], "mjcf", out)
    engine = PinocchioExport(path)
    home = np.concatenate([[0.0, 0.0, 0.0], engine.home_centre])
    return file, RusRobot(doc), engine, home


def states(home, count, seed):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        pose = home + np.concatenate([rng.uniform(-0.08, 0.08, 3),
                                      rng.uniform(-0.015, 0.015, 3)])
        twist = np.concatenate([rng.uniform(-1, 1, 3), rng.uniform(-0.2, 0.2, 3)])
        accel = np.concatenate([rng.uniform(-5, 5, 3), rng.uniform(-1, 1, 3)])
        yield pose, twist, accel


def line(pose, twist, accel=None, gamma=None):
    out = dict(pose=list(pose), omega=list(twist[:3]), velocity=list(twist[3:]))
    if accel is not None:
        out.update(omega_dot=list(accel[:3]), acceleration=list(accel[3:]))
    if gamma is not None:
        out["gamma"] = list(gamma)
    return out


def offsets(geometry):
    return np.array([leg.get("encoder_offset", 0.0) for leg in geometry.legs])


def relative(mine, theirs):
    mine, theirs = np.asarray(mine), np.asarray(theirs)
    return np.max(np.abs(mine - theirs)) / np.max(np.abs(theirs))


def pinocchio_motor_rates(engine, pose, twist):
    _, v, _ = engine.state(pose, twist)
    return v[engine.actuated]


def pinocchio_torques(engine, pose, twist, accel):
    """The torques under which Pinocchio's platform has the classical acceleration `accel`."""
    n = len(accel)
    base = engine.forward(pose, twist, np.zeros(n))
    columns = [engine.forward(pose, twist, np.eye(n)[k]) - base for k in range(n)]
    return np.linalg.solve(np.column_stack(columns), accel - base)


def task_space_differences(robot, engine, samples):
    """The worst relative differences of the Python `Robot`'s `M_x`, `h` and `M_q` from
    Pinocchio's constraint dynamics at `samples` (pose and twist; a Delta's position and
    velocity), and `M_x`'s asymmetry. Pinocchio's acceleration is affine in the torques,
    `V̇ = A Γ + V̇₀`, and ours is `M_x V̇ + h = J⁻ᵀ Γ`, so `M_x = J⁻ᵀ A⁻¹`, `h = -M_x V̇₀` and
    `M_q = Jᵀ M_x J = A⁻¹ J`."""
    worst = dict(m_x=0.0, h=0.0, m_q=0.0, asymmetry=0.0)
    for pose, twist in samples:
        n = len(pose)
        base = engine.forward(pose, twist, np.zeros(n))
        a = np.column_stack([engine.forward(pose, twist, np.eye(n)[k]) - base
                             for k in range(n)])
        m_x = robot.inverse_jacobian(pose).T @ np.linalg.inv(a)
        angular = {"omega": twist[:3], "velocity": twist[3:]} if n == 6 else {"velocity": twist}
        mine = robot.task_inertia(pose)
        worst["m_x"] = max(worst["m_x"], relative(mine, m_x))
        worst["asymmetry"] = max(worst["asymmetry"], relative(mine, mine.T))
        worst["h"] = max(worst["h"], relative(robot.task_bias(pose, **angular), -m_x @ base))
        q = robot.inverse_kinematics(pose)
        m_q = np.linalg.inv(a) @ robot.jacobian(pose)
        worst["m_q"] = max(worst["m_q"], relative(robot.joint_inertia(q), m_q))
    return worst


def eval_differences(engine, geometry, samples, ours):
    """The worst relative differences of `eval`'s lines `ours` at the states `samples`
    (pose, twist, acceleration; a Delta's position, velocity, acceleration) from Pinocchio's
    and the issue's formula: `q`, `jinv`, `qd`, `gamma`, `qdd`, and `J⁻¹ J - I`."""
    worst = dict(q=0.0, jinv=0.0, qd=0.0, gamma=0.0, qdd=0.0, identity=0.0)
    for (pose, twist, accel), mine in zip(samples, ours):
        assert "error" not in mine, mine
        n = len(twist)
        worst["q"] = max(worst["q"], relative(mine["q"],
                                              geometry.angles(pose) + offsets(geometry)))
        jinv = np.column_stack([pinocchio_motor_rates(engine, pose, e) for e in np.eye(n)])
        worst["jinv"] = max(worst["jinv"], relative(mine["jinv"], jinv))
        worst["qd"] = max(worst["qd"], relative(mine["qd"], jinv @ twist))
        identity = np.asarray(mine["jinv"]) @ np.asarray(mine["jacobian"])
        worst["identity"] = max(worst["identity"], np.max(np.abs(identity - np.eye(n))))
        worst["gamma"] = max(worst["gamma"], relative(
            mine["gamma"], pinocchio_torques(engine, pose, twist, accel)))
        q, v, _ = engine.state(pose, twist)
        ddq = engine_ddq(engine, q, v, mine["gamma"])
        worst["qdd"] = max(worst["qdd"], relative(mine["qdd"], ddq[engine.actuated]))
    print("eval against Pinocchio, relative: " +
          ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))
    return worst


def test_eval_agrees_with_pinocchio_and_the_issues_formula(hexapod, run_c5):
    file, geometry, engine, home = hexapod
    samples = list(states(home, 8, 5))
    ours = run_c5("eval", [line(*s) for s in samples], "--robot", str(file))
    worst = eval_differences(engine, geometry, samples, ours)
    assert all(v < BOUND for v in worst.values()), worst


def engine_ddq(engine, q, v, gamma):
    """Pinocchio's joint accelerations under the motor torques `gamma`."""
    m = engine.model
    tau = np.zeros(m.nv)
    tau[engine.actuated] = gamma
    data = m.createData()
    datas = pin.StdVec_RigidConstraintData()
    for c in engine.constraints:
        datas.append(c.createData())
    pin.initConstraintDynamics(m, data, engine.constraints, datas)
    return pin.constraintDynamics(m, data, q, v, tau, engine.constraints, datas,
                                  pin.ProximalSettings(1e-14, 1e-8, 100))


def test_forward_agrees_with_pinocchio_constraint_dynamics(hexapod, run_c5):
    file, _, engine, home = hexapod
    rng = np.random.default_rng(8)
    samples = [(p, t, rng.uniform(-3, 3, 6)) for p, t, _ in states(home, 10, 6)]
    ours = run_c5("forward", [line(p, t, gamma=g) for p, t, g in samples], "--robot", str(file))
    worst = 0.0
    for (pose, twist, gamma), mine in zip(samples, ours):
        theirs = engine.forward(pose, twist, gamma)
        worst = max(worst, relative(mine["omega_dot"] + mine["acceleration"], theirs))
    print(f"forward dynamics against Pinocchio: {worst:.1e} relative")
    assert worst < BOUND


def test_the_pose_from_q_has_those_crank_angles(hexapod, run_c5):
    file, geometry, _, home = hexapod
    poses = [s[0] for s in states(home, 8, 9)]
    q = [geometry.angles(p) + offsets(geometry) for p in poses]
    ours = run_c5("eval", [dict(q=list(x)) for x in q], "--robot", str(file))
    worst_q = worst_pose = 0.0
    for pose, angles, mine in zip(poses, q, ours):
        found = np.asarray(mine["pose"])
        worst_q = max(worst_q, np.max(np.abs(geometry.angles(found) + offsets(geometry)
                                             - angles)))
        worst_pose = max(worst_pose, np.max(np.abs(found - pose)))
    print(f"pose from q: crank angles within {worst_q:.1e} rad, pose within {worst_pose:.1e}")
    assert worst_q < 1e-12
    assert worst_pose < 1e-10


def test_the_torques_close_the_power_balance_with_pinocchios_energies(hexapod, run_c5):
    """`Γ·q̇ = d/dt (T + U)` along a trajectory, `T` and `U` Pinocchio's, of every body."""
    file, _, engine, home = hexapod
    waves = [(0.08, 1.3, 0.0), (-0.06, 0.9, 0.4), (0.1, 0.7, 0.0),
             (0.01, 1.1, 1.5), (0.008, 1.7, 0.0), (0.012, 0.8, 0.0)]

    def motion(t):
        x = home + np.array([a * np.sin(f * t + p) for a, f, p in waves])
        xd = np.array([a * f * np.cos(f * t + p) for a, f, p in waves])
        xdd = np.array([-a * f * f * np.sin(f * t + p) for a, f, p in waves])
        return x, xd, xdd

    def twist_of(x, xd, xdd):
        """`ω` and `ω̇` of the RPY rates (`R = Rx Ry Rz`), `v_C` and `a_C`."""
        def omega(x, xd):
            a, b, _ = x[:3]
            ex = np.array([1.0, 0, 0])
            ey = np.array([0, np.cos(a), np.sin(a)])
            ez = np.array([np.sin(b), -np.sin(a) * np.cos(b), np.cos(a) * np.cos(b)])
            return xd[0] * ex + xd[1] * ey + xd[2] * ez
        h = 1e-6
        w = omega(x, xd)
        wd = (omega(x + h * xd, xd + h * xdd) - omega(x - h * xd, xd - h * xdd)) / (2 * h)
        return np.concatenate([w, xd[3:]]), np.concatenate([wd, xdd[3:]])

    def energy(t):
        x, xd, xdd = motion(t)
        twist, _ = twist_of(x, xd, xdd)
        q, v, _ = engine.state(x, twist)
        data = engine.model.createData()
        return (pin.computeKineticEnergy(engine.model, data, q, v)
                + pin.computePotentialEnergy(engine.model, data, q))

    times = np.linspace(0.0, 3.0, 12)
    lines = []
    for t in times:
        x, xd, xdd = motion(t)
        twist, accel = twist_of(x, xd, xdd)
        lines.append(line(x, twist, accel))
    ours = run_c5("eval", lines, "--robot", str(file))
    worst = 0.0
    for t, mine in zip(times, ours):
        power = np.dot(mine["gamma"], mine["qd"])
        h = 1e-4
        rate = (energy(t + h) - energy(t - h)) / (2 * h)
        scale = max(np.sum(np.abs(np.multiply(mine["gamma"], mine["qd"]))), 1e-3)
        worst = max(worst, abs(power - rate) / scale)
    print(f"power balance against Pinocchio's energies: {worst:.1e}")
    # The central differences of the energy (h = 1e-4) and of ω̇ bound what can be seen.
    assert worst < 1e-6


def test_bad_states_are_refused_naming_the_term(hexapod, c5_program):
    """A ball beyond its crank's reach, a crank aligned with its rod at the reach's edge, and
    a non-finite pose: each line refused by name, the others served."""
    file, geometry, _, home = hexapod
    lifted = home + np.array([0, 0, 0, 0, 0, 0.3])
    # The platform raised until leg 1's K/ρ reaches 1: its crank and rod align.
    low, high = home[5], lifted[5]
    for _ in range(200):
        mid = 0.5 * (low + high)
        x = home.copy()
        x[5] = mid
        with np.errstate(invalid="ignore"):
            ok = not np.isnan(geometry.angles(x)).any()
        low, high = (mid, high) if ok else (low, mid)
    # A tenth of a picometre inside: `1 - (K/ρ)²` is then about 1e-12, below the bound and
    # clear of the rounding that puts the edge itself on either side.
    edge = home.copy()
    edge[5] = low - 1e-13
    rest = np.zeros(6)
    text = "".join(json.dumps(x) + "\n" for x in [
        line(lifted, rest, rest), line(edge, rest, rest), line(home, rest, rest)])
    text += '{"pose": [0, 0, 0, 0, 0, 1e999]}\n'
    done = subprocess.run([str(c5_program), "eval", "--robot", str(file)], input=text,
                          text=True, capture_output=True)
    out = [json.loads(x) for x in done.stdout.splitlines()]
    assert "beyond its crank's reach" in out[0]["error"], out[0]
    assert "aligned" in out[1]["error"], out[1]
    assert "gamma" in out[2]
    assert "error" in out[3]
    assert done.returncode != 0


def test_python_serves_the_rotary_hexapod_as_the_program_does(hexapod, run_c5):
    """`c5_kernels.Robot` on the file: the same forces and pose from `q`, bit for bit."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, geometry, _, home = hexapod
    robot = c5_kernels.Robot(robot=str(file))
    assert robot.mechanism == "rus-hexapod" and repr(robot).startswith("Robot(")
    pose, twist, accel = next(states(home, 1, 12))
    gamma = robot.inverse_dynamics(pose, twist[:3], twist[3:], accel[:3], accel[3:])
    ours = run_c5("eval", [line(pose, twist, accel)], "--robot", str(file))[0]
    assert list(gamma) == ours["gamma"]
    q = geometry.angles(pose) + offsets(geometry)
    found = robot.forward_kinematics(q)
    assert np.max(np.abs(found - pose)) < 1e-10
    # What needs derivative kernels, not generated for this mechanism, is refused by name.
    for call in (lambda: robot.forward_dynamics_derivatives(pose, twist[:3], twist[3:], gamma),
                 lambda: robot.plan(home, home + 0.01, 0.3, 60)):
        with pytest.raises(ValueError, match="rus-hexapod.*derivative kernels are not generated"):
            call()


def test_the_task_space_terms_and_joint_inertia_are_pinocchios(hexapod):
    """`M_x`, `h` and `M_q` of Python's `Robot` against Pinocchio's constraint dynamics."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, _, engine, home = hexapod
    robot = c5_kernels.Robot(robot=str(file))
    samples = [(pose, twist) for pose, twist, _ in states(home, 6, 43)]
    worst = task_space_differences(robot, engine, samples)
    print(f"task space and joint inertia against Pinocchio: {worst}")
    assert all(value < BOUND for value in worst.values()), worst


def test_the_regressor_carries_pinocchios_torques_and_identify_finds_them(hexapod):
    """`Y π` (Python's `Robot`, the file's masses and a friction) is Pinocchio's torques with
    that friction on its motor rates; `identify` on forces of the base regressor gives back
    the base parameters."""
    c5_kernels = pytest.importorskip("c5_kernels")
    file, _, engine, home = hexapod
    robot = c5_kernels.Robot(robot=str(file))
    viscous = np.array([0.02, 0.03, 0.025, 0.018, 0.04, 0.022])
    coulomb = np.array([0.1, 0.12, 0.08, 0.11, 0.09, 0.1])
    pi = robot.standard_values(viscous, coulomb)
    assert len(pi) == len(robot.standard_parameters) == 76
    worst = 0.0
    for pose, twist, accel in states(home, 12, 31):
        y = robot.regressor(pose, twist[:3], twist[3:], accel[:3], accel[3:])
        qd = pinocchio_motor_rates(engine, pose, twist)
        want = pinocchio_torques(engine, pose, twist, accel) + viscous * qd + coulomb * np.sign(qd)
        worst = max(worst, relative(y @ pi, want))
    assert worst < BOUND, worst
    samples = [np.array(column) for column in zip(*states(home, 300, 32))]
    pose, twist, accel = samples
    motion = (pose, twist[:, :3], twist[:, 3:], accel[:, :3], accel[:, 3:])
    beta = robot.base_values(viscous, coulomb)
    gamma = robot.base_regressor(*motion) @ beta
    assert np.allclose(robot.regressor(*motion) @ pi, gamma, rtol=1e-10, atol=1e-9)
    estimate = robot.identify(*motion, gamma)
    assert estimate["model"] == "rus-hexapod" and estimate["names"] == robot.base_parameters
    assert np.allclose(estimate["values"], beta, rtol=1e-7, atol=1e-8)
