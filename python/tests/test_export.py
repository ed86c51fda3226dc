"""`c5 export` checked by two engines that share nothing with the kernels: Pinocchio's
`constraintDynamics` on the exported MJCF (its welds as rigid constraints) against `c5 forward`,
MuJoCo simulating the same file under held actuator forces against `c5 simulate --torques`, and
a URDF parser's tree summed against the robot file (docs/export.md). The rotary hexapod and the
Delta are also held to their robot files' geometry and statics written from the mechanism
issue's formulas (rus_geometry.py); the rotary hexapod's kernels against Pinocchio:
test_rus_hexapod.py.

The engines read the exported files alone (exported.py): no test here tells them which
mechanism the file holds. Robots: the chapter's C5, a C5 no Rust test uses, docs/hexapod.toml,
a hexapod of other numbers, docs/rus-hexapod.toml, docs/delta.toml and one of each of other
numbers.
"""

from __future__ import annotations

import subprocess
import tomllib

import numpy as np
import pytest

from conftest import DEFAULT_ROBOT, ROOT
from exported import PinocchioExport, rotation
from rus_geometry import RusRobot

mujoco = pytest.importorskip("mujoco")
pin = pytest.importorskip("pinocchio")

HEXAPOD = ROOT / "docs" / "hexapod.toml"
# The largest differences docs/export.md states; each is held at ten times.
STATED = {
    "pinocchio": 4e-13,      # relative, the platform's acceleration
    "weld": 1e-15,           # Pinocchio's welds after Newton (m, rad)
    "keyframe": 1e-15,       # MuJoCo's loops at the keyframe (m, rad)
    "held_position": 3e-7,   # MuJoCo against `c5 simulate --torques`, 0.5 s (m)
    "held_rotation": 5e-7,   # the same, the rotation matrices' entries
    "held_loops": 5e-7,      # MuJoCo's loops along the way (m)
    "crank_angle": 2e-14,    # Pinocchio's motor angles against the issue's formula (rad)
    "statics": 1e-8,         # Pinocchio's holding torques against virtual work, relative
    "still": 6e-8,           # MuJoCo holding still under those torques for 0.5 s (m)
}


@pytest.fixture(scope="session")
def unseen_hexapod_file(tmp_path_factory):
    from test_gough_stewart_pinocchio import toml, unseen_hexapod

    path = tmp_path_factory.mktemp("robots") / "unseen-hexapod.toml"
    path.write_text(toml(unseen_hexapod(np.random.default_rng(11))))
    return path


@pytest.fixture(params=["c5", "unseen-c5", "hexapod", "unseen-hexapod"])
def robot(request, unseen_robot, unseen_hexapod_file):
    """The robot's `--robot` arguments, whether it is a C5, and its file."""
    path, is_c5 = {
        "c5": (None, True),
        "unseen-c5": (unseen_robot, True),
        "hexapod": (HEXAPOD, False),
        "unseen-hexapod": (unseen_hexapod_file, False),
    }[request.param]
    return (["--robot", str(path)] if path else []), is_c5, path or DEFAULT_ROBOT


def export(c5_program, args, fmt, tmp_path):
    path = tmp_path / f"robot.{'xml' if fmt == 'mjcf' else 'urdf'}"
    subprocess.run([str(c5_program), "export", *args, "--format", fmt, "--out", str(path)],
                   check=True)
    return path


def home_pose(mjcf_path):
    """The home pose the file was written at (level at home, as both mechanisms are)."""
    m = mujoco.MjModel.from_xml_path(str(mjcf_path))
    assert np.allclose(m.key_qpos[0][3:7], [1, 0, 0, 0]), "a level home"
    return [0.0, 0.0, 0.0, *m.key_qpos[0][0:3]]


def holding_forces(run_c5, args, home):
    rest = dict(pose=list(home), omega=[0, 0, 0], velocity=[0, 0, 0], omega_dot=[0, 0, 0],
                acceleration=[0, 0, 0])
    return np.array(run_c5("eval", [rest], *args)[0]["gamma"])


def test_pinocchio_constraint_dynamics_agrees_with_c5_forward(robot, c5_program, run_c5,
                                                              tmp_path):
    args, is_c5, file = robot
    path = export(c5_program, args, "mjcf", tmp_path)
    engine = PinocchioExport(path)
    home = home_pose(path)
    rng = np.random.default_rng(7)
    spread = (0.15, 0.03) if is_c5 else (0.2, 0.06)
    hold = holding_forces(run_c5, args, home)
    states = []
    for _ in range(20):
        pose = list(rng.uniform(-spread[0], spread[0], 3)) + list(
            np.array(home[3:]) + rng.uniform(-spread[1], spread[1], 3))
        twist = list(rng.uniform(-1, 1, 3)) + list(rng.uniform(-0.5, 0.5, 3))
        states.append((pose, twist, list(hold + rng.uniform(-100, 100, 6))))
    ours = run_c5("forward", [dict(pose=p, omega=t[:3], velocity=t[3:], gamma=g)
                              for p, t, g in states], *args)
    worst, weld = 0.0, 0.0
    for (pose, twist, gamma), mine in zip(states, ours):
        theirs = engine.forward(pose, twist, gamma)
        weld = max(weld, engine.state(pose, twist)[2])
        mine = np.array(mine["omega_dot"] + mine["acceleration"])
        worst = max(worst, np.max(np.abs(mine - theirs)) / np.max(np.abs(theirs)))
    print(f"Pinocchio on the export: {worst:.1e} relative, welds closed to {weld:.1e}")
    assert worst < 10 * STATED["pinocchio"]
    assert weld < 10 * STATED["weld"]


def weld_errors(m, d, reference, to_world=False):
    """How far each welded body is from where the file welds it: position (m), rotation
    (the rotation vector's length, rad); with `to_world`, the welds to the world alone."""
    position, angle = 0.0, 0.0
    for k in range(m.neq):
        if to_world and not (m.eq_type[k] == mujoco.mjtEq.mjEQ_WELD and m.eq_obj2id[k] == 0):
            continue
        body = m.eq_obj1id[k]
        position = max(position, np.max(np.abs(d.xpos[body] - reference[body][0])))
        q = np.zeros(4)
        mujoco.mju_mulQuat(q, d.xquat[body], reference[body][1] * [1, -1, -1, -1])
        angle = max(angle, 2 * np.arctan2(np.linalg.norm(q[1:]), abs(q[0])))
    return position, angle


@pytest.fixture(params=["c5", "hexapod", "rus-hexapod", "delta", "unseen-rus-hexapod",
                        "unseen-delta"])
def any_robot(request, new_robot_files):
    """Every mechanism: `--robot` arguments and the number of actuators."""
    path = {"c5": None, "hexapod": HEXAPOD, **new_robot_files}[request.param]
    actuators = 3 if "delta" in request.param else 6
    return (["--robot", str(path)] if path else []), actuators


def connect_errors(m, d):
    """How far apart the two points each ball constraint (`connect`) joins are (m)."""
    worst = 0.0
    for k in range(m.neq):
        if m.eq_type[k] != mujoco.mjtEq.mjEQ_CONNECT:
            continue
        ends = [d.xpos[b] + d.xmat[b].reshape(3, 3) @ m.eq_data[k][3 * j:3 * j + 3]
                for j, b in enumerate([m.eq_obj1id[k], m.eq_obj2id[k]])]
        worst = max(worst, np.max(np.abs(ends[0] - ends[1])))
    return worst


def test_mujoco_loads_the_export_without_a_warning_and_its_keyframe_closes_the_loops(
        any_robot, c5_program, tmp_path):
    args, actuators = any_robot
    path = export(c5_program, args, "mjcf", tmp_path)
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    assert m.nu == actuators and m.neq >= actuators and m.nkey == 1
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    # Each weld holds its body where the file puts it: its place in the reference
    # configuration, which is the keyframe.
    reference = {m.eq_obj1id[k]: (d.xpos[m.eq_obj1id[k]].copy(), d.xquat[m.eq_obj1id[k]].copy())
                 for k in range(m.neq)}
    dq = mujoco.MjData(m)
    dq.qpos[:] = m.qpos0
    mujoco.mj_forward(m, dq)
    assert np.max(np.abs(m.key_qpos[0] - m.qpos0)) == 0.0
    assert np.max(np.abs(d.efc_pos[:d.nefc])) < 10 * STATED["keyframe"]
    assert all(w.number == 0 for w in d.warning), [w.number for w in d.warning]
    assert max(weld_errors(m, d, reference)) == 0.0
    model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
    assert len(constraints) == m.neq and model.nv == m.nv


# The platform: the root of every export's tree, the world's first child.
PLATFORM = 1


def follow_held(mjcf, gamma, held_csv, moved_at_least):
    """MuJoCo on the export `mjcf` from its keyframe under `ctrl = gamma`, stepped along the
    rows of `c5 simulate --torques`' `held_csv` (the platform's coordinates: with the angles
    for a platform free in space, without for one that only translates): the platform's
    position and rotation, and the loops (the welds to the world and each ball closure),
    held to the figures docs/export.md states."""
    ours = np.loadtxt(held_csv, delimiter=",", skiprows=1)
    header = held_csv.read_text().splitlines()[0].split(",")
    at, turns = header.index("xc"), "alpha" in header
    m = mujoco.MjModel.from_xml_path(str(mjcf))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    reference = {m.eq_obj1id[k]: (d.xpos[m.eq_obj1id[k]].copy(), d.xquat[m.eq_obj1id[k]].copy())
                 for k in range(m.neq)}
    d.ctrl[:] = gamma
    per_row = round((ours[1, 0] - ours[0, 0]) / m.opt.timestep)
    position = rotation_error = loops = 0.0
    for k, row in enumerate(ours):
        if k:
            mujoco.mj_step(m, d, nstep=per_row)
        mujoco.mj_kinematics(m, d)
        position = max(position, np.max(np.abs(d.xpos[PLATFORM] - row[at:at + 3])))
        mine = rotation(row[1:4]) if turns else np.eye(3)
        theirs = d.xmat[PLATFORM].reshape(3, 3)
        rotation_error = max(rotation_error, np.max(np.abs(theirs - mine)))
        loops = max(loops, weld_errors(m, d, reference, to_world=True)[0],
                    connect_errors(m, d))
    moved = np.max(np.abs(ours[-1, at:at + 3] - ours[0, at:at + 3]))
    print(f"MuJoCo against c5 simulate over {ours[-1, 0]} s, the platform moving "
          f"{moved * 1e3:.1f} mm: position {position:.1e} m, rotation {rotation_error:.1e}, "
          f"loops {loops:.1e} m")
    assert moved > moved_at_least, "the platform moves: the comparison is not of two rests"
    assert abs(d.time - ours[-1, 0]) < 1e-9
    assert all(w.number == 0 for w in d.warning), [w.number for w in d.warning]
    assert position < 10 * STATED["held_position"]
    assert rotation_error < 10 * STATED["held_rotation"]
    assert loops < 10 * STATED["held_loops"]


def test_mujoco_follows_c5_simulate_under_held_forces(robot, c5_program, run_c5, tmp_path):
    args, _, _ = robot
    path = export(c5_program, args, "mjcf", tmp_path)
    home = home_pose(path)
    gamma = holding_forces(run_c5, args, home) + np.random.default_rng(5).uniform(-3, 3, 6)
    subprocess.run([str(c5_program), "simulate", *args, "--torques",
                    ",".join(repr(float(g)) for g in gamma), "--duration", "0.5",
                    "--out", str(tmp_path)], check=True, capture_output=True)
    follow_held(path, gamma, tmp_path / "held.csv", 5e-3)


def rpy_matrix(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def urdf_totals(text):
    """The URDF's tree at zero joints: total mass, first moment and inertia about the base
    origin, base frame."""
    urdf = pytest.importorskip("urdf_parser_py.urdf")
    model = urdf.URDF.from_xml_string(text)
    placement = {model.get_root(): (np.eye(3), np.zeros(3))}
    pending = list(model.joints)
    while pending:
        joint = pending.pop(0)
        if joint.parent not in placement:
            pending.append(joint)
            continue
        rp, op = placement[joint.parent]
        placement[joint.child] = (rp @ rpy_matrix(joint.origin.rpy),
                                  op + rp @ np.array(joint.origin.xyz))
    return composite((placement[link.name][0], placement[link.name][1], link.inertial)
                     for link in model.links if link.inertial is not None)


def composite(bodies):
    mass, first, inertia = 0.0, np.zeros(3), np.zeros((3, 3))
    for rot, origin, inertial in bodies:
        i = inertial.inertia
        local = np.array([[i.ixx, i.ixy, i.ixz], [i.ixy, i.iyy, i.iyz], [i.ixz, i.iyz, i.izz]])
        c = origin + rot @ np.array(inertial.origin.xyz)
        m = inertial.mass
        mass += m
        first += m * c
        inertia += rot @ local @ rot.T + m * (c @ c * np.eye(3) - np.outer(c, c))
    return mass, first, inertia


class Inertial:
    """A body's inertia as the robot file gives it, in the URDF parser's shape."""

    def __init__(self, mass, com, matrix):
        m = np.asarray(matrix, float)
        self.mass = mass
        self.origin = type("Origin", (), {"xyz": list(com)})
        self.inertia = type("Inertia", (), dict(ixx=m[0, 0], ixy=m[0, 1], ixz=m[0, 2],
                                                iyy=m[1, 1], iyz=m[1, 2], izz=m[2, 2]))


def c5_file_totals(path):
    """The C5 at home from its file: the platform at the origin, each body 2 at `A_i` (where
    eq 16 puts `B_i` at the level home), each rod's centre of mass at `A_i` too."""
    doc = tomllib.loads(path.read_text())
    half = doc["half_spacing"]
    anchors = [[0, 0, half], [0, 0, -half], [half, 0, 0], [-half, 0, 0], [0, half, 0],
               [0, -half, 0]]
    bodies = [(np.eye(3), np.zeros(3), Inertial(doc["platform"]["mass"], doc["platform"]["com"],
                                                doc["platform"]["inertia"]))]
    for anchor, segment in zip(anchors, doc["segments"]):
        joint, rod = segment["joint"], segment["rod"]
        bodies.append((np.eye(3), np.array(anchor, float),
                       Inertial(joint["mass"], joint["com"], joint["inertia"])))
        bodies.append((np.eye(3), np.array(anchor, float),
                       Inertial(rod["mass"], [0, 0, 0], rod["inertia"])))
    return composite(bodies)


def hexapod_file_totals(path, home):
    """The hexapod at home, built from its file by the independent Pinocchio model of
    test_gough_stewart_pinocchio.py."""
    from test_gough_stewart_pinocchio import PinocchioHexapod

    engine = PinocchioHexapod(tomllib.loads(path.read_text()), home)
    q, _ = engine.configuration(home, [0.0] * 6)
    data = engine.model.createData()
    pin.ccrba(engine.model, data, q, np.zeros(engine.model.nv))
    whole = data.oYcrb[0]
    c = whole.lever
    inertia = whole.inertia + whole.mass * (c @ c * np.eye(3) - np.outer(c, c))
    return whole.mass, whole.mass * c, inertia


def test_urdf_loads_and_its_links_sum_to_the_robot_file(robot, c5_program, tmp_path):
    args, is_c5, file = robot
    text = export(c5_program, args, "urdf", tmp_path).read_text()
    assert text.count("<constraint ") == 6
    mass, first, inertia = urdf_totals(text)
    if is_c5:
        want = c5_file_totals(file)
    else:
        want = hexapod_file_totals(file, home_pose(export(c5_program, args, "mjcf", tmp_path)))
    assert abs(mass - want[0]) < 1e-12 * want[0]
    assert np.max(np.abs(first - want[1])) < 1e-12 * want[0]
    assert np.max(np.abs(inertia - want[2])) < 1e-12 * np.max(np.abs(want[2]))


def test_the_python_robot_exports_what_the_program_does(c5_program, tmp_path):
    import c5_kernels

    for args, robot in [([], c5_kernels.Robot()),
                        (["--robot", str(HEXAPOD)], c5_kernels.Robot(robot=HEXAPOD))]:
        assert robot.to_mjcf() == export(c5_program, args, "mjcf", tmp_path).read_text()
        assert robot.to_urdf() == export(c5_program, args, "urdf", tmp_path).read_text()
    for file in [ROOT / "docs" / "rus-hexapod.toml", ROOT / "docs" / "delta.toml"]:
        assert c5_kernels.export(file) == export(c5_program, ["--robot", str(file)], "mjcf",
                                                  tmp_path).read_text()
        assert c5_kernels.export(file, "urdf") == export(c5_program, ["--robot", str(file)],
                                                         "urdf", tmp_path).read_text()
    assert c5_kernels.export() == c5_kernels.Robot().to_mjcf()
    with pytest.raises(ValueError, match="`mjcf` or `urdf`"):
        c5_kernels.export(format="sdf")
    assert c5_kernels.C5 is c5_kernels.Robot
    with pytest.raises(ValueError, match="not a mechanism"):
        c5_kernels.C5(model="paper").to_mjcf()


def unseen(doc: dict, rng) -> dict:
    """`doc` with other numbers: the geometry scaled and jittered, other masses and inertias,
    gravity off the z axis, encoder offsets."""
    doc = {**doc, "gravity": [0.15, -0.2, -9.79]}
    doc["platform"] = {**doc["platform"], "mass": doc["platform"]["mass"] * 1.3,
                       "centre_of_mass": [0.004, -0.003, doc["platform"]["centre_of_mass"][2]]}
    key = "arms" if doc["mechanism"] == "delta" else "legs"
    legs = []
    for leg in doc[key]:
        leg = dict(leg)
        leg["base"] = [1.1 * x + rng.uniform(-0.005, 0.005) for x in leg["base"]]
        leg["platform"] = [1.1 * x + rng.uniform(-0.005, 0.005) for x in leg["platform"]]
        leg["axis"] = [x + rng.uniform(-0.05, 0.05) for x in leg["axis"]]
        leg["crank"] = {**leg["crank"], "length": 1.1 * leg["crank"]["length"],
                        "mass": leg["crank"]["mass"] * rng.uniform(0.8, 1.2),
                        "com": leg["crank"]["com"] * rng.uniform(0.8, 1.2)}
        leg["rod"] = {**leg["rod"], "length": 1.1 * leg["rod"]["length"],
                      "mass": leg["rod"]["mass"] * rng.uniform(0.8, 1.2)}
        leg["encoder_offset"] = rng.uniform(-0.1, 0.1)
        legs.append(leg)
    doc[key] = legs
    return doc


def toml_text(doc: dict) -> str:
    def value(v):
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, str):
            return f'"{v}"'
        return repr(float(v))
    lists = {k: v for k, v in doc.items() if isinstance(v, list) and v and isinstance(v[0], dict)}
    text = "".join(f"{k} = {value(v)}\n" for k, v in doc.items()
                   if not isinstance(v, dict) and k not in lists)
    text += "".join(f"[{k}]\n" + "".join(f"{f} = {value(x)}\n" for f, x in v.items())
                    for k, v in doc.items() if isinstance(v, dict))
    for k, items in lists.items():
        text += "".join(f"[[{k}]]\n" + "".join(f"{f} = {value(x)}\n" for f, x in item.items())
                        for item in items)
    return text


@pytest.fixture(scope="session")
def new_robot_files(tmp_path_factory):
    """docs/rus-hexapod.toml, docs/delta.toml, and one of each of other numbers."""
    files = {"rus-hexapod": ROOT / "docs" / "rus-hexapod.toml",
             "delta": ROOT / "docs" / "delta.toml"}
    out = tmp_path_factory.mktemp("new-robots")
    for name, path in list(files.items()):
        doc = unseen(tomllib.loads(path.read_text()), np.random.default_rng(len(name)))
        files[f"unseen-{name}"] = out / f"unseen-{name}.toml"
        files[f"unseen-{name}"].write_text(toml_text(doc))
    return files


@pytest.fixture(params=["rus-hexapod", "delta", "unseen-rus-hexapod", "unseen-delta"])
def new_robot(request, new_robot_files, c5_program, tmp_path):
    """A rotary hexapod or a Delta: its geometry from the file, its export in
    Pinocchio, its MJCF path and its home pose."""
    file = new_robot_files[request.param]
    path = export(c5_program, ["--robot", str(file)], "mjcf", tmp_path)
    geometry = RusRobot(tomllib.loads(file.read_text()))
    m = mujoco.MjModel.from_xml_path(str(path))
    home = m.body_pos[1].copy() if geometry.delta else [0.0, 0.0, 0.0, *m.key_qpos[0][0:3]]
    return geometry, PinocchioExport(path), path, np.asarray(home, float)


def near(home, rng, delta):
    if delta:
        return home + rng.uniform(-0.04, 0.04, 3)
    return home + np.concatenate([rng.uniform(-0.1, 0.1, 3), rng.uniform(-0.02, 0.02, 3)])


def test_pinocchio_turns_the_exported_cranks_as_the_issue_computes_them(new_robot):
    geometry, engine, _, home = new_robot
    names = [f"{'arm' if geometry.delta else 'leg'}{i + 1}_angle"
             for i in range(len(geometry.legs))]
    at_home = geometry.angles(home)
    rng = np.random.default_rng(3)
    worst = weld = 0.0
    for _ in range(10):
        pose = near(home, rng, geometry.delta)
        q, _, error = engine.state(pose, np.zeros(3 if geometry.delta else 6))
        turned = at_home + np.array([engine.joint_value(q, n) for n in names])
        worst = max(worst, np.max(np.abs(turned - geometry.angles(pose))))
        weld = max(weld, error)
    print(f"crank angles against the issue's formula: {worst:.1e} rad, welds {weld:.1e}")
    assert worst < 10 * STATED["crank_angle"]
    assert weld < 10 * STATED["weld"]


def pinocchio_holding_torques(engine, pose, actuators):
    """The torques under which Pinocchio's platform stays at rest at `pose`: the acceleration
    is affine in them, so one solve."""
    rest = np.zeros(engine.platform_dofs)
    base = engine.forward(pose, rest, np.zeros(actuators))
    columns = [engine.forward(pose, rest, np.eye(actuators)[k]) - base
               for k in range(actuators)]
    return np.linalg.solve(np.column_stack(columns), -base)


def test_pinocchio_holds_the_export_with_the_torques_of_virtual_work(new_robot):
    geometry, engine, _, home = new_robot
    rng = np.random.default_rng(4)
    worst = 0.0
    for pose in [home] + [near(home, rng, geometry.delta) for _ in range(4)]:
        theirs = pinocchio_holding_torques(engine, pose, len(geometry.legs))
        ours = geometry.holding_torques(pose)
        worst = max(worst, np.max(np.abs(theirs - ours)) / np.max(np.abs(ours)))
    print(f"holding torques, Pinocchio against virtual work: {worst:.1e} relative")
    assert worst < 10 * STATED["statics"]


def test_mujoco_keeps_the_export_still_under_the_torques_of_virtual_work(new_robot):
    geometry, _, path, home = new_robot
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    d.ctrl[:] = geometry.holding_torques(home)
    start = d.qpos[0:3].copy()
    mujoco.mj_step(m, d, nstep=round(0.5 / m.opt.timestep))
    drift = np.max(np.abs(d.qpos[0:3] - start))
    print(f"MuJoCo under the holding torques, 0.5 s: the platform moves {drift:.1e} m")
    assert all(w.number == 0 for w in d.warning)
    assert drift < 10 * STATED["still"]


@pytest.mark.parametrize("name", ["rus-hexapod", "delta", "unseen-rus-hexapod", "unseen-delta"])
def test_mujoco_follows_c5_simulate_of_the_new_mechanisms_under_held_torques(
        name, new_robot_files, c5_program, tmp_path):
    """`c5 simulate --torques` of a rotary hexapod or a Delta (its platform's coordinates,
    three for the Delta) against MuJoCo on the export under the same `ctrl`: the holding
    torques of virtual work (rus_geometry.py) and a little more, so that the platform moves
    (for 0.3 s: the unseen rotary hexapod reaches its legs' singularity at 0.43 s)."""
    file = new_robot_files[name]
    args = ["--robot", str(file)]
    path = export(c5_program, args, "mjcf", tmp_path)
    geometry = RusRobot(tomllib.loads(file.read_text()))
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_kinematics(m, d)
    centre = d.xpos[PLATFORM].copy()
    home = centre if geometry.delta else np.array([0, 0, 0, *centre])
    hold = geometry.holding_torques(home)
    rng = np.random.default_rng(len(name))
    gamma = hold + 0.03 * np.max(np.abs(hold)) * rng.uniform(-1, 1, len(hold))
    subprocess.run([str(c5_program), "simulate", *args, "--torques",
                    ",".join(repr(float(g)) for g in gamma), "--duration", "0.3",
                    "--out", str(tmp_path)], check=True, capture_output=True)
    header = (tmp_path / "held.csv").read_text().splitlines()[0].split(",")
    angles = [] if geometry.delta else ["alpha", "beta", "gamma"]
    rates = [] if geometry.delta else ["wx", "wy", "wz"]
    assert header == ["t", *angles, "xc", "yc", "zc", *rates, "vx", "vy", "vz"]
    follow_held(path, gamma, tmp_path / "held.csv", 2e-3)


def test_the_new_mechanisms_urdf_sums_to_their_files(new_robot, c5_program, tmp_path,
                                                      new_robot_files):
    geometry, _, path, home = new_robot
    file = next(f for f in new_robot_files.values()
                if RusRobot(tomllib.loads(f.read_text())).doc == geometry.doc)
    text = export(c5_program, ["--robot", str(file)], "urdf", tmp_path).read_text()
    mass, first, inertia = urdf_totals(text)
    want = composite((rot, com, Inertial(m, [0, 0, 0], i))
                     for rot, com, m, i in geometry.bodies(home))
    assert abs(mass - want[0]) < 1e-12 * want[0]
    assert np.max(np.abs(first - want[1])) < 1e-12 * want[0]
    assert np.max(np.abs(inertia - want[2])) < 1e-11 * np.max(np.abs(want[2]))
