"""Pinocchio's closed-loop forward dynamics (`constraintDynamics`) in C++, on robots exported by
`c5 export`: the peer figure of the `forward_dynamics_runtime` benches (docs/speed.md).

Run in a virtual environment with `pip install pin mujoco numpy cmeel-eigen`, from the
repository root, after `cargo build --release`:

    taskset -c 0 python python/bench_pinocchio_cpp.py docs/delta.toml lean:docs/hexapod.toml

For each robot file: the export read by Pinocchio's MJCF parser (python/tests/exported.py), or
for `lean:FILE` a Gough-Stewart file's lean model (a U joint and a slide per leg, one 3D contact
each: the model the Python tests check against); the loops closed at a state near home, the
model written as text; benches/pinocchio/
constraint_dynamics.cpp builds the same model in code (header-only, with the `pin` wheel's
headers: `g++ -std=c++17 -O3 -march=native -DNDEBUG`, about a minute, cached under
target/pinocchio/), checks its accelerations against Pinocchio's Python ones (1e-9) and times
the call: 11 runs of 20 000 calls with the data made once beforehand, as a controller would.
One JSON line per robot: the median, min and max in microseconds, and every run's time.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "python" / "tests"))
from exported import PinocchioExport  # noqa: E402

SOURCE = ROOT / "benches" / "pinocchio" / "constraint_dynamics.cpp"
SIMPLE = {f"JointModel{a}{x}": f"{a}{x}" for a in "RP" for x in "XYZ"}
# The defines of the wheel's CMake interface (lib/cmake/pinocchio): its headers need them.
DEFINES = ["-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_MPL_LIMIT_LIST_SIZE=30",
           "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12"]


def numbers(values) -> str:
    return " ".join(f"{x:.17g}" for x in values)


def placement(se3) -> str:
    return numbers([*se3.rotation.flatten(), *se3.translation])


def joint(j) -> str:
    name, x = j.shortname(), j.extract()
    if name == "JointModelComposite":
        parts = [joint(jj) + " " + placement(pl) for jj, pl in zip(x.joints, x.jointPlacements)]
        return f"composite {len(parts)} " + " ".join(parts)
    if name in SIMPLE:
        return SIMPLE[name]
    if name in ("JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned"):
        return ("Ru " if "Revolute" in name else "Pu ") + numbers(x.axis)
    if name in ("JointModelSpherical", "JointModelFreeFlyer"):
        return name[len("JointModel")]
    raise SystemExit(f"a joint the harness does not build: {name}")


def settings(engine):
    """A hexapod's constraints are independent: one iteration, no damping. A Delta's repeat
    (each parallelogram's two balls, and the slides): `mu = 1e-8` and a second iteration,
    which brings the acceleration from 1.6e-9 off the converged one to 2e-16."""
    return (0.0, 1) if engine.free else (1e-8, 2)


def model_text(engine) -> str:
    """The model, its constraints, a state near home and Pinocchio's accelerations there."""
    m = engine.model
    if engine.free:
        home = engine.home_centre
        pose = np.array([0.05, -0.03, 0.04, home[0] + 0.005, home[1] - 0.004, home[2] + 0.003])
        twist = np.array([0.3, -0.2, 0.1, 0.05, 0.02, -0.03])
    else:
        pose = engine.home_centre + np.array([0.01, -0.02, 0.01])
        twist = np.array([0.2, -0.1, 0.3])
    q, v, loops = engine.state(pose, twist)
    assert loops < 1e-12, f"the loops did not close: {loops}"
    tau = np.zeros(m.nv)
    tau[engine.actuated] = 1.0
    mu, iterations = settings(engine)
    lines = ["gravity " + numbers(m.gravity.linear)]
    for i in range(1, m.njoints):
        inertia = m.inertias[i]
        lines.append(f"joint {m.parents[i]} {placement(m.jointPlacements[i])} "
                     f"{numbers([inertia.mass, *inertia.lever, *inertia.inertia.flatten()])} "
                     f"{joint(m.joints[i])}")
    for c in engine.constraints:
        kind = 3 if c.type == pin.ContactType.CONTACT_3D else 6
        lines.append(f"constraint {kind} {c.joint1_id} {c.joint2_id} "
                     f"{placement(c.joint1_placement)} {placement(c.joint2_placement)}")
    data = m.createData()
    datas = pin.StdVec_RigidConstraintData()
    for c in engine.constraints:
        datas.append(c.createData())
    pin.initConstraintDynamics(m, data, engine.constraints, datas)
    ddq = pin.constraintDynamics(m, data, q, v, tau, engine.constraints, datas,
                                 pin.ProximalSettings(1e-14, mu, iterations))
    lines += [f"settings {mu:.17g} {iterations}", "q " + numbers(q), "v " + numbers(v),
              "tau " + numbers(tau), "ddq " + numbers(ddq)]
    return "\n".join(lines) + "\n"


class LeanHexapod:
    """A Gough-Stewart file's lean model, the one the Python tests check against
    (python/tests/test_gough_stewart_pinocchio.py: a free platform, per leg a U joint and a
    slide, one 3D contact each), in the terms `model_text` reads."""

    free = True

    def __init__(self, robot: Path, home_centre):
        import tomllib

        from test_gough_stewart_pinocchio import PinocchioHexapod

        self.hexapod = PinocchioHexapod(tomllib.loads(robot.read_text()),
                                        [0.0, 0.0, 0.0, *home_centre])
        self.model, self.constraints = self.hexapod.model, self.hexapod.constraints
        self.home_centre = np.array(home_centre)
        self.actuated = [self.model.joints[leg["prismatic"]].idx_v for leg in self.hexapod.legs]

    def state(self, pose, twist):
        """`q`, `v` at the pose and twist, and the largest gap of a leg's tip to its ball."""
        q, v = self.hexapod.configuration(pose, twist)
        data = self.model.createData()
        pin.forwardKinematics(self.model, data, q)
        platform = data.oMi[self.hexapod.platform]
        loops = max(np.linalg.norm(data.oMi[leg["prismatic"]].translation
                                   - platform.act(leg["joint"])) for leg in self.hexapod.legs)
        return q, v, loops


def engine(robot: str, program: str, tmp: str):
    """The robot's model: `lean:FILE` a hexapod's lean model (about the export's home pose),
    otherwise the file's export."""
    file = robot.removeprefix("lean:")
    mjcf = Path(tmp) / (Path(file).stem + ".xml")
    subprocess.run([program, "export", "--robot", file, "--out", str(mjcf)], check=True)
    export = PinocchioExport(mjcf)
    return LeanHexapod(ROOT / file, export.home_centre) if robot != file else export


def harness() -> Path:
    """The compiled harness, rebuilt when its source changes."""
    prefix = Path(pin.__file__).resolve().parents[4]
    digest = hashlib.sha256(SOURCE.read_bytes()).hexdigest()[:12]
    binary = ROOT / "target" / "pinocchio" / f"constraint_dynamics-{digest}"
    if not binary.exists():
        binary.parent.mkdir(parents=True, exist_ok=True)
        subprocess.run([os.environ.get("CXX", "g++"), "-std=c++17", "-O3", "-march=native",
                        "-DNDEBUG", *DEFINES, f"-I{prefix / 'include'}",
                        f"-I{prefix / 'include' / 'eigen3'}", str(SOURCE), "-o", str(binary)],
                       check=True)
    return binary


def main() -> None:
    program = os.environ.get("C5_PROGRAM", str(ROOT / "target" / "release" / "c5"))
    binary = harness()
    with tempfile.TemporaryDirectory() as tmp:
        for robot in sys.argv[1:]:
            text = Path(tmp) / (Path(robot).stem + ".txt")
            text.write_text(model_text(engine(robot, program, tmp)))
            out = subprocess.run([str(binary), str(text)], check=True, capture_output=True,
                                 text=True).stdout.strip()
            print(out.replace(str(text), robot))


if __name__ == "__main__":
    main()
