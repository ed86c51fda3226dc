"""The Delta's accuracy contract near its parallel singularity (docs/embedding.md): what
`c5 eval` serves, from the centre's motion or from the motors' readings, and what `c5 forward`
serves, is within its stated bound of a 50-digit reference (exact_delta.py), or refused naming
the arms' hold, its value and the bound it misses.

States on rays from a point below home to where the arms lose their hold (`det J⁻¹` changes
sign, found by bisection in 50 digits), at relative distances 3e-2 to 1e-7 before it, the
motion at random: holds `det(J⁻¹)²/Π|row|²` from about 1e-2 down to 1e-12."""

from __future__ import annotations

import json
import subprocess
import tomllib

import numpy as np
from mpmath import mp, mpf

from conftest import ROOT
from exact_delta import ExactDelta, ExactDeltaDynamics, joint_state
from rus_geometry import axes

DELTA = ROOT / "docs" / "delta.toml"
# The runtime's bounds (`c5_runtime::singularity::HOLD_RATIO_TOLERANCE`,
# `c5_runtime::legged::JOINT_STATE_HOLD_RATIO_TOLERANCE`).
HOLD_RATIO_TOLERANCE = 1e-8
JOINT_STATE_HOLD_RATIO_TOLERANCE = 1e-4
# The worst relative errors docs/embedding.md states where served.
STATED = {"q": 5e-16, "jinv": 5e-15, "J": 2e-12, "Γ": 5e-12, "forward": 3e-12,
          "position from q": 3e-15, "velocity from q̇": 4e-13, "acceleration from q̈": 2e-11}


def eval_lines(c5_program, lines: list[dict], command: str = "eval") -> list[dict]:
    """`c5 eval` (or `command`) of the Delta on `lines`: an answer or an `error` each (a
    refused line makes the exit status nonzero)."""
    done = subprocess.run([str(c5_program), command, "--robot", str(DELTA)], text=True,
                          input="".join(json.dumps(line) + "\n" for line in lines),
                          capture_output=True)
    return [json.loads(line) for line in done.stdout.splitlines()]


def relative(served, exact) -> float:
    exact = [mpf(x) for x in np.ravel(np.array(exact, dtype=object))]
    return float(max(abs(mpf(s) - e) for s, e in zip(np.ravel(served), exact))
                 / max(abs(e) for e in exact))


def within_reach(doc, x, margin=1e-6) -> bool:
    """Every arm's `1 - (K/ρ)²` above `margin` at the centre `x` (the mechanism issue's
    formulas)."""
    for arm in doc["arms"]:
        r, h, k = axes(arm)
        d = np.asarray(x) + arm["platform"] - np.asarray(arm["base"], float)
        c, length = arm["crank"]["length"], arm["rod"]["length"]
        ratio = (d @ d + c * c - length * length) / (2 * c * np.hypot(d @ h, d @ k))
        if not 1 - ratio * ratio > margin:
            return False
    return True


def near_singular_states(doc, seed: int, rays: int,
                         distances=(3e-2, 1e-2, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6, 1e-7)):
    """Centres `distances` (relative) before the arms lose their hold on `rays` random rays,
    with a random motion each."""
    rng = np.random.default_rng(seed)
    start = np.array([0.0, 0.0, -0.5])

    def det(x):
        return mp.det(mp.matrix(ExactDelta(doc, x).jinv))

    found = 0
    while found < rays:
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        previous = None
        for s in np.linspace(0.05, 0.7, 131):
            if not within_reach(doc, start + s * direction):
                break
            d = det(start + s * direction)
            if previous is not None and previous[1] * d < 0:
                lo, hi = mpf(previous[0]), mpf(s)
                for _ in range(60):
                    mid = (lo + hi) / 2
                    if det(start + float(mid) * direction) * previous[1] > 0:
                        lo = mid
                    else:
                        hi = mid
                for distance in distances:
                    yield (start + float(lo) * (1 - distance) * direction,
                           rng.uniform(-0.5, 0.5, 3), rng.uniform(-5, 5, 3))
                found += 1
                break
            previous = (s, d)


def test_the_delta_serves_within_the_bound_or_refuses(c5_program):
    doc = tomllib.loads(DELTA.read_text())
    states = list(near_singular_states(doc, 11, 3))
    exact = [ExactDelta(doc, x) for x, _, _ in states]
    dynamics = ExactDeltaDynamics(doc)
    exact_torques = [dynamics.gamma(*state) for state in states]
    torques = [[float(t) for t in gamma] for gamma in exact_torques]
    joints = [e.actuators(v, a) for e, (_, v, a) in zip(exact, states)]
    posed = eval_lines(c5_program, [{"pose": list(x), "velocity": list(v),
                                     "acceleration": list(a)} for x, v, a in states])
    read = eval_lines(c5_program, [{"q": [float(t) for t in q], "qd": [float(t) for t in qd],
                                    "qdd": [float(t) for t in qdd]} for q, qd, qdd in joints])
    forward = eval_lines(c5_program, [{"pose": list(x), "velocity": list(v), "gamma": g}
                                      for (x, v, _), g in zip(states, torques)], "forward")
    worst = dict.fromkeys(STATED, 0.0)
    refused = motion_refused = 0
    for state, e, exact_gamma, gamma, (q, qd, qdd), pose_line, joint_line, forward_line in zip(
            states, exact, exact_torques, torques, joints, posed, read, forward):
        hold = float(e.hold())
        if "error" in pose_line:
            assert "arms' hold" in pose_line["error"], pose_line["error"]
            assert hold < 1.01 * HOLD_RATIO_TOLERANCE, (hold, pose_line["error"])
            assert "arms' hold" in forward_line.get("error", ""), forward_line
            refused += 1
            continue
        assert hold > 0.99 * HOLD_RATIO_TOLERANCE, hold
        jinv = mp.matrix(e.jinv)
        worst["q"] = max(worst["q"], relative(pose_line["q"], e.angles()))
        worst["jinv"] = max(worst["jinv"], relative(pose_line["jinv"], e.jinv))
        worst["J"] = max(worst["J"], relative(pose_line["jacobian"], (jinv ** -1).tolist()))
        worst["Γ"] = max(worst["Γ"], relative(pose_line["gamma"], exact_gamma))
        worst["forward"] = max(worst["forward"], relative(
            forward_line["acceleration"], dynamics.forward(state[0], state[1], gamma)))
        if "error" in joint_line:
            assert "platform motion from the actuators" in joint_line["error"], joint_line
            assert "arms' hold" in joint_line["error"], joint_line["error"]
            assert hold < 1.01 * JOINT_STATE_HOLD_RATIO_TOLERANCE, (hold, joint_line["error"])
            motion_refused += 1
            continue
        assert hold > 0.99 * JOINT_STATE_HOLD_RATIO_TOLERANCE, hold
        # The exact motion of the readings as served (rounded to f64), from the served position.
        floats = [[float(t) for t in xs] for xs in (q, qd, qdd)]
        x, v, a = joint_state(doc, *floats, guess=joint_line["pose"])
        worst["position from q"] = max(worst["position from q"], relative(joint_line["pose"], x))
        worst["velocity from q̇"] = max(worst["velocity from q̇"],
                                        relative(joint_line["velocity"], v))
        worst["acceleration from q̈"] = max(worst["acceleration from q̈"],
                                            relative(joint_line["acceleration"], a))
    print("delta: worst relative errors where served", worst, "motion refused", motion_refused,
          "refused", refused)
    for what, error in worst.items():
        assert error < 10 * STATED[what], (what, error)
    assert motion_refused >= 6 and refused >= 3, (motion_refused, refused)
