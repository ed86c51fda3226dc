"""Throughput of the c5_kernels module on a million states, one call each.

    python python/bench.py [--states N] [--repeat R]

Prints the median wall time of R calls (and per state) for the batch methods, from float64
numpy arrays already in memory, results copied out into new arrays. For comparison, the same
inverse dynamics through `c5 eval`'s JSON Lines (the way before this module), on a tenth of
the states, and one state per call (the Python call's own cost). Time it on a quiet machine
(`uptime`)."""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np

import c5_kernels


def median_seconds(f, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def states(n: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    pose = np.hstack([rng.uniform(-0.35, 0.35, (n, 3)), rng.uniform(-0.06, 0.06, (n, 3))])
    return (pose, *(rng.normal(scale=s, size=(n, 3)) for s in (0.8, 0.3, 4.0, 2.0)))


def report(name: str, seconds: float, n: int) -> None:
    print(f"{name:<44} {seconds * 1e3:9.1f} ms  {seconds / n * 1e9:8.1f} ns/state")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--c5", type=Path, default=Path(__file__).resolve().parents[1]
                        / "target" / "release" / "c5", help="the c5 program, for the JSON row")
    args = parser.parse_args()
    n, repeat = args.states, args.repeat
    print(f"c5_kernels {c5_kernels.__version__}, numpy {np.__version__}, "
          f"Python {platform.python_version()}, {platform.machine()}; {n} states, "
          f"median of {repeat}")
    s = states(n)
    pose, omega, velocity = s[:3]
    for model in ("consistent", "paper"):
        c5 = c5_kernels.C5(model)
        gamma = c5.inverse_dynamics(*s)
        q = c5.inverse_kinematics(pose)
        qd = c5.joint_velocities(pose, omega, velocity)
        qdd = np.zeros_like(qd)
        report(f"{model}: inverse_dynamics", median_seconds(lambda: c5.inverse_dynamics(*s),
                                                            repeat), n)
        report(f"{model}: forward_dynamics",
               median_seconds(lambda: c5.forward_dynamics(pose, omega, velocity, gamma), repeat),
               n)
        report(f"{model}: inverse_dynamics_joint",
               median_seconds(lambda: c5.inverse_dynamics_joint(q, qd, qdd), repeat), n)
        report(f"{model}: inverse_kinematics",
               median_seconds(lambda: c5.inverse_kinematics(pose), repeat), n)
    c5 = c5_kernels.C5()
    one = [a[0] for a in s]
    calls = 100_000
    report("consistent: inverse_dynamics, one state a call",
           median_seconds(lambda: [c5.inverse_dynamics(*one) for _ in range(calls // 10)],
                          repeat), calls // 10)
    if args.c5.exists():
        m = n // 10
        text = "".join(json.dumps({"pose": list(x), "omega": list(w), "velocity": list(v),
                                   "omega_dot": list(wd), "acceleration": list(a)}) + "\n"
                       for x, w, v, wd, a in zip(*(b[:m] for b in s)))
        seconds = median_seconds(lambda: subprocess.run([str(args.c5), "eval"], input=text,
                                                        text=True, capture_output=True,
                                                        check=True), 3)
        report("consistent: c5 eval, JSON Lines (every output)", seconds, m)


if __name__ == "__main__":
    main()
