"""The Delta's kinematics of a robot file in 50-digit arithmetic (mpmath), by a route of its own:
the motor angle from the mechanism issue's closed form (`θ = atan2(e2, e1) + branch·acos(K/ρ)`),
each row of `J⁻¹` from the rod's length held constant (`∂θ/∂B = uᵀ/(u·∂E/∂θ)`, `u = B - E`), and
the actuators' accelerations at rest by differentiating `q(C + v t)` twice in time. The
yardstick of the Delta's platform motion from its actuators' (docs/embedding.md); it shares with
the kernels only the description's meaning (docs/mechanisms.md)."""

from __future__ import annotations

from mpmath import mp, mpf

from exact import cross, dot, vec

mp.dps = 50


def axes(arm):
    """`r`, `h` (the crank's zero, orthogonal to `r`) and `k = r × h`, unit."""
    r = vec(arm["axis"])
    r = [x / mp.sqrt(dot(r, r)) for x in r]
    h = vec(arm["zero"])
    along = dot(h, r)
    h = [a - along * b for a, b in zip(h, r)]
    h = [x / mp.sqrt(dot(h, h)) for x in h]
    return r, h, cross(r, h)


class ExactDelta:
    """The Delta of the robot file `doc` (a parsed TOML) at the centre position `x`."""

    def __init__(self, doc: dict, x):
        self.doc, self.x = doc, vec(x)
        self.arms = doc["arms"]

    def ball(self, arm, x):
        return [a + b for a, b in zip(x, vec(arm["platform"]))]

    def angles(self, x=None):
        """The motors' readings `q_i = θ_i + o_i` (rad), `θ_i` wrapped into `(−π, π]`."""
        x = self.x if x is None else vec(x)
        out = []
        for arm in self.arms:
            r, h, k = axes(arm)
            d = [b - a for b, a in zip(self.ball(arm, x), vec(arm["base"]))]
            e1, e2 = dot(d, h), dot(d, k)
            c, length = mpf(arm["crank"]["length"]), mpf(arm["rod"]["length"])
            ratio = (dot(d, d) + c * c - length * length) / (2 * c * mp.sqrt(e1 * e1 + e2 * e2))
            theta = mp.atan2(e2, e1) + arm.get("branch", 1) * mp.acos(ratio)
            theta = (theta + mp.pi) % (2 * mp.pi) - mp.pi
            out.append(theta + mpf(arm.get("encoder_offset", 0.0)))
        return out

    @property
    def jinv(self):
        """`∂q/∂x`: the rod's length fixed, `u·(∂B - ∂E/∂θ ∂θ) = 0`, so row `i` is
        `uᵀ/(u·t)` with `u = B - E` and `t = ∂E/∂θ = c (−sin θ h + cos θ k)`."""
        rows = []
        for arm, q in zip(self.arms, self.angles()):
            r, h, k = axes(arm)
            theta = q - mpf(arm.get("encoder_offset", 0.0))
            c = mpf(arm["crank"]["length"])
            along = [mp.cos(theta) * a + mp.sin(theta) * b for a, b in zip(h, k)]
            tangent = [c * (-mp.sin(theta) * a + mp.cos(theta) * b) for a, b in zip(h, k)]
            elbow = [a + c * b for a, b in zip(vec(arm["base"]), along)]
            u = [b - e for b, e in zip(self.ball(arm, self.x), elbow)]
            rows.append([x / dot(u, tangent) for x in u])
        return rows

    def hold(self):
        """`det(J⁻¹)² / Π |row|²`, the measure the kernels' hold term reports."""
        rows = self.jinv
        return mp.det(mp.matrix(rows)) ** 2 / mp.fprod(dot(row, row) for row in rows)

    def at_rest(self, v):
        """`q̈` at zero platform acceleration and velocity `v`: `d²/dt² q(x + v t)` at 0."""
        v = vec(v)
        return [mp.diff(lambda t, i=i: self.angles([a + b * t for a, b in zip(self.x, v)])[i],
                        0, 2) for i in range(3)]

    def actuators(self, v, a):
        """`q`, `q̇ = J⁻¹ v` and `q̈ = J⁻¹ a + q̈(v, 0)`."""
        jinv = mp.matrix(self.jinv)
        qd = list(jinv * mp.matrix(vec(v)))
        qdd = [x + y for x, y in zip(jinv * mp.matrix(vec(a)), self.at_rest(v))]
        return self.angles(), qd, qdd


def joint_state(doc: dict, q, qd, qdd, guess):
    """The centre's position, velocity and acceleration whose motors read `q`, `q̇`, `q̈`: the
    position by Newton's method in 50 digits from `guess`, then `q̇ = J⁻¹ v` and
    `q̈ = J⁻¹ a + q̈(v, 0)` solved for `v` and `a`."""
    q = vec(q)
    x = list(mp.findroot(lambda *x: [a - b for a, b in zip(ExactDelta(doc, x).angles(), q)],
                         vec(guess), tol=mpf(10) ** -45))
    delta = ExactDelta(doc, x)
    jinv = mp.matrix(delta.jinv)
    v = list(mp.lu_solve(jinv, mp.matrix(vec(qd))))
    a = list(mp.lu_solve(jinv, mp.matrix([mpf(y) - b for y, b in zip(qdd, delta.at_rest(v))])))
    return x, v, a
