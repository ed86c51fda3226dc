"""The inverse dynamics of the C5 robot, both models, written with SymPy and printed as C.

The baseline a user would pick instead of c5-codegen: the same equations as
`codegen/src/model/{geometry,bodies,paper,consistent}.rs` (the same formulations: Euler's
equations in the platform frame, one point-acceleration map, the consistent model in the
platform frame with its 3x3 pair system, the paper model regrouped), the default robot folded
in, then `sympy.cse` and `sympy.ccode`; and the paper model leg by leg as the chapter computes
it (`sympy_paper_by_legs.c`), what a user transcribing the chapter gets. Regenerate with

    pip install sympy==1.14.0
    python3 tests/c-output/sympy/generate.py

which rewrites the `sympy_*.c` files beside this file and prints the counted
operations of each.
"""

import pathlib
import sympy as sp

L = sp.Float(0.2)
G = sp.Matrix([0, 0, -9.81])
AXIS = [0, 0, 1, 1, 2, 2]
ANCHOR = [(2, 1), (2, -1), (0, 1), (0, -1), (1, 1), (1, -1)]
M_PLATFORM, M_ROD, M_JOINT = 10.0, 2.0, 1.67
I_PLATFORM = sp.diag(0.375, 0.1875, 0.1875)


def i_joint(i):
    d = [0.0084] * 3
    d[AXIS[i]] = 0.00167
    return sp.diag(*d)


def unit(k):
    e = sp.zeros(3, 1)
    e[k] = 1
    return e


def anchor(i):
    k, sign = ANCHOR[i]
    return unit(k) * (sign * L)


def cross(a, b):
    return a.cross(b)


def tilde(v):
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


# Inputs.
alpha, beta, gamma, xc, yc, zc = sp.symbols("alpha beta gamma xc yc zc")
wx, wy, wz, vx, vy, vz = sp.symbols("wx wy wz vx vy vz")
wdx, wdy, wdz, ax, ay, az = sp.symbols("wdx wdy wdz ax ay az")
omega, v_c = sp.Matrix([wx, wy, wz]), sp.Matrix([vx, vy, vz])
omega_dot, a_c = sp.Matrix([wdx, wdy, wdz]), sp.Matrix([ax, ay, az])
C = sp.Matrix([xc, yc, zc])

# Eq 15.
sa, ca, sb, cb, sg, cg = (sp.sin(alpha), sp.cos(alpha), sp.sin(beta), sp.cos(beta),
                          sp.sin(gamma), sp.cos(gamma))
R = sp.Matrix([
    [cb * cg, -cb * sg, sb],
    [sg * ca + cg * sb * sa, ca * cg - sa * sb * sg, -cb * sa],
    [sg * sa - cg * sb * ca, sa * cg + ca * sb * sg, cb * ca],
])
# Eq 16 and eq 27.
Q, P = [], []
for i in range(6):
    k, m, a = AXIS[i], R[:, AXIS[i]], anchor(i)
    q = C[k] - a[k] + sum(m[j] * (C[j] - a[j]) for j in range(3) if j != k) / m[k]
    Q.append(q)
    P.append(C - a - unit(k) * q)

# Euler's equations in the platform frame, shared by the bodies that turn with the platform.
w_p, wd_p = R.T * omega, R.T * omega_dot


def euler(inertia):
    return inertia * wd_p + cross(w_p, inertia * w_p)


def step6(k):
    # Eq 62: Gamma = Pi1^T J1^T K.
    x = lambda i: P[i - 1][0]
    y = lambda i: P[i - 1][1]
    z = lambda i: P[i - 1][2]
    e = lambda i: sp.Matrix([1 if j == i - 1 else 0 for j in range(6)])
    al = (e(5) - e(6)) / (y(6) - y(5))
    be = (e(1) - e(2)) / (z(2) - z(1))
    ga = (e(3) - e(4)) / (x(4) - x(3))
    u = al * (z(1) - z(3)) + ga * (x(3) - x(1)) + e(3)
    w = al * (y(5) - y(1)) + be * (x(1) - x(5)) + e(5)
    pi1 = sp.Matrix.hstack(w, u, ga, be, al, e(1)).T
    x1, y1, z1 = P[0]
    j1 = sp.Matrix([
        [0, 0, 0, 0, 1, 0], [0, 0, 0, 1, 0, 0], [0, 0, 1, 0, 0, 0],
        [0, 0, -y1, z1, 0, 1], [0, 1, x1, 0, -z1, 0], [1, 0, 0, -x1, y1, 0],
    ])
    return pi1.T * (j1.T * k)


def paper():
    """Eq 60 regrouped, as `codegen/src/model/paper.rs`: the platform and the bodies 2 lumped
    into one body about C, the rods' axial loads added after step 6."""
    a_s = a_c - cross(omega, v_c)  # the spatial acceleration of eq 43
    pam = tilde(omega_dot) + tilde(omega) * tilde(omega)
    # The lumped body: reference points B_i = C - P_i, centres of mass there.
    mass = M_PLATFORM + 6 * M_JOINT
    h = sp.zeros(3, 1)
    i_rot = I_PLATFORM
    i_offsets = sp.zeros(3, 3)
    for i in range(6):
        h += -M_JOINT * P[i]
        i_rot = i_rot + i_joint(i)
        i_offsets += -M_JOINT * tilde(P[i]) * tilde(P[i])
    a = a_c - G
    force = mass * a + pam * h
    moment = (R * euler(i_rot) + i_offsets * omega_dot + cross(omega, i_offsets * omega)
              + cross(h, a))
    k = sp.Matrix.vstack(moment, force)
    # The rods' axial loads, Q_i1'' by projection (eq 47).
    tau = sp.Matrix([M_ROD * (unit(AXIS[i]).dot(a_s + cross(P[i], omega_dot))
                              - G[AXIS[i]]) for i in range(6)])
    return step6(k) + tau


def paper_by_legs():
    """Eqs 43-62 with the slips corrected, leg by leg as the chapter computes them
    (`inverse_dynamics_by_legs` in `codegen/src/model/paper.rs`)."""
    a_s = a_c - cross(omega, v_c)  # the spatial acceleration of eq 43
    pam = tilde(omega_dot) + tilde(omega) * tilde(omega)
    phi = sp.zeros(6, 1)
    for i in range(6):
        n, p, q = unit(AXIS[i]), P[i], Q[i]
        qdd = n.dot(a_s + cross(p, omega_dot))  # eq 47
        a_b = a_s + cross(omega, v_c) - pam * p
        f2 = M_JOINT * (a_b - G)
        n2 = R * euler(i_joint(i))
        f1 = M_ROD * (n * qdd - G)
        # Backward recursion (eq 10) and T_i (eq 49): the rod's actuator force.
        t1 = n.dot(f1 + f2)
        # Phi += P^-1 J_B^-T T: body 2's wrench moved to C, plus the rod's force along n at B.
        force = f2 + n * (t1 - n.dot(f2))
        moment = n2 + cross(-p, force)
        phi += sp.Matrix.vstack(moment, force)
    # Eqs 52-57 (centre of mass at C).
    f_platform = sp.Matrix.vstack(R * euler(I_PLATFORM), M_PLATFORM * (a_c - G))
    k = f_platform + phi
    return step6(k)


def consistent():
    """Virtual work, step 6 factored, as `codegen/src/model/consistent.rs`."""
    rt = R.T
    u_p, a_p, g_p = rt * v_c, rt * a_c, rt * G
    p = []
    for i in range(6):
        full = rt * P[i]
        p.append(sp.Matrix([0 if j == AXIS[i] else full[j] for j in range(3)]))
    nu = [R[AXIS[i], :].T for i in range(6)]
    d = [R[AXIS[i], AXIS[i]] for i in range(6)]
    rows = [sp.Matrix.vstack(cross(unit(AXIS[i]), p[i]), unit(AXIS[i])) for i in range(6)]
    wu = sp.Matrix.vstack(w_p, u_p)
    qd = [rows[i].dot(wu) / d[i] for i in range(6)]
    qdd = []
    for i in range(6):
        e = unit(AXIS[i])
        slip = 2 * (u_p - nu[i] * qd[i])
        qdd.append((cross(e, p[i]).dot(wd_p) + a_p[AXIS[i]]
                    + cross(w_p, e).dot(cross(p[i], w_p) + slip)) / d[i])
    moments = sp.zeros(3, 1)
    direct = []
    for i in range(6):
        moments += euler(i_joint(i))
        direct.append((M_ROD + M_JOINT) * (qdd[i] - G[AXIS[i]]))
    k = sp.Matrix.vstack(euler(I_PLATFORM) + moments, M_PLATFORM * (a_p - g_p))
    # S^-T k by the pair system G^T y_a = n - sum f_k e_k x p_b.
    pairs = [(0, 1), (2, 3), (4, 5)]
    gm = sp.Matrix([list((rows[a] - rows[b])[:3]) for a, b in pairs])
    rhs = k[:3, 0]
    for axis, (_, b) in enumerate(pairs):
        rhs = rhs - rows[b][:3, 0] * k[3 + axis]
    gt = gm.T
    ya = gt.adjugate() * rhs / gt.det()
    y = [0] * 6
    for axis, (a, b) in enumerate(pairs):
        y[a] = ya[axis]
        y[b] = k[3 + axis] - ya[axis]
    return sp.Matrix([d[i] * y[i] + direct[i] for i in range(6)])


def emit(name, gamma_expr):
    replacements, (reduced,) = sp.cse(gamma_expr)
    ops = sum(sp.count_ops(e, visual=True) for _, e in replacements) + sp.count_ops(reduced, visual=True)
    lines = [
        f"/* @generated by tests/c-output/sympy/generate.py (SymPy {sp.__version__}): the {name}",
        " * model's inverse dynamics, default robot, sympy.cse then sympy.ccode. The baseline of",
        " * the bench inverse_dynamics_c; regenerate with `python3 tests/c-output/sympy/generate.py`.",
        f" * SymPy's count: {ops}",
        " */",
        "#include <math.h>",
        "",
        f"void sympy_{name}_inverse_dynamics(const double pose[6], const double twist[6],",
        "                                    const double accel[6], double gamma_out[6])",
        "{",
    ]
    for arr, names in (("pose", "alpha beta gamma xc yc zc"), ("twist", "wx wy wz vx vy vz"),
                       ("accel", "wdx wdy wdz ax ay az")):
        for j, n in enumerate(names.split()):
            lines.append(f"    const double {n} = {arr}[{j}];")
    for sym, expr in replacements:
        lines.append(f"    const double {sym} = {sp.ccode(expr)};")
    for j in range(6):
        lines.append(f"    gamma_out[{j}] = {sp.ccode(reduced[j])};")
    lines.append("}")
    path = pathlib.Path(__file__).with_name(f"sympy_{name}.c")
    path.write_text("\n".join(lines) + "\n")
    print(f"{path.name}: {ops}")


emit("paper", paper())
emit("paper_by_legs", paper_by_legs())
emit("consistent", consistent())
