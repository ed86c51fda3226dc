"""Pinocchio's closed-loop forward dynamics (`constraintDynamics`) on a robot exported by
`c5 export` (its welds as rigid constraints, python/tests/exported.py), timed through its Python
bindings: the peer figure of the `forward_dynamics_runtime` benches (docs/mechanisms.md).

Run in a virtual environment with `pip install pin mujoco numpy`, from the repository root:

    cargo run --release -- export --robot docs/rus-hexapod.toml --out rus.xml
    taskset -c 0 python python/bench_pinocchio_export.py rus.xml \\
        0.05 -0.03 0.04 0.005 -0.004 0.33   0.3 -0.2 0.1 0.05 0.02 -0.03

    cargo run --release -- export --robot docs/delta.toml --out delta.xml
    taskset -c 0 python python/bench_pinocchio_export.py delta.xml \\
        0.01 -0.02 -0.6   0.2 -0.1 0.3

The numbers are the platform's pose `[α β γ xc yc zc]` and twist `(ω; v_C)`, or for a platform
that only translates (the Delta) its position and velocity. A Delta's constraints repeat (each
parallelogram's two balls, and the slides), so its solve needs a positive `mu` and a second
proximal iteration: with `mu = 1e-8`, one iteration is 1.6e-9 off the converged acceleration,
two are 2e-16 off, and further ones only cost time; a hexapod's takes one. Each call is timed
with its data made once beforehand, as a C++ caller would; the Python call itself costs about
a microsecond of what is printed.
"""

from __future__ import annotations

import sys
import timeit
from pathlib import Path

import numpy as np
import pinocchio as pin

sys.path.insert(0, str(Path(__file__).resolve().parent / "tests"))
from exported import PinocchioExport  # noqa: E402

CALLS = 20000


def main() -> None:
    path, *numbers = sys.argv[1:]
    values = [float(x) for x in numbers]
    engine = PinocchioExport(path)
    n = 6 if engine.free else 3
    q, v, loops = engine.state(np.array(values[:n]), values[n:])
    assert loops < 1e-12, f"the loops did not close: {loops}"
    m = engine.model
    tau = np.zeros(m.nv)
    tau[engine.actuated] = 1.0
    data = m.createData()
    datas = pin.StdVec_RigidConstraintData()
    for c in engine.constraints:
        datas.append(c.createData())
    pin.initConstraintDynamics(m, data, engine.constraints, datas)
    settings = (pin.ProximalSettings(1e-14, 0.0, 1) if engine.free
                else pin.ProximalSettings(1e-14, 1e-8, 2))

    def call():
        pin.constraintDynamics(m, data, q, v, tau, engine.constraints, datas, settings)

    times = sorted(t / CALLS for t in timeit.repeat(call, number=CALLS, repeat=7))
    print(f"pinocchio {pin.__version__} constraintDynamics on {path}: median "
          f"{times[3] * 1e6:.2f} us a call (min {times[0] * 1e6:.2f}, max "
          f"{times[-1] * 1e6:.2f}; 7 runs of {CALLS}, Python bindings)")


if __name__ == "__main__":
    main()
