"""An exported MJCF file read by the two independent engines, knowing nothing of the mechanism:
Pinocchio 4.1 (`buildModelAndLegacyConstraintsFromMJCF`: the tree and its welds as 6D rigid
constraints) and MuJoCo (the same file, soft welds). The leg joints for a platform state are
found from the file alone: Newton on the welds' errors with the platform held, the rates from
the welds' Jacobian. The actuators are the file's `<motor>`s, in order.

Conventions (docs/export.md): the platform body's origin is `C`; `R = Rx(α) Ry(β) Rz(γ)`;
twists `(ω; v_C)` and classical accelerations `(ω̇; a_C)` in the base frame. A platform that
only translates (the Delta) takes poses `[xc yc zc]` and velocities `v_C`.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin


def rotation(pose):
    a, b, g = pose[:3]
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(g), -np.sin(g), 0], [np.sin(g), np.cos(g), 0], [0, 0, 1]])
    return rx @ ry @ rz


def motor_joints(path) -> list[str]:
    """The joints the file's motors drive, in actuator order (read by MuJoCo)."""
    import mujoco

    m = mujoco.MjModel.from_xml_path(str(path))
    return [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.actuator_trnid[k, 0])
            for k in range(m.nu)]


class PinocchioExport:
    """The file in Pinocchio, with its welds as rigid constraints and gravity as MuJoCo reads
    it from the same file."""

    def __init__(self, path):
        import mujoco

        self.model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
        self.model.gravity = pin.Motion(np.concatenate(
            [mujoco.MjModel.from_xml_path(str(path)).opt.gravity, np.zeros(3)]))
        self.constraints = pin.StdVec_RigidConstraintModel()
        for c in constraints:
            self.constraints.append(c)
        root = self.model.joints[1]
        self.free = root.shortname() == "JointModelFreeFlyer"
        self.platform_dofs = root.nv
        assert self.free or root.nv == 3, "the platform is free, or translates (three slides)"
        # The slides' zero is the home position, where MuJoCo places the platform body.
        self.home_centre = mujoco.MjModel.from_xml_path(str(path)).body_pos[1].copy()
        self.actuated = [self.model.joints[self.model.getJointId(name)].idx_v
                         for name in motor_joints(path)]

    def joint_value(self, q, name):
        """The value in `q` of the joint `name` (a hinge or a slide)."""
        return q[self.model.joints[self.model.getJointId(name)].idx_q]

    def _constraint_jacobian(self, data, q):
        """The welds' and balls' errors at `q` and their Jacobian. The constraints' data hold
        the anchors' placements only after a constraint-dynamics pass, so one runs first."""
        m = self.model
        datas = pin.StdVec_RigidConstraintData()
        for c in self.constraints:
            datas.append(c.createData())
        pin.initConstraintDynamics(m, data, self.constraints, datas)
        pin.constraintDynamics(m, data, q, np.zeros(m.nv), np.zeros(m.nv), self.constraints,
                               datas, pin.ProximalSettings(1e-12, 1e-10, 10))
        pin.computeJointJacobians(m, data, q)
        rows, errors = [], []
        for c, cd in zip(self.constraints, datas):
            rows.append(pin.getConstraintJacobian(m, data, c, cd))
            one = data.oMi[c.joint1_id] * c.joint1_placement
            two = data.oMi[c.joint2_id] * c.joint2_placement
            relative = one.inverse() * two
            if c.type == pin.ContactType.CONTACT_3D:
                errors.append(relative.translation)
            else:
                errors.append(pin.log6(relative).vector)
        return np.vstack(rows), np.concatenate(errors)

    def state(self, pose, twist, start=None):
        """Pinocchio's `q`, `v` for the platform's pose and twist: the legs' joints by Newton
        on the welds from `start` (the reference configuration, the robot at home), the
        largest weld error left, and the legs' rates from the welds' Jacobian."""
        m = self.model
        data = m.createData()
        q = (m.referenceConfigurations["home"] if start is None else start).copy()
        n = self.platform_dofs
        v = np.zeros(m.nv)
        if self.free:
            rot = rotation(pose)
            q[0:3] = pose[3:]
            q[3:7] = pin.Quaternion(rot).coeffs()
            w, vc = np.asarray(twist[:3], float), np.asarray(twist[3:], float)
            v[0:3], v[3:6] = rot.T @ vc, rot.T @ w
        else:
            q[0:3] = np.asarray(pose, float) - self.home_centre
            v[0:3] = twist
        for _ in range(50):
            jac, err = self._constraint_jacobian(data, q)
            if np.max(np.abs(err)) < 1e-15:
                break
            step = np.zeros(m.nv)
            # Pinocchio's constraint Jacobian is that of the relative motion the error undoes;
            # least squares, as a Delta's parallelograms repeat constraints.
            step[n:] = np.linalg.lstsq(jac[:, n:], err, rcond=None)[0]
            q = pin.integrate(m, q, step)
        jac, err = self._constraint_jacobian(data, q)
        v[n:] = -np.linalg.lstsq(jac[:, n:], jac[:, :n] @ v[:n], rcond=None)[0]
        return q, v, np.max(np.abs(err))

    def forward(self, pose, twist, gamma):
        """The platform's classical acceleration `(ω̇; a_C)`, base frame, under the actuator
        forces `gamma`, by `constraintDynamics`."""
        m = self.model
        q, v, _ = self.state(pose, twist)
        tau = np.zeros(m.nv)
        tau[self.actuated] = gamma
        data = m.createData()
        datas = pin.StdVec_RigidConstraintData()
        for c in self.constraints:
            datas.append(c.createData())
        pin.initConstraintDynamics(m, data, self.constraints, datas)
        # The proximal iterations converge on the exact solution, and need a positive `mu`
        # where constraints repeat (a Delta's parallelograms and its platform's slides).
        ddq = pin.constraintDynamics(m, data, q, v, tau, self.constraints, datas,
                                     pin.ProximalSettings(1e-14, 1e-8, 100))
        if not self.free:
            return ddq[0:3]
        rot = rotation(pose)
        return np.concatenate([rot @ ddq[3:6], rot @ (ddq[0:3] + np.cross(v[3:6], v[0:3]))])
