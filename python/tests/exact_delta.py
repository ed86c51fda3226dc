"""The Delta of a robot file in 50-digit arithmetic (mpmath), by a route of its own: the motor
angle from the mechanism issue's closed form (`θ = atan2(e2, e1) + branch·acos(K/ρ)`), each row
of `J⁻¹` from the rod's length held constant (`∂θ/∂B = uᵀ/(u·∂E/∂θ)`, `u = B - E`), the
actuators' accelerations at rest by differentiating `q(C + v t)` twice in time, and the torques
by virtual power ([`ExactDeltaDynamics`]). The yardstick of the Delta's accuracy near the arms'
loss of hold (docs/embedding.md); it shares with the kernels only the description's meaning
(docs/mechanisms.md)."""

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


def _frame(columns):
    """The 3×3 matrix whose columns are `columns`."""
    return [[columns[j][i] for j in range(3)] for i in range(3)]


class ExactDeltaDynamics:
    """The Delta's motor torques in 50 digits by virtual power, sharing nothing with the
    kernels' derivation: every moving body's pose from the description's meaning (the crank's
    frame `(x'', r × x'', r)`, `x'' = cos θ h + sin θ k`; each of the parallelogram's rods from
    `E ± (w/2) r` along `u = (B - E)/L`, its frame `(y' × u, y' ∝ u × r, u)`), its velocity and
    acceleration by differences in time along `C(t) = C + v t + a t²/2` (at 90 digits, steps
    1e-25 and 1e-20), and `Γ = J⁻ᵀ W` with `W_k` the bodies' Newton-Euler wrenches' power on
    the unit velocity `e_k` of the centre."""

    def __init__(self, doc: dict):
        self.doc = doc
        self.gravity = vec(doc["gravity"])

    def bodies(self, x):
        """Every moving body as `(R, centre of mass, mass, inertia about it in its frame)`."""
        delta = ExactDelta(self.doc, x)
        platform = self.doc["platform"]
        eye = [[mpf(int(i == j)) for j in range(3)] for i in range(3)]
        zero = [[mpf(0)] * 3 for _ in range(3)]
        out = [(eye, [a + b for a, b in zip(delta.x, vec(platform["centre_of_mass"]))],
                mpf(platform["mass"]), zero)]
        for arm, q in zip(self.doc["arms"], delta.angles()):
            r, h, k = axes(arm)
            theta = q - mpf(arm.get("encoder_offset", 0.0))
            along = [mp.cos(theta) * a + mp.sin(theta) * b for a, b in zip(h, k)]
            crank, rod = arm["crank"], arm["rod"]
            base = vec(arm["base"])
            out.append((_frame([along, cross(r, along), r]),
                        [a + mpf(crank["com"]) * b for a, b in zip(base, along)],
                        mpf(crank["mass"]), [[mpf(crank["inertia"][i]) * (i == j)
                                              for j in range(3)] for i in range(3)]))
            elbow = [a + mpf(crank["length"]) * b for a, b in zip(base, along)]
            d = [b - e for b, e in zip(delta.ball(arm, delta.x), elbow)]
            u = [t / mp.sqrt(dot(d, d)) for t in d]
            y = cross(u, r)
            y = [t / mp.sqrt(dot(y, y)) for t in y]
            frame = _frame([cross(y, u), y, u])
            inertia = [[mpf(rod["inertia"][i]) * (i == j) for j in range(3)] for i in range(3)]
            half = mpf(rod.get("separation", 0.0)) / 2
            for side in (half, -half):
                centre = [e + side * a + mpf(rod["com"]) * b for e, a, b in zip(elbow, r, u)]
                out.append((frame, centre, mpf(rod["mass"]), inertia))
        return out

    def gamma(self, x, v, a):
        """`Γ` for the centre's position `x`, velocity `v` and acceleration `a`."""
        x, v, a = vec(x), vec(v), vec(a)
        with mp.workdps(90):
            h1, h2 = mpf(10) ** -25, mpf(10) ** -20

            def at(t):
                return self.bodies([p + w * t + b * t * t / 2 for p, w, b in zip(x, v, a)])

            def rates(before, after, now, step):
                """`ω` (base frame) of each body from its frames `step` before and after."""
                out = []
                for (r0, _, _, _), (r1, _, _, _), (r, _, _, _) in zip(before, after, now):
                    dr = [[(r1[i][j] - r0[i][j]) / (2 * step) for j in range(3)]
                          for i in range(3)]
                    w = [[sum(dr[i][m] * r[j][m] for m in range(3)) for j in range(3)]
                         for i in range(3)]
                    out.append([w[2][1], w[0][2], w[1][0]])
                return out

            now = at(0)
            omega = rates(at(-h1), at(h1), now, h1)
            omega_dot = [[(p - m) / (2 * h2) for p, m in zip(wp, wm)] for wp, wm in zip(
                rates(at(h2 - h1), at(h2 + h1), at(h2), h1),
                rates(at(-h2 - h1), at(-h2 + h1), at(-h2), h1))]
            ahead, behind = at(h2), at(-h2)
            accel = [[(p - 2 * c + m) / (h2 * h2) for p, c, m in zip(b1[1], b0[1], b2[1])]
                     for b1, b0, b2 in zip(ahead, now, behind)]
            power = []
            for k in range(3):
                step = [mpf(int(j == k)) * h1 for j in range(3)]
                up = self.bodies([p + s for p, s in zip(x, step)])
                down = self.bodies([p - s for p, s in zip(x, step)])
                virtual = rates(down, up, now, h1)
                total = mpf(0)
                for b, (r, _, mass, inertia) in enumerate(now):
                    v_k = [(p - m) / (2 * h1) for p, m in zip(up[b][1], down[b][1])]
                    world = [[sum(r[i][m] * inertia[m][n] * r[j][n] for m in range(3)
                                  for n in range(3)) for j in range(3)] for i in range(3)]
                    w, wd = omega[b], omega_dot[b]
                    moment = [a + c for a, c in zip(
                        [dot(row, wd) for row in world],
                        cross(w, [dot(row, w) for row in world]))]
                    force = [mass * (ab - g) for ab, g in zip(accel[b], self.gravity)]
                    total += dot(force, v_k) + dot(moment, virtual[b])
                power.append(total)
            jinv = mp.matrix(ExactDelta(self.doc, x).jinv)
            torques = list(mp.lu_solve(jinv.T, mp.matrix(power)))
        return [+t for t in torques]

    def forward(self, x, v, gamma):
        """The centre's acceleration under the torques `gamma`: `Γ` is affine in `a`."""
        bias = self.gamma(x, v, [0, 0, 0])
        columns = [[g - b for g, b in zip(self.gamma(x, v, [int(j == k) for j in range(3)]),
                                          bias)] for k in range(3)]
        mass = mp.matrix([[columns[k][i] for k in range(3)] for i in range(3)])
        return list(mp.lu_solve(mass, mp.matrix([mpf(g) - b for g, b in zip(gamma, bias)])))
