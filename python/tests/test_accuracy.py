"""The accuracy contract (docs/embedding.md): near eq 16's singularities (`r11`, `r22` or
`r33 → 0`), what `c5 eval` and `c5 forward` serve is within 1e-8 relative of a 50-digit
reference (exact.py), or refused naming the term, its value and the bound it misses.

States at distances 1e-1 to 1e-7 from a singularity (`β` or `α` at `π/2 - s`, the other angles
and the motion at random), the consistent model, the default robot."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest
from mpmath import mp

from conftest import DEFAULT_ROBOT
from exact import Exact, forward_dynamics
from reference import Robot, rotation

BOUND = 1e-8
DISTANCES = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]


def relative(served, exact) -> float:
    """The largest error over the largest exact magnitude."""
    exact = np.array([float(x) for x in np.ravel(exact)])
    return float(np.max(np.abs(np.ravel(served) - exact)) / np.max(np.abs(exact)))


def near_singular_states(seed: int):
    rng = np.random.default_rng(seed)
    for s in DISTANCES:
        for which in (0, 1):
            pose = np.concatenate([rng.uniform(-0.3, 0.3, 3), rng.uniform(-0.05, 0.05, 3)])
            pose[which] = (np.pi / 2 - s) * rng.choice([-1.0, 1.0])
            yield (s, pose, rng.uniform(-1, 1, 3), rng.uniform(-0.3, 0.3, 3),
                   rng.uniform(-3, 3, 3), rng.uniform(-2, 2, 3))


def distance(pose) -> float:
    return float(np.min(np.abs(np.diag(rotation(*pose[:3])))))


@pytest.fixture(scope="module")
def robot():
    return Robot.load(DEFAULT_ROBOT)


@pytest.fixture(scope="module")
def answers(c5_program):
    """`c5 COMMAND` on JSON lines: one answer a line, a refusal as `{"line", "error"}`."""

    def run(command: str, lines: list[dict]) -> list[dict]:
        text = "".join(json.dumps(line) + "\n" for line in lines)
        done = subprocess.run([str(c5_program), command], input=text, text=True,
                              capture_output=True)
        out = [json.loads(line) for line in done.stdout.splitlines()]
        assert len(out) == len(lines) and done.returncode == (1 if any("error" in o for o in out)
                                                              else 0), done.stderr
        return out

    return run


def test_eval_serves_within_the_bound_or_refuses(robot, answers):
    states = list(near_singular_states(1))
    lines = [{"pose": list(p), "omega": list(w), "velocity": list(v), "omega_dot": list(wd),
              "acceleration": list(a)} for _, p, w, v, wd, a in states]
    out = answers("eval", lines)
    served = 0
    for (s, pose, w, v, wd, a), line in zip(states, out):
        if "error" in line:
            # Only at the singularity's own tolerance: the eval kernels stay accurate up to it.
            assert distance(pose) < 1e-9, (s, line["error"])
            continue
        exact = Exact(robot, pose, w, v, wd, a)
        jinv = mp.matrix(exact.jinv)
        errors = {
            "q": relative(line["q"], exact.q),
            "qd": relative(line["qd"], exact.qd),
            "qdd": relative(line["qdd"], exact.qdd),
            "gamma": relative(line["gamma"], exact.gamma()),
            "jinv": relative(line["jinv"], exact.jinv),
            "jacobian": relative(line["jacobian"], list(jinv ** -1)),
        }
        # The contract is 1e-8; docs/embedding.md states 3e-14 for these and 1e-12 for `J`,
        # held here to 10x.
        jacobian = errors.pop("jacobian")
        assert max(errors.values()) < 3e-13 and jacobian < 1e-11, (s, errors, jacobian)
        served += 1
    assert served == len(states)


def test_forward_serves_within_the_bound_or_refuses(robot, answers):
    states = list(near_singular_states(2))
    gammas = [[float(x) for x in Exact(robot, p, w, v, wd, a).gamma()]
              for _, p, w, v, wd, a in states]
    lines = [{"pose": list(p), "omega": list(w), "velocity": list(v), "gamma": g}
             for (_, p, w, v, _, _), g in zip(states, gammas)]
    out = answers("forward", lines)
    refused = 0
    for (s, pose, w, v, _, _), gamma, line in zip(states, gammas, out):
        if "error" in line:
            assert "forward dynamics" in line["error"] and "r" in line["error"], line["error"]
            assert distance(pose) < 1e-2, (s, line["error"])
            refused += 1
            continue
        served = line["omega_dot"] + line["acceleration"]
        error = relative(served, forward_dynamics(robot, pose, w, v, gamma))
        # docs/embedding.md states 3.8e-10 at worst where served; held here to 10x (the
        # contract itself is 1e-8).
        assert error < 4e-9, (s, distance(pose), error)
    # Every state within 1e-3 of a singularity is refused, none beyond 2e-2.
    assert refused >= sum(1 for s, *_ in states if s <= 1e-3)
