"""The rotary hexapod's and the Delta's geometry straight from their robot files, written from
the mechanism issue's formulas (docs/mechanisms.md) and sharing nothing with the Rust code or
the exported files: the crank angle of a ball's position, and every body's centre of mass,
frame and inertia at a pose. The export's tests hold Pinocchio and MuJoCo to it."""

from __future__ import annotations

import numpy as np

from exported import rotation


def axes(leg):
    r = np.array(leg["axis"], float)
    r /= np.linalg.norm(r)
    h = np.array(leg["zero"], float)
    h -= (h @ r) * r
    h /= np.linalg.norm(h)
    return r, h, np.cross(r, h)


def reach(leg, ball):
    """`atan2(e2, e1)` and `K/ρ`: the ball's direction about the motor's axis, and the cosine
    of the crank's angle from it."""
    r, h, k = axes(leg)
    d = np.asarray(ball, float) - leg["base"]
    e1, e2 = d @ h, d @ k
    c, length = leg["crank"]["length"], leg["rod"]["length"]
    return np.arctan2(e2, e1), (d @ d + c * c - length * length) / (2 * c * np.hypot(e1, e2))


def crank_angle(leg, ball):
    """`θ = atan2(e2, e1) + branch·acos(K/ρ)`, wrapped into `(−π, π]`."""
    direction, ratio = reach(leg, ball)
    theta = direction + leg["branch"] * np.arccos(ratio)
    return (theta + np.pi) % (2 * np.pi) - np.pi


class RusRobot:
    """A robot file of either mechanism: `pose` is `[α β γ xc yc zc]` for the rotary hexapod,
    `[xc yc zc]` for the Delta."""

    def __init__(self, doc: dict):
        self.doc = doc
        self.delta = doc["mechanism"] == "delta"
        self.legs = doc["arms"] if self.delta else doc["legs"]

    def placement(self, pose):
        if self.delta:
            return np.eye(3), np.asarray(pose, float)
        return rotation(pose), np.asarray(pose[3:], float)

    def balls(self, pose):
        rot, centre = self.placement(pose)
        return [centre + rot @ np.array(leg["platform"], float) for leg in self.legs]

    def reach_terms(self, pose):
        """`1 − (K/ρ)²` of each leg: the squared sine of the angle between its crank and its
        rod, zero where they align."""
        return np.array([1 - reach(leg, b)[1] ** 2 for leg, b in zip(self.legs, self.balls(pose))])

    def angles(self, pose):
        return np.array([crank_angle(leg, b) for leg, b in zip(self.legs, self.balls(pose))])

    def bodies(self, pose):
        """Every moving body as `(rotation, centre of mass, mass, inertia about it in its
        frame)`, base frame."""
        rot, centre = self.placement(pose)
        p = self.doc["platform"]
        inertia = np.zeros((3, 3))
        if "inertia" in p:
            xx, yy, zz, xy, xz, yz = p["inertia"]
            inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        out = [(rot, centre + rot @ np.array(p["centre_of_mass"], float), p["mass"], inertia)]
        for leg, ball in zip(self.legs, self.balls(pose)):
            r, h, k = axes(leg)
            theta = crank_angle(leg, ball)
            along = np.cos(theta) * h + np.sin(theta) * k
            crank = leg["crank"]
            out.append((np.column_stack([along, np.cross(r, along), r]),
                        np.asarray(leg["base"], float) + crank["com"] * along, crank["mass"],
                        np.diag(crank["inertia"])))
            elbow = np.asarray(leg["base"], float) + crank["length"] * along
            u = (ball - elbow) / np.linalg.norm(ball - elbow)
            y = np.cross(u, r)
            y /= np.linalg.norm(y)
            frame = np.column_stack([np.cross(y, u), y, u])
            rod = leg["rod"]
            half = 0.5 * rod.get("separation", 0.0)
            for offset in ([half, -half] if self.delta else [0.0]):
                out.append((frame, elbow + offset * r + rod["com"] * u, rod["mass"],
                            np.diag(rod["inertia"])))
        return out

    def potential(self, pose):
        g = np.asarray(self.doc["gravity"], float)
        return -sum(mass * (g @ com) for _, com, mass, _ in self.bodies(pose))

    def holding_torques(self, pose, step=1e-6):
        """The motor torques that hold the robot at rest at `pose`, by virtual work:
        `Γ = (∂θ/∂x)⁻ᵀ ∂U/∂x`, both derivatives by central differences."""
        x = np.asarray(pose, float)
        n = len(x)
        jinv = np.zeros((len(self.legs), n))
        grad = np.zeros(n)
        for j in range(n):
            dx = np.zeros(n)
            dx[j] = step
            jinv[:, j] = (self.angles(x + dx) - self.angles(x - dx)) / (2 * step)
            grad[j] = (self.potential(x + dx) - self.potential(x - dx)) / (2 * step)
        return np.linalg.solve(jinv.T, grad)
