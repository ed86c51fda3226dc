"""The Gough-Stewart platform (6-UPS) of a robot file in 50-digit arithmetic (mpmath), derived
by a route of its own: the bodies' velocities from the U joints' kinematics, their accelerations
by central differences in time in 50 digits along the state's motion, and the forces by the
power balance over six unit twists. The yardstick of the hexapod's accuracy near its
singularities (docs/embedding.md); it shares with the kernels only the description's meaning
(docs/mechanisms.md): `B_i = C + R p_i`, `q_i = |B_i - A_i| + encoder_offset`; the cylinder turns
on the U joint (first axis `a_i` fixed in the base, the second `∝ u × a_i`), its centre of mass
`com` from `A_i` along the leg; the rod slides in it, its centre of mass `com` back from `B_i`;
their inertias about the centre of mass in the leg frame `(y' × u, y' ∝ u × a_i, u)`."""

from __future__ import annotations

import tomllib
from pathlib import Path

from mpmath import mp, mpf

from exact import add, cross, dot, matmul, matvec, rotation, scale, transpose, vec

mp.dps = 50
STEP = mpf(10) ** -20  # in time (s): its truncation error, h², is far below 50 digits' use


def load(path: Path) -> dict:
    return tomllib.loads(Path(path).read_text())


def norm(v):
    return mp.sqrt(dot(v, v))


def unit(v):
    return scale(1 / norm(v), v)


def symmetric(six):
    xx, yy, zz, xy, xz, yz = vec(six)
    return [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]


def skew_apply(w, m):
    """`[w]× m` for a 3×3 matrix `m`."""
    return transpose([cross(w, column) for column in transpose(m)])


class Motion:
    """The platform at time `t` of the motion through the state with constant `ω̇`, `a_C`."""

    def __init__(self, pose, omega, velocity, omega_dot, acceleration):
        pose = vec(pose)
        self.r0, self.c0 = rotation(*pose[:3]), pose[3:]
        self.w, self.v = vec(omega), vec(velocity)
        self.wd, self.a = vec(omega_dot), vec(acceleration)

    def at(self, t):
        """`(R, C, ω, v_C)` at `t`, `R` to `O(t³)`: `Ṙ = [ω]× R` with `ω(t) = ω + ω̇ t`."""
        w2 = skew_apply(self.w, skew_apply(self.w, [[1, 0, 0], [0, 1, 0], [0, 0, 1]]))
        wd = skew_apply(self.wd, [[1, 0, 0], [0, 1, 0], [0, 0, 1]])
        wx = skew_apply(self.w, [[1, 0, 0], [0, 1, 0], [0, 0, 1]])
        step = [[(1 if i == j else 0) + wx[i][j] * t + (wd[i][j] + w2[i][j]) * t * t / 2
                 for j in range(3)] for i in range(3)]
        r = matmul(step, self.r0)
        c = add(self.c0, scale(t, self.v), scale(t * t / 2, self.a))
        return r, c, add(self.w, scale(t, self.wd)), add(self.v, scale(t, self.a))


def bodies(robot: dict, r, c, w, v):
    """Every body's `(mass, inertia about its centre of mass in the base frame, v_G, ω)` and
    each leg's `(q, q̇, u, sine of the U joint)`."""
    p = robot["platform"]
    s = matvec(r, vec(p.get("centre_of_mass", [0, 0, 0])))
    out = [(mpf(p["mass"]), matmul(matmul(r, symmetric(p["inertia"])), transpose(r)),
            add(v, cross(w, s)), w)]
    legs = []
    for leg in robot["legs"]:
        a_i, axis = vec(leg["base"]), unit(vec(leg["u_axis"]))
        arm = matvec(r, vec(leg["platform"]))
        b = add(c, arm)
        length = norm(add(b, scale(-1, a_i)))
        u = scale(1 / length, add(b, scale(-1, a_i)))
        v_b = add(v, cross(w, arm))
        u_dot = scale(1 / length, add(v_b, scale(-dot(u, v_b), u)))
        # The U joint: ω_leg = θ̇1 a + θ̇2 y' with y' ⟂ a, u; its part across u is u × u̇.
        across = cross(u, u_dot)
        a_perp = add(axis, scale(-dot(axis, u), u))
        y = unit(cross(u, axis))
        w_leg = add(scale(dot(across, a_perp) / dot(a_perp, a_perp), axis),
                    scale(dot(across, y), y))
        frame = transpose([cross(y, u), y, u])  # columns x', y', u
        for body, at in ((leg["cylinder"], add(a_i, scale(mpf(leg["cylinder"]["com"]), u))),
                         (leg["rod"], add(b, scale(-mpf(leg["rod"]["com"]), u)))):
            inertia = matmul(matmul(frame, [[mpf(body["inertia"][0]), 0, 0],
                                            [0, mpf(body["inertia"][1]), 0],
                                            [0, 0, mpf(body["inertia"][2])]]),
                             transpose(frame))
            out.append((mpf(body["mass"]), inertia, velocity_of(at, a_i, u, u_dot, length, w_leg,
                                                                  body is leg["rod"], v_b), w_leg))
        legs.append((length + mpf(leg.get("encoder_offset", 0)), dot(u, v_b), u,
                     norm(cross(axis, u))))
    return out, legs


def velocity_of(point, a_i, u, u_dot, length, w_leg, on_rod, v_b):
    """A leg body's point: the cylinder's turns about `A_i`; the rod's also slides with `B_i`."""
    offset = add(point, scale(-1, a_i))
    turning = cross(w_leg, offset)
    if not on_rod:
        return turning
    # The rod's point moves with B_i's motion along u and turns with the leg.
    along = scale(dot(u, v_b), u)
    return add(along, turning)


class ExactHexapod:
    """One state of a hexapod in 50 digits: `q`, `q̇`, `q̈`, `J⁻¹`, the U joints' sines, `Γ`."""

    def __init__(self, robot: dict, pose, omega=(0, 0, 0), velocity=(0, 0, 0),
                 omega_dot=(0, 0, 0), acceleration=(0, 0, 0)):
        self.robot = robot
        self.motion = Motion(pose, omega, velocity, omega_dot, acceleration)
        r, c, w, v = self.motion.at(mpf(0))
        self.now, legs = bodies(robot, r, c, w, v)
        self.q = [leg[0] for leg in legs]
        self.qd = [leg[1] for leg in legs]
        self.sines = [leg[3] for leg in legs]
        self.jinv = [cross(matvec(r, vec(leg["platform"])), l[2]) + l[2]
                     for leg, l in zip(robot["legs"], legs)]
        (self.later, later), (self.earlier, earlier) = (
            bodies(robot, *self.motion.at(t)) for t in (STEP, -STEP))
        self.qdd = [(x[1] - y[1]) / (2 * STEP) for x, y in zip(later, earlier)]
        self.pose = (r, c)

    def gamma(self):
        """`J⁻ᵀ Γ = Σ_b (∂v_G/∂V)ᵀ m (a_G - g) + (∂ω/∂V)ᵀ (I ω̇ + ω × I ω)`, then solved."""
        g = vec(self.robot.get("gravity", [0, 0, -9.81]))
        loads = []
        for (m, inertia, v_g, w), later, earlier in zip(self.now, self.later, self.earlier):
            a_g = scale(1 / (2 * STEP), add(later[2], scale(-1, earlier[2])))
            w_dot = scale(1 / (2 * STEP), add(later[3], scale(-1, earlier[3])))
            force = scale(m, add(a_g, scale(-1, g)))
            moment = add(matvec(inertia, w_dot), cross(w, matvec(inertia, w)))
            loads.append((force, moment))
        r, c = self.pose
        wrench = []
        for k in range(6):
            e = [mpf(0)] * 6
            e[k] = mpf(1)
            unit_bodies, _ = bodies(self.robot, r, c, e[:3], e[3:])
            wrench.append(sum((dot(f, b[2]) + dot(n, b[3])
                               for (f, n), b in zip(loads, unit_bodies)), mpf(0)))
        return list(mp.lu_solve(mp.matrix(transpose(self.jinv)), mp.matrix(wrench)))
