"""The consistent model in numpy, derived again from the mechanism of docs/models.md by another route than the Rust
code: ``Q_i1`` from ``m_i . (B_i - C) = 0`` differentiated twice in time, and the forces by the
power balance ``gamma . qd = sum over bodies of f . v_G + n . omega`` for the six unit twists.
It shares nothing with the generator or the nalgebra reference but the mechanism's definition.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

AXIS = [0, 0, 1, 1, 2, 2]
"""The base axis ``n_i`` of segment ``i`` (0-based): x, x, y, y, z, z."""


@dataclass
class Body:
    mass: float
    com: np.ndarray  # platform frame, from C (platform) or from B_i (body 2)
    inertia: np.ndarray  # about the centre of mass, platform frame


@dataclass
class Robot:
    half_spacing: float
    gravity: np.ndarray
    platform: Body
    rod_masses: list[float]
    joints: list[Body]

    @staticmethod
    def load(path: Path) -> "Robot":
        doc = tomllib.loads(Path(path).read_text())

        def body(b: dict) -> Body:
            return Body(b["mass"], np.array(b.get("com", [0.0] * 3)), np.array(b["inertia"]))

        return Robot(
            half_spacing=doc["half_spacing"],
            gravity=np.array(doc["gravity"]),
            platform=body(doc["platform"]),
            rod_masses=[s["rod"]["mass"] for s in doc["segments"]],
            joints=[body(s["joint"]) for s in doc["segments"]],
        )


def rotation(alpha: float, beta: float, gamma: float) -> np.ndarray:
    """``R = Rx(alpha) Ry(beta) Rz(gamma)`` as a product of elementary rotations."""
    ca, sa, cb, sb, cg, sg = (np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta),
                              np.cos(gamma), np.sin(gamma))
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]])
    return rx @ ry @ rz


def anchor(l: float, i: int) -> np.ndarray:
    """``A_i``: the actuator of segments 1-2 along x at z = +-L, 3-4 along y at x = +-L, 5-6
    along z at y = +-L."""
    a = np.zeros(3)
    a[[2, 2, 0, 0, 1, 1][i]] = l if i % 2 == 0 else -l
    return a


def axis(i: int) -> np.ndarray:
    n = np.zeros(3)
    n[AXIS[i]] = 1.0
    return n


def skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


class Model:
    """One state of the consistent model for ``robot``."""

    def __init__(self, robot: Robot, pose, omega=(0, 0, 0), velocity=(0, 0, 0),
                 omega_dot=(0, 0, 0), acceleration=(0, 0, 0)):
        self.robot = robot
        self.r = rotation(*pose[:3])
        self.c = np.asarray(pose[3:], dtype=float)
        self.w, self.v = np.asarray(omega, float), np.asarray(velocity, float)
        self.wd, self.a = np.asarray(omega_dot, float), np.asarray(acceleration, float)
        l = robot.half_spacing
        # m_i . (A_i + Q n_i - C) = 0, so Q m_ik = m_i . (C - A_i), differentiated twice with
        # m' = w x m, m'' = wd x m + w x (w x m).
        self.q, self.qd, self.qdd, self.jinv = (np.zeros(6), np.zeros(6), np.zeros(6),
                                                np.zeros((6, 6)))
        for i in range(6):
            k, a_i = AXIS[i], anchor(l, i)
            m = self.r[:, k]
            md = np.cross(self.w, m)
            mdd = np.cross(self.wd, m) + np.cross(self.w, md)
            d = self.c - a_i
            self.q[i] = m @ d / m[k]
            self.qd[i] = (md @ d + m @ self.v - self.q[i] * md[k]) / m[k]
            self.qdd[i] = (mdd @ d + 2 * md @ self.v + m @ self.a
                           - 2 * self.qd[i] * md[k] - self.q[i] * mdd[k]) / m[k]
            p = self.c - (a_i + self.q[i] * axis(i))
            self.jinv[i] = np.concatenate([np.cross(m, p), m]) / m[k]

    def _bodies(self):
        """Each body as (mass, inertia about its centre of mass in the base frame, centre of
        mass offset s from the point it moves with, the classical acceleration of that centre,
        and how its centre's velocity and its angular velocity follow a platform twist:
        ``v_G = Tv V``, ``omega = Tw V``)."""
        rb = self.robot
        w, wd = self.w, self.wd
        top = np.hstack([np.eye(3), np.zeros((3, 3))])
        none = np.zeros((3, 6))

        def spin(s):
            return np.cross(wd, s) + np.cross(w, np.cross(w, s))

        s = self.r @ rb.platform.com
        yield (rb.platform.mass, self.r @ rb.platform.inertia @ self.r.T,
               self.a + spin(s), np.hstack([-skew(s), np.eye(3)]), top)
        for i in range(6):
            n = axis(i)
            along = np.outer(n, self.jinv[i])  # Q_i' n_i = n_i (J^-1 V)_i
            yield rb.rod_masses[i], np.zeros((3, 3)), self.qdd[i] * n, along, none
            j = rb.joints[i]
            s = self.r @ j.com
            yield (j.mass, self.r @ j.inertia @ self.r.T, self.qdd[i] * n + spin(s),
                   along - skew(s) @ top, top)

    def gamma(self) -> np.ndarray:
        """Actuator forces: ``(J^-1)^T gamma = sum_b Tv^T f_b + Tw^T n_b``."""
        g = self.robot.gravity
        w = np.zeros(6)
        for mass, inertia, a_g, tv, tw in self._bodies():
            f = mass * (a_g - g)
            n = inertia @ self.wd + np.cross(self.w, inertia @ self.w)
            w += tv.T @ f + tw.T @ n
        return np.linalg.solve(self.jinv.T, w)


def forward_dynamics(robot: Robot, pose, omega, velocity, gamma) -> np.ndarray:
    """``(omega_dot; acceleration)``: the forces are affine in the acceleration, so six unit
    accelerations and one zero one give the matrix and the bias to solve."""
    bias = Model(robot, pose, omega, velocity).gamma()
    columns = []
    for j in range(6):
        e = np.zeros(6)
        e[j] = 1.0
        columns.append(Model(robot, pose, omega, velocity, e[:3], e[3:]).gamma() - bias)
    return np.linalg.solve(np.array(columns).T, np.asarray(gamma) - bias)
