"""The Gough-Stewart platform against an independent closed-loop multibody engine: Pinocchio's
constraint dynamics (`pip install pin`), on a hexapod file no Rust test uses, through `c5 eval`
and `c5 forward`.

Pinocchio's model: a free-flying platform, and per leg a chain from `A_i`, a revolute joint
about `a_i`, a revolute joint about the leg frame's `y'`, a prismatic joint along the leg (the
actuator), the cylinder on the second revolute and the rod on the prismatic joint; each rod's
end is held to the platform point `p_i` by a 3D contact constraint. The chain's frame at any
angles is the U joint's frame of the description (`z' = u`, `y' ∝ u × a`), so its bodies turn
as the kernels' do. Compared: `q`, `q̇`, `q̈`, `J⁻¹ V`, the forces (Pinocchio's forward dynamics
of `c5 eval`'s `Γ` gives the acceleration back), the forward dynamics, and the pose `c5 eval`
finds from leg lengths alone.
"""

from __future__ import annotations

import numpy as np
import pytest

pin = pytest.importorskip("pinocchio")

HOME_HEIGHT = 0.6  # a height of the test robot's workspace
# The largest relative difference from Pinocchio that docs/mechanisms.md states, per result
# (the issue asked for 1e-9).
STATED = {"q": 3e-16, "qd": 7e-16, "qdd": 6e-14, "gamma": 6e-14, "forward": 2e-15,
          "pose": 2e-12}


def rotation(pose):
    a, b, g = pose[:3]
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(g), -np.sin(g), 0], [np.sin(g), np.cos(g), 0], [0, 0, 1]])
    return rx @ ry @ rz


def leg_frame(u, a):
    y = np.cross(u, a)
    y /= np.linalg.norm(y)
    return np.column_stack([np.cross(y, u), y, u])


def rodrigues(axis, t):
    k = axis / np.linalg.norm(axis)
    skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(t) * skew + (1 - np.cos(t)) * skew @ skew


class PinocchioHexapod:
    """The description's hexapod in Pinocchio, closed by one 3D contact per leg."""

    def __init__(self, robot: dict, home: list[float]):
        m = pin.Model()
        m.gravity = pin.Motion(np.array(list(robot["gravity"]) + [0.0, 0.0, 0.0]))
        p = robot["platform"]
        self.platform = m.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "platform")
        xx, yy, zz, xy, xz, yz = p["inertia"]
        inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        m.appendBodyToJoint(self.platform, pin.Inertia(p["mass"], np.array(p["centre_of_mass"]),
                                                       inertia), pin.SE3.Identity())
        r0, c0 = rotation(home), np.array(home[3:])
        self.legs = []
        for leg in robot["legs"]:
            base, axis, joint = (np.array(leg[k], float) for k in ("base", "u_axis", "platform"))
            axis /= np.linalg.norm(axis)
            b0 = c0 + r0 @ joint
            frame0 = leg_frame((b0 - base) / np.linalg.norm(b0 - base), axis)
            u1 = m.addJoint(0, pin.JointModelRevoluteUnaligned(frame0.T @ axis),
                            pin.SE3(frame0, base), "u1")
            u2 = m.addJoint(u1, pin.JointModelRY(), pin.SE3.Identity(), "u2")
            cyl = leg["cylinder"]
            m.appendBodyToJoint(u2, pin.Inertia(cyl["mass"], np.array([0, 0, cyl["com"]]),
                                                np.diag(cyl["inertia"])), pin.SE3.Identity())
            prismatic = m.addJoint(u2, pin.JointModelPZ(), pin.SE3.Identity(), "p")
            rod = leg["rod"]
            m.appendBodyToJoint(prismatic, pin.Inertia(rod["mass"], np.array([0, 0, -rod["com"]]),
                                                       np.diag(rod["inertia"])),
                                pin.SE3.Identity())
            self.legs.append(dict(base=base, axis=axis, joint=joint, frame0=frame0, u1=u1, u2=u2,
                                  prismatic=prismatic, offset=leg.get("encoder_offset", 0.0)))
        self.model = m
        self.constraints = pin.StdVec_RigidConstraintModel()
        for leg in self.legs:
            self.constraints.append(pin.RigidConstraintModel(
                pin.ContactType.CONTACT_3D, m, leg["prismatic"], pin.SE3.Identity(),
                self.platform, pin.SE3(np.eye(3), leg["joint"]), pin.ReferenceFrame.LOCAL))

    def configuration(self, pose, twist):
        """Pinocchio's `q`, `v` for a platform pose and twist: each leg's U joint angles and
        length solved in closed form, its rates from the chain's Jacobian."""
        m = self.model
        rot, centre = rotation(pose), np.array(pose[3:])
        q = pin.neutral(m)
        q[0:3] = centre
        q[3:7] = pin.Quaternion(rot).coeffs()
        w, vc = np.array(twist[:3]), np.array(twist[3:])
        v = np.zeros(m.nv)
        v[0:3], v[3:6] = rot.T @ vc, rot.T @ w
        for leg in self.legs:
            d = centre + rot @ leg["joint"] - leg["base"]
            length = np.linalg.norm(d)
            u, y0, a = d / length, leg["frame0"][:, 1], leg["axis"]
            t1 = np.arctan2(-(y0 @ u), np.cross(a, y0) @ u)
            local = leg["frame0"].T @ rodrigues(a, -t1) @ u
            for joint, value in ((leg["u1"], t1), (leg["u2"], np.arctan2(local[0], local[2])),
                                 (leg["prismatic"], length)):
                q[m.joints[joint].idx_q] = value
        data = m.createData()
        pin.computeJointJacobians(m, data, q)
        for leg in self.legs:
            jac = pin.getJointJacobian(m, data, leg["prismatic"],
                                       pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
            columns = [m.joints[j].idx_v for j in (leg["u1"], leg["u2"], leg["prismatic"])]
            tip_rate = vc + np.cross(w, rot @ leg["joint"])
            v[columns] = np.linalg.solve(jac[0:3, columns], tip_rate)
        return q, v

    def forward(self, pose, twist, gamma):
        """The platform's classical acceleration and the actuators' positions, rates and
        accelerations under the actuator forces `gamma`."""
        m = self.model
        q, v = self.configuration(pose, twist)
        tau = np.zeros(m.nv)
        for leg, g in zip(self.legs, gamma):
            tau[m.joints[leg["prismatic"]].idx_v] = g
        data = m.createData()
        datas = pin.StdVec_RigidConstraintData()
        for c in self.constraints:
            datas.append(c.createData())
        pin.initConstraintDynamics(m, data, self.constraints, datas)
        ddq = pin.constraintDynamics(m, data, q, v, tau, self.constraints, datas,
                                     pin.ProximalSettings(1e-14, 0.0, 1))
        rot = rotation(pose)
        accel = np.concatenate([rot @ ddq[3:6], rot @ (ddq[0:3] + np.cross(v[3:6], v[0:3]))])
        idx = [m.joints[leg["prismatic"]] for leg in self.legs]
        return (accel, np.array([q[j.idx_q] + leg["offset"] for j, leg in zip(idx, self.legs)]),
                np.array([v[j.idx_v] for j in idx]), np.array([ddq[j.idx_v] for j in idx]))


def unseen_hexapod(rng) -> dict:
    """A hexapod of other numbers than docs/hexapod.toml's: a larger base, tilted U axes,
    joints off their planes, its own masses, encoder offsets."""
    legs = []
    for k in range(3):
        for side in (1, -1):
            ab = 2 * np.pi * k / 3 + side * 0.15 + rng.uniform(-0.03, 0.03)
            ap = 2 * np.pi * k / 3 + side * 0.7 + rng.uniform(-0.03, 0.03)
            t_c, t_r = rng.uniform(0.05, 0.1), rng.uniform(0.02, 0.05)
            legs.append(dict(
                base=[0.6 * np.cos(ab), 0.6 * np.sin(ab), rng.uniform(-0.02, 0.02)],
                u_axis=[-np.sin(ab) + rng.uniform(-0.2, 0.2), np.cos(ab), rng.uniform(-0.1, 0.1)],
                platform=[0.35 * np.cos(ap), 0.35 * np.sin(ap), rng.uniform(-0.03, 0.0)],
                cylinder=dict(mass=rng.uniform(1, 4), com=rng.uniform(0.1, 0.4),
                              inertia=[t_c, t_c, rng.uniform(0.001, t_c)]),
                rod=dict(mass=rng.uniform(0.5, 2), com=rng.uniform(0.1, 0.4),
                         inertia=[t_r, t_r, rng.uniform(0.001, t_r)]),
                encoder_offset=rng.uniform(-0.05, 0.05),
            ))
    return dict(gravity=[0.2, -0.1, -9.81],
                platform=dict(mass=30.0, centre_of_mass=[0.01, -0.01, 0.05],
                              inertia=[1.2, 1.3, 2.0, 0.02, -0.01, 0.03]),
                legs=legs)


def toml(robot: dict) -> str:
    def value(v):
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(float(v))
    text = f'mechanism = "gough-stewart"\ngravity = {value(robot["gravity"])}\n[platform]\n'
    text += "".join(f"{k} = {value(v)}\n" for k, v in robot["platform"].items())
    for leg in robot["legs"]:
        text += "[[legs]]\n" + "".join(f"{k} = {value(v)}\n" for k, v in leg.items())
    return text


def relative(got, want):
    got, want = np.asarray(got, float), np.asarray(want, float)
    return np.max(np.abs(got - want)) / max(1e-12, np.max(np.abs(want)))


@pytest.mark.parametrize("seed", [1, 2])
def test_eval_and_forward_agree_with_pinocchio(seed, run_c5, tmp_path):
    rng = np.random.default_rng(seed)
    robot = unseen_hexapod(rng)
    path = tmp_path / "unseen-hexapod.toml"
    path.write_text(toml(robot))
    engine = PinocchioHexapod(robot, [0, 0, 0, 0, 0, HOME_HEIGHT])
    states = []
    for _ in range(25):
        pose = [*rng.uniform(-0.25, 0.25, 3), *rng.uniform(-0.08, 0.08, 2),
                HOME_HEIGHT + rng.uniform(-0.08, 0.08)]
        states.append((pose, list(rng.uniform(-1, 1, 3)) + list(rng.uniform(-0.5, 0.5, 3)),
                       list(rng.uniform(-5, 5, 3)) + list(rng.uniform(-2, 2, 3))))
    evaluated = run_c5("eval", [dict(pose=p, omega=t[:3], velocity=t[3:], omega_dot=a[:3],
                                     acceleration=a[3:]) for p, t, a in states],
                       "--robot", str(path))
    forces = [list(rng.uniform(-300, 300, 6)) for _ in states]
    forward = run_c5("forward", [dict(pose=p, omega=t[:3], velocity=t[3:], gamma=g)
                                 for (p, t, _), g in zip(states, forces)], "--robot", str(path))
    poses = run_c5("eval", [dict(q=e["q"]) for e in evaluated], "--robot", str(path))
    worst = dict.fromkeys(STATED, 0.0)
    for (pose, twist, accel), e, f, g, back in zip(states, evaluated, forward, forces, poses):
        accel_back, q, qd, qdd = engine.forward(pose, twist, e["gamma"])
        accel_of_forces, _, _, _ = engine.forward(pose, twist, g)
        for what, error in [
            ("q", relative(e["q"], q)),
            ("qd", relative(e["qd"], qd)),
            ("qd", relative(np.array(e["jinv"]) @ np.array(twist), qd)),
            ("qdd", relative(e["qdd"], qdd)),
            ("gamma", relative(accel_back, accel)),
            ("forward", relative(f["omega_dot"] + f["acceleration"], accel_of_forces)),
            ("pose", relative(back["pose"], pose)),
        ]:
            worst[what] = max(worst[what], error)
    print("worst relative differences from Pinocchio:", worst)
    # docs/mechanisms.md states these figures; each is held at ten times.
    for what, stated in STATED.items():
        assert worst[what] < 10 * stated, (what, worst[what])
