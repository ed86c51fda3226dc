"""The consistent model in 50-digit arithmetic (mpmath): the same derivation as
``reference.py`` (``m_i . (B_i - C) = 0`` differentiated twice in time, forces by the power
balance), every operation in ``mpf`` so that its results are exact to far below ``f64``'s
rounding. The yardstick of the accuracy contract (docs/embedding.md): what the ``f64`` kernels
serve must be within its bound of these numbers, or refused."""

from __future__ import annotations

from mpmath import mp, mpf

from reference import AXIS, Robot

mp.dps = 50


def vec(v):
    return [mpf(x) for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum((x * y for x, y in zip(a, b)), mpf(0))


def add(*vs):
    return [sum(c, mpf(0)) for c in zip(*vs)]


def scale(s, v):
    return [s * x for x in v]


def matvec(m, v):
    return [dot(row, v) for row in m]


def transpose(m):
    return [list(c) for c in zip(*m)]


def matmul(a, b):
    bt = transpose(b)
    return [[dot(r, c) for c in bt] for r in a]


def rotation(alpha, beta, gamma):
    ca, sa, cb, sb, cg, sg = (mp.cos(alpha), mp.sin(alpha), mp.cos(beta), mp.sin(beta),
                              mp.cos(gamma), mp.sin(gamma))
    rx = [[1, 0, 0], [0, ca, -sa], [0, sa, ca]]
    ry = [[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]]
    rz = [[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]]
    return matmul(matmul(rx, ry), rz)


def anchor(l, i):
    a = [mpf(0)] * 3
    a[[2, 2, 0, 0, 1, 1][i]] = l if i % 2 == 0 else -l
    return a


def axis(i):
    n = [mpf(0)] * 3
    n[AXIS[i]] = mpf(1)
    return n


def skew_times(s, v):
    """``-[s]x v = v x s``: how a point at ``s`` from the reference moves with ``omega``."""
    return cross(v, s)


class Exact:
    """One state of the consistent model for ``robot``, in 50 digits."""

    def __init__(self, robot: Robot, pose, omega=(0, 0, 0), velocity=(0, 0, 0),
                 omega_dot=(0, 0, 0), acceleration=(0, 0, 0)):
        self.robot = robot
        pose = vec(pose)
        self.r = rotation(*pose[:3])
        self.c = pose[3:]
        self.w, self.v = vec(omega), vec(velocity)
        self.wd, self.a = vec(omega_dot), vec(acceleration)
        l = mpf(robot.half_spacing)
        self.q, self.qd, self.qdd, self.jinv = [], [], [], []
        for i in range(6):
            k, a_i = AXIS[i], anchor(l, i)
            m = [self.r[j][k] for j in range(3)]
            md = cross(self.w, m)
            mdd = add(cross(self.wd, m), cross(self.w, md))
            d = add(self.c, scale(-1, a_i))
            q = dot(m, d) / m[k]
            qd = (dot(md, d) + dot(m, self.v) - q * md[k]) / m[k]
            qdd = (dot(mdd, d) + 2 * dot(md, self.v) + dot(m, self.a)
                   - 2 * qd * md[k] - q * mdd[k]) / m[k]
            p = add(self.c, scale(-1, add(a_i, scale(q, axis(i)))))
            self.q.append(q)
            self.qd.append(qd)
            self.qdd.append(qdd)
            self.jinv.append([x / m[k] for x in cross(m, p) + m])

    def gamma(self):
        """``(J^-1)^T gamma = sum_b Tv^T f_b + Tw^T n_b``, the generalized force of each body
        on the six unit twists, then solved."""
        rb = self.robot
        g = vec(rb.gravity)
        w, wd = self.w, self.wd
        wrench = [mpf(0)] * 6  # (moment; force) at C, base frame

        def spin(s):
            return add(cross(wd, s), cross(w, cross(w, s)))

        def body_wrench(mass, inertia_body, s, a_g):
            """The force and the moment about the body's point that moves with C's frame."""
            inertia = matmul(matmul(self.r, inertia_body), transpose(self.r))
            f = scale(mpf(mass), add(a_g, scale(-1, g)))
            n = add(matvec(inertia, wd), cross(w, matvec(inertia, w)))
            return f, n

        # The platform: v_G = v + w x s.
        s = matvec(self.r, vec(rb.platform.com))
        f, n = body_wrench(rb.platform.mass, [vec(r) for r in rb.platform.inertia], s,
                           add(self.a, spin(s)))
        moment = add(n, cross(s, f))
        for k in range(3):
            wrench[k] += moment[k]
            wrench[3 + k] += f[k]
        for i in range(6):
            n_i = axis(i)
            # The rod: v = n_i (J^-1 V)_i.
            f_rod = scale(mpf(rb.rod_masses[i]), add(scale(self.qdd[i], n_i), scale(-1, g)))
            along = dot(n_i, f_rod)
            for c in range(6):
                wrench[c] += self.jinv[i][c] * along
            # Body 2: v_G = n_i (J^-1 V)_i + w x s, omega = w.
            j = rb.joints[i]
            s = matvec(self.r, vec(j.com))
            f, n = body_wrench(j.mass, [vec(r) for r in j.inertia], s,
                               add(scale(self.qdd[i], n_i), spin(s)))
            along = dot(n_i, f)
            for c in range(6):
                wrench[c] += self.jinv[i][c] * along
            moment = add(n, cross(s, f))
            for k in range(3):
                wrench[k] += moment[k]
        return list(mp.lu_solve(mp.matrix(transpose(self.jinv)), mp.matrix(wrench)))


class ExactPaper:
    """One state of the paper model (docs/models.md, the chapter as published with its slips 1-3
    corrected) for ``robot``, in 50 digits, written from the chapter's equations: ``q`` by eq 16;
    ``J⁻¹`` by eq 22, rows ``[(n_i × P_i2)ᵀ n_iᵀ]`` with ``P_i2 = C - B_i``; ``q̈`` by the
    projection of eq 47, ``n_i · (a_C - ω × v_C + P_i2 × ω̇)``; the forces by eq 60 as Newton-Euler
    of the platform and the bodies 2 moving as points of the platform (eq 43), the rods' axial
    loads ``m_i1 (q̈_i - n_i·g)``, and ``Γ = Jᵀ W + τ``."""

    def __init__(self, robot: Robot, pose, omega=(0, 0, 0), velocity=(0, 0, 0),
                 omega_dot=(0, 0, 0), acceleration=(0, 0, 0)):
        self.robot = robot
        pose = vec(pose)
        self.r = rotation(*pose[:3])
        self.c = pose[3:]
        self.w, self.v = vec(omega), vec(velocity)
        self.wd, self.a = vec(omega_dot), vec(acceleration)
        l = mpf(robot.half_spacing)
        twist = self.w + self.v
        spatial = add(self.a, scale(-1, cross(self.w, self.v)))
        self.q, self.p, self.qd, self.qdd, self.jinv = [], [], [], [], []
        for i in range(6):
            k, a_i, n = AXIS[i], anchor(l, i), axis(i)
            m = [self.r[j][k] for j in range(3)]
            q = dot(m, add(self.c, scale(-1, a_i))) / m[k]
            p = add(self.c, scale(-1, add(a_i, scale(q, n))))
            row = cross(n, p) + n
            self.q.append(q)
            self.p.append(p)
            self.jinv.append(row)
            self.qd.append(dot(row, twist))
            self.qdd.append(dot(n, add(spatial, cross(p, self.wd))))

    def gamma(self):
        rb = self.robot
        g = vec(rb.gravity)
        w, wd = self.w, self.wd
        wrench = [mpf(0)] * 6  # (moment; force) at C, base frame

        def add_body(mass, inertia_body, offset):
            """A body turning with the platform, its centre of mass at ``C + offset``."""
            a_g = add(self.a, cross(wd, offset), cross(w, cross(w, offset)))
            f = scale(mpf(mass), add(a_g, scale(-1, g)))
            inertia = matmul(matmul(self.r, [vec(r) for r in inertia_body]), transpose(self.r))
            n = add(matvec(inertia, wd), cross(w, matvec(inertia, w)), cross(offset, f))
            for k in range(3):
                wrench[k] += n[k]
                wrench[3 + k] += f[k]

        add_body(rb.platform.mass, rb.platform.inertia, matvec(self.r, vec(rb.platform.com)))
        for i, j in enumerate(rb.joints):
            add_body(j.mass, j.inertia, add(scale(-1, self.p[i]), matvec(self.r, vec(j.com))))
        tau = [mpf(rb.rod_masses[i]) * (self.qdd[i] - dot(axis(i), g)) for i in range(6)]
        wrench_share = mp.lu_solve(mp.matrix(transpose(self.jinv)), mp.matrix(wrench))
        return [wrench_share[i] + tau[i] for i in range(6)]


MODELS = {"consistent": Exact, "paper": ExactPaper}


def acceleration_map(robot: Robot, pose, omega=(0, 0, 0), velocity=(0, 0, 0), model=Exact):
    """``Γ`` at zero acceleration and ``C = ∂Γ/∂(ω̇; a_C)``: the forces are affine in the
    acceleration, so six differences of exact evaluations give ``C`` exactly."""
    bias = model(robot, pose, omega, velocity).gamma()
    columns = []
    for j in range(6):
        e = [0] * 6
        e[j] = 1
        g = model(robot, pose, omega, velocity, e[:3], e[3:]).gamma()
        columns.append([x - b for x, b in zip(g, bias)])
    return bias, mp.matrix(transpose(columns))


def forward_dynamics(robot: Robot, pose, omega, velocity, gamma, model=Exact):
    """``(omega_dot; acceleration)``: the forces are affine in the acceleration."""
    bias, c = acceleration_map(robot, pose, omega, velocity, model)
    rhs = [mpf(x) - b for x, b in zip(gamma, bias)]
    return list(mp.lu_solve(c, mp.matrix(rhs)))


def task_inertia(robot: Robot, pose, model=Exact):
    """``M_x`` of ``J⁻ᵀ Γ = M_x (ω̇; a_C) + h``: the wrench at ``C`` per unit acceleration."""
    _, c = acceleration_map(robot, pose, model=model)
    return mp.matrix(model(robot, pose).jinv).T * c


def task_bias(robot: Robot, pose, omega, velocity, model=Exact):
    """``h = J⁻ᵀ Γ(X, V, 0)``: the wrench at ``C`` the motion needs at zero acceleration."""
    bias = model(robot, pose, omega, velocity).gamma()
    return list(mp.matrix(model(robot, pose).jinv).T * mp.matrix(bias))


def joint_state(robot: Robot, q, qd=(0,) * 6, qdd=(0,) * 6, guess=None, model=Exact):
    """The pose, twist and acceleration whose actuators are at ``q``, ``q̇``, ``q̈``: eq 16
    solved for the pose by Newton's method in 50 digits from ``guess`` (a pose near the one
    sought), then ``q̇ = J⁻¹ V`` and ``q̈ = J⁻¹ A + q̈(V, 0)`` solved for ``V`` and ``A``."""
    q = vec(q)

    def residual(*pose):
        return [x - y for x, y in zip(model(robot, pose).q, q)]

    pose = list(mp.findroot(residual, vec(guess), tol=mpf(10) ** -45))
    jinv = mp.matrix(model(robot, pose).jinv)
    twist = list(mp.lu_solve(jinv, mp.matrix(vec(qd))))
    at_rest = model(robot, pose, twist[:3], twist[3:]).qdd
    accel = list(mp.lu_solve(jinv, mp.matrix([mpf(x) - b for x, b in zip(qdd, at_rest)])))
    return pose, twist, accel


def joint_inertia(robot: Robot, pose, model=Exact):
    """``M_q = ∂Γ/∂q̈ = C J``, at the pose the actuators give."""
    _, c = acceleration_map(robot, pose, model=model)
    return c * mp.matrix(model(robot, pose).jinv) ** -1


def central(f, x, h):
    """``∂f/∂x`` by central differences in 50 digits, row output, column component of ``x``.
    With ``h`` far below ``f64``'s resolution and far above 50 digits' rounding, both the
    truncation (``h²``) and the rounding (``10⁻⁵⁰/h``) are far below what ``f64`` resolves."""
    columns = []
    for j in range(len(x)):
        up, down = vec(x), vec(x)
        up[j] += h
        down[j] -= h
        columns.append([(a - b) / (2 * h) for a, b in zip(f(up), f(down))])
    return transpose(columns)
