"""Pinocchio's closed-loop forward dynamics (`constraintDynamics`) on the example hexapod
(docs/hexapod.toml), timed through its Python bindings: the peer figure of
`cargo bench --bench gough_stewart` (`forward_dynamics`).

Run in a virtual environment with `pip install pin numpy` (from the repository root):

    taskset -c 0 python python/bench_pinocchio_hexapod.py

The model is the one the Python tests check `c5 forward` against (a free-flying platform, per
leg a U joint, a prismatic joint and two bodies, closed by one 3D contact per leg). Each call is
timed with its data made once beforehand, as a C++ caller would; the Python call itself costs
about a microsecond of what is printed.
"""

from __future__ import annotations

import sys
import timeit
import tomllib
from pathlib import Path

import numpy as np
import pinocchio as pin

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python" / "tests"))
from test_gough_stewart_pinocchio import PinocchioHexapod  # noqa: E402

CALLS = 20000


def main() -> None:
    robot = tomllib.loads((ROOT / "docs" / "hexapod.toml").read_text())
    home = [0.0, 0.0, 0.0, 0.0, 0.0, 0.425]
    hexapod = PinocchioHexapod(robot, home)
    pose = [0.05, -0.03, 0.08, 0.01, 0.02, 0.44]
    q, v = hexapod.configuration(pose, [0.3, -0.2, 0.1, 0.05, 0.02, -0.03])
    m = hexapod.model
    tau = np.zeros(m.nv)
    data = m.createData()
    datas = pin.StdVec_RigidConstraintData()
    for c in hexapod.constraints:
        datas.append(c.createData())
    pin.initConstraintDynamics(m, data, hexapod.constraints, datas)
    settings = pin.ProximalSettings(1e-14, 0.0, 1)

    def call():
        pin.constraintDynamics(m, data, q, v, tau, hexapod.constraints, datas, settings)

    best = min(timeit.repeat(call, number=CALLS, repeat=5)) / CALLS
    print(f"pinocchio {pin.__version__} constraintDynamics, hexapod: {best * 1e6:.2f} us a call "
          f"(best of 5 runs of {CALLS}, Python bindings)")


if __name__ == "__main__":
    main()
