//! The kernel table: which kernels a model is generated into, declared as data.
//!
//! Every model gets [`TABLE`] (plus its own [`Mechanics::extra_kernels`]); a [`Decl`] says
//! what a kernel is ([`Kernel`], its typed identity), which equations it computes, from which
//! kinds of input, into which outputs, and which singularity terms it returns. A kernel's
//! build reads its inputs by kind through a [`Context`], never by position, so a new kernel
//! is one declaration. [`specs`] turns the table into the engine's [`KernelSpec`]s for one
//! model, robot and parameter set, each tagged with its [`KernelId`].

use super::bodies::{platform_wrench, Dynamics, Frame};
use super::geometry::{self, JointMotion, Motion, Posed};
use super::{Mechanics, Mechanism, Quantity, INTERNAL_INPUTS};
use crate::dag::{Expr, Graph};
use crate::error::Error;
use crate::kernel::{Arg, ChapterCount, KernelSpec, Objective, Setting, Shape};
use crate::linalg::{Mat, Mat3, Vec6, Vector};

macro_rules! kernels {
    ($($(#[$doc:meta])* $id:ident => $name:literal,)*) => {
        /// What a kernel computes: its typed identity, the same for every model, scalar and
        /// variant. The generated function's name is [`Kernel::name`] (with `_params` when the
        /// robot's parameters are inputs, `_x4`/`_x8` in batch form).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Kernel {
            $($(#[$doc])* $id,)*
        }

        impl Kernel {
            /// Every kernel, in the table's order.
            pub const ALL: &'static [Kernel] = &[$(Kernel::$id),*];

            /// The generated function's base name.
            pub const fn name(self) -> &'static str {
                match self {
                    $(Kernel::$id => $name,)*
                }
            }
        }
    };
}

kernels! {
    /// `[r11 r22 r33]` from the pose.
    SingularityTerms => "singularity_terms",
    /// Eq 16: `Q_i1` and `P_i2` from the pose.
    InverseKinematics => "inverse_kinematics",
    /// `J⁻¹` from the pose.
    InverseJacobianPose => "inverse_jacobian_pose",
    /// `J` from the pose.
    JacobianPose => "jacobian_pose",
    /// `Q̇_a = J⁻¹ V`.
    JointVelocities => "joint_velocities",
    /// `Q̈_a` from the platform's motion.
    JointAccelerations => "joint_accelerations",
    /// `Φ`, the legs' loads at `C`.
    LegWrench => "leg_wrench",
    /// `F_{N+1}`, the platform's wrench.
    PlatformWrench => "platform_wrench",
    /// `M_x`.
    TaskInertia => "task_inertia",
    /// `h`.
    TaskBias => "task_bias",
    /// `(ω̇; a_C)` from `Γ`.
    ForwardDynamics => "forward_dynamics",
    /// `Γ` from the platform's motion.
    InverseDynamics => "inverse_dynamics",
    /// The chapter's setting: eq 22 from `P_i2`.
    InverseJacobian => "inverse_jacobian",
    /// The chapter's setting: eq 39.
    Pi1 => "pi1",
    /// The chapter's setting: eq 40.
    Jacobian => "jacobian",
    /// The chapter's setting: eqs 43-48 for segment 1.
    JointAccelerationsSegment => "joint_accelerations_segment",
    /// The chapter's setting: eq 62.
    Step6Factored => "step6_factored",
    /// The chapter's setting: the denominators of eq 39.
    Pi1Denominators => "pi1_denominators",
    /// Eqs 43-48 for every segment, the passive joints included.
    LegJointAccelerations => "leg_joint_accelerations",
    /// `Y` of `Γ = Y π`.
    Regressor => "regressor",
    /// `Y_b` of `Γ = Y_b β`.
    BaseRegressor => "base_regressor",
    /// `R` and `C` from the actuator positions.
    ForwardKinematics => "forward_kinematics",
    /// The RPY angles of a rotation.
    RpyAngles => "rpy_angles",
    /// `V = J Q̇_a`.
    PlatformTwist => "platform_twist",
    /// `(ω̇; a_C)` from the actuators' motion.
    PlatformAcceleration => "platform_acceleration",
    /// The whole platform state from the actuators' motion.
    PlatformState => "platform_state",
    /// `Γ` from the actuators' motion.
    InverseDynamicsJoint => "inverse_dynamics_joint",
    /// `M_q`.
    JointInertia => "joint_inertia",
    /// `c_q`.
    JointBias => "joint_bias",
    /// What the limits bound: ball positions, plate offsets, tilt cosines.
    LimitGeometry => "limit_geometry",
    /// `Γ` and `∂Γ/∂(X, V, A)`.
    InverseDynamicsDerivatives => "inverse_dynamics_derivatives",
    /// `a` and `∂a/∂(X, V, Γ)`.
    ForwardDynamicsDerivatives => "forward_dynamics_derivatives",
    /// `Γ` and `∂Γ/∂(q, q̇, q̈)`.
    InverseDynamicsJointDerivatives => "inverse_dynamics_joint_derivatives",
    /// A Newton step of the forward kinematics: the actuators' residual and `∂q/∂X`.
    ForwardKinematicsStep => "forward_kinematics_step",
    /// Kinematic calibration: the legs' residuals at a measured pose and their Jacobians with
    /// respect to the geometry and the pose.
    CalibrationResiduals => "calibration_residuals",
}

/// A generated kernel: what it computes and whether the robot's parameters are its inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct KernelId {
    pub kernel: Kernel,
    /// The robot's parameters are a `params` argument (else folded in as constants).
    pub parameters: bool,
}

impl KernelId {
    pub const fn folded(kernel: Kernel) -> Self {
        KernelId {
            kernel,
            parameters: false,
        }
    }
}

/// A kernel's engine specification with its identity.
pub struct Entry {
    pub id: KernelId,
    pub spec: KernelSpec,
    /// Also emitted in batch form.
    pub batch: bool,
    /// The robot's parameters are folded in as constants, and a `*_params` form of the same
    /// kernel takes them as inputs: a program for any robot of the kind needs only the latter.
    pub folded: bool,
}

/// The kind of an input of a kernel; a build reads its inputs by kind through [`Context`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Input {
    /// The platform pose `[α β γ xc yc zc]`.
    Pose,
    /// The platform twist `(ω; v_C)`.
    Twist,
    /// The classical platform acceleration `(ω̇; a_C)`.
    Accel,
    /// The actuator forces `Γ`.
    Gamma,
    /// The chapter's setting: the six vectors `P_i2` as free inputs.
    P,
    /// The chapter's setting: `P_12` alone.
    P1,
    /// The spatial platform acceleration `V̇_{N+1}` (eqs 43-48).
    SpatialAccel,
    /// A wrench `K` at `C`.
    Wrench,
    /// The actuator positions `Q_i1` (what the encoders measure).
    Actuators,
    /// The actuator rates `Q̇_i1`.
    ActuatorRates,
    /// The actuator accelerations `Q̈_i1`.
    ActuatorAccelerations,
    /// A rotation matrix `R`.
    Rotation,
    /// The position `C` of a platform that only translates (the Delta's `[xc yc zc]`).
    Position,
    /// Its velocity `v_C`.
    Velocity,
    /// Its acceleration `a_C`.
    LinearAccel,
}

fn names(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

impl Input {
    /// The argument of this kind for a mechanism of `actuators` actuators.
    pub(crate) fn arg(self, actuators: usize) -> Arg {
        let each = |prefix: &str| (1..=actuators).map(|i| format!("{prefix}{i}")).collect();
        match self {
            Input::Pose => Arg::new(
                "pose",
                Shape::Vector(6),
                names(&["alpha", "beta", "gamma", "xc", "yc", "zc"]),
                "platform pose `[α β γ xc yc zc]` (rad, m), RPY as eq 15",
            ),
            Input::Twist => Arg::new(
                "twist",
                Shape::Vector(6),
                names(&["wx", "wy", "wz", "vx", "vy", "vz"]),
                "platform twist `(ω; v_C)` at `C`, base frame (rad/s, m/s)",
            ),
            Input::Accel => Arg::new(
                "accel",
                Shape::Vector(6),
                names(&["wdx", "wdy", "wdz", "ax", "ay", "az"]),
                "classical platform acceleration `(ω̇; a_C)`, `a_C = d v_C/dt` (rad/s², m/s²)",
            ),
            // Not `gamma`: the pose's third element has that name.
            Input::Gamma => Arg::new(
                "forces",
                Shape::Vector(actuators),
                each("g"),
                "actuator forces `Γ` (N), segment order; positive pushes the rod along `+n_i`",
            ),
            Input::P => Arg::new(
                "p",
                Shape::Matrix(6, 3),
                (1..=6)
                    .flat_map(|i| ["x", "y", "z"].map(|c| format!("{c}{i}")))
                    .collect(),
                "`p[i] = P_i2 = [x_i y_i z_i]`, from `B_i` to `C` for segment `i+1` (eq 27)",
            ),
            Input::P1 => Arg::new(
                "p1",
                Shape::Vector(3),
                names(&["x1", "y1", "z1"]),
                "`P_12 = [x1 y1 z1]` (eq 27)",
            ),
            Input::SpatialAccel => Arg::new(
                "vdot",
                Shape::Vector(6),
                names(&["wdx", "wdy", "wdz", "ax", "ay", "az"]),
                "spatial platform acceleration `V̇_{N+1} = (ω̇; a_C - ω × v_C)`",
            ),
            Input::Wrench => Arg::new(
                "k",
                Shape::Vector(6),
                names(&["knx", "kny", "knz", "kfx", "kfy", "kfz"]),
                "`K = F_{N+1} + Φ` at `C`, moment first (N·m, N)",
            ),
            Input::Actuators => Arg::new(
                "q",
                Shape::Vector(actuators),
                each("q"),
                "actuator positions (m) in actuator order, as the conventions above define them \
                 (the C5's `Q_i1`: `B_i = A_i + Q_i1 n_i`)",
            ),
            Input::ActuatorRates => Arg::new(
                "qd",
                Shape::Vector(actuators),
                each("qd"),
                "actuator rates `Q̇_i1` (m/s), segment order",
            ),
            Input::ActuatorAccelerations => Arg::new(
                "qdd",
                Shape::Vector(actuators),
                each("qdd"),
                "actuator accelerations `Q̈_i1` (m/s²), segment order",
            ),
            Input::Rotation => Arg::new(
                "r",
                Shape::Matrix(3, 3),
                (1..=3)
                    .flat_map(|i| (1..=3).map(move |j| format!("r{i}{j}")))
                    .collect(),
                "a rotation `R` of the workspace (`r11 > 0`, `r33 > 0`), row-major",
            ),
            Input::Position => Arg::new(
                "position",
                Shape::Vector(3),
                names(&["xc", "yc", "zc"]),
                "the platform's position `C` (m), base frame; its frame stays parallel to the \
                 base's",
            ),
            Input::Velocity => Arg::new(
                "velocity",
                Shape::Vector(3),
                names(&["vx", "vy", "vz"]),
                "the platform's velocity `v_C` (m/s), base frame",
            ),
            Input::LinearAccel => Arg::new(
                "accel",
                Shape::Vector(3),
                names(&["ax", "ay", "az"]),
                "the platform's acceleration `a_C` (m/s²), base frame",
            ),
        }
    }

    /// The setting of a kernel that takes this input.
    fn setting(self) -> Option<Setting> {
        match self {
            Input::Pose => Some(Setting::Pose),
            Input::Actuators | Input::Rotation => Some(Setting::Joint),
            Input::P | Input::P1 => Some(Setting::Free),
            _ => None,
        }
    }
}

/// An output of a kernel.
#[derive(Clone, Copy, Debug)]
pub struct Output {
    pub name: &'static str,
    pub shape: Shape,
    pub doc: &'static str,
}

/// Where a kernel's equation numbers come from.
#[derive(Clone, Copy, Debug)]
pub enum Cite {
    /// The same for every model.
    Fixed(&'static [&'static str]),
    /// The model's own ([`Mechanics::equations`]).
    Model(Quantity),
}

/// Which singularity terms a kernel returns as its last result; what they are is the
/// mechanism's ([`Structure::guard`](super::Structure::guard)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Guard {
    /// None: the kernel never divides by a term that can vanish.
    Never,
    /// Those of the pose: where the legs' closed forms divide (the C5's divisors of eq 16,
    /// `[r11 r22 r33]`).
    Pose,
    /// Those of the pose and of the solve with `J⁻ᵀ` (the C5 needs none beyond the pose's).
    Solve,
    /// From the actuator positions: the forward singularity term, then the pose's (the C5's
    /// `[1 + abc, r11, r22, r33]`).
    Forward,
}

/// What a kernel reads of the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reads {
    /// Nothing: the same kernel for every robot.
    Nothing,
    /// Its parameters, folded or a `params` argument as the [`ParameterSet`] says (the
    /// checked-in crate has both, the second named `*_params`).
    Robot,
    /// Its geometry and gravity, always a `params` argument (the first
    /// [`Structure::geometry_parameters`](super::Structure::geometry_parameters) of its
    /// parameter vector); the identification kernels, whose unknowns are the
    /// inertial parameters.
    Geometry,
}

/// Builds a robot kernel's outputs from its [`Context`].
pub type RobotBuild = for<'c, 'g> fn(&Context<'c, 'g>) -> Vec<Vec<Expr<'g>>>;

/// Builds a chapter-setting kernel's outputs from its free inputs.
pub type FreeBuild = for<'g> fn(&'g Graph, &[Vec<Expr<'g>>]) -> Vec<Vec<Expr<'g>>>;

/// Which columns an identification kernel keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Columns {
    /// Every standard parameter's.
    Standard,
    /// The base parameters' leads.
    Base,
}

/// How a kernel's outputs are built.
#[derive(Clone, Copy)]
pub enum Build {
    /// From the robot and the inputs the kernel declares, read by kind.
    Robot(RobotBuild),
    /// From free inputs (the chapter's setting): no robot parameter.
    Free(FreeBuild),
    /// A regressor of the model's inverse dynamics (identification).
    Regressor(Columns),
}

/// One kernel, declared.
#[derive(Clone, Copy)]
pub struct Decl {
    pub kernel: Kernel,
    /// One line saying what the kernel computes.
    pub title: &'static str,
    /// Further documentation (may be empty).
    pub doc: &'static str,
    pub equations: Cite,
    pub inputs: &'static [Input],
    pub outputs: &'static [Output],
    pub guard: Guard,
    pub reads: Reads,
    /// Also in batch form (vector inputs and outputs only).
    pub batch: bool,
    /// The chapter's published count, for the kernels audited against its table.
    pub chapter: Option<ChapterCount>,
    pub build: Build,
}

/// What a robot kernel's build reads: the model, the robot's dynamics (constants or inputs)
/// and the kernel's inputs, by kind. The platform state it needs is derived from whichever
/// inputs the kernel declares.
pub struct Context<'c, 'g> {
    pub mech: &'c dyn Mechanics,
    pub dynamics: &'c Dynamics<'g>,
    /// The mechanism's geometry and gravity ([`Posed::geometry`]).
    pub geometry: &'c [Expr<'g>],
    graph: &'g Graph,
    bound: Vec<(Input, Vec<Expr<'g>>)>,
}

impl<'c, 'g> Context<'c, 'g> {
    pub fn graph(&self) -> &'g Graph {
        self.graph
    }

    /// Whether the kernel takes an input of this kind.
    pub fn has(&self, kind: Input) -> bool {
        self.bound.iter().any(|(k, _)| *k == kind)
    }

    /// The kernel's input of this kind; zeros (and the graph marked invalid, so the
    /// generation fails) if it declares none.
    pub fn input(&self, kind: Input) -> Vec<Expr<'g>> {
        match self.bound.iter().find(|(k, _)| *k == kind) {
            Some((_, v)) => v.clone(),
            None => {
                self.graph
                    .invalidate(format!("the build reads an undeclared input {kind:?}"));
                vec![self.graph.zero(); kind.arg(self.mech.structure().actuators()).shape.len()]
            }
        }
    }

    fn vector(&self, kind: Input) -> Vec6<'g> {
        let v = self.input(kind);
        Vector(std::array::from_fn(|i| v[i]))
    }

    fn vector_or_zero(&self, kind: Input) -> Option<Vec6<'g>> {
        self.has(kind).then(|| self.vector(kind))
    }

    /// The pose, expanded (eqs 15, 16, 27 for the C5): from the pose the kernel takes, or from
    /// the actuator positions by the mechanism's closed-form forward kinematics.
    pub fn posed(&self) -> Posed<'g> {
        let structure = self.mech.structure();
        if self.has(Input::Actuators) && !self.has(Input::Pose) {
            let q = self.input(Input::Actuators);
            let q = std::array::from_fn(|i| q[i]);
            if let Some(posed) = structure.forward_kinematics(self.geometry, &q) {
                return posed;
            }
            self.graph
                .invalidate("the mechanism has no closed-form forward kinematics".into());
        }
        structure.pose(self.geometry, &self.input(Input::Pose))
    }

    /// The platform's motion: the twist and acceleration the kernel takes, zero where it
    /// takes none; or, from the actuator positions, the motion the actuators' rates and
    /// accelerations give (zero where the kernel takes none).
    pub fn motion(&self) -> Motion<'g> {
        let zeros = Vec6::zeros(self.graph);
        if self.has(Input::Actuators) {
            let joint = JointMotion {
                qd: self.vector_or_zero(Input::ActuatorRates).unwrap_or(zeros),
                qdd: self
                    .vector_or_zero(Input::ActuatorAccelerations)
                    .unwrap_or(zeros),
            };
            return self.mech.motion_from_actuators(&self.posed(), &joint);
        }
        Motion::new(
            self.vector_or_zero(Input::Twist).unwrap_or(zeros),
            self.vector_or_zero(Input::Accel).unwrap_or(zeros),
        )
    }

    /// The inverse dynamics at the kernel's state, `Γ`.
    pub fn inverse_dynamics(&self) -> Vec6<'g> {
        self.mech
            .inverse_dynamics(self.dynamics, &self.posed(), &self.motion())
    }

    /// The actuator forces `Γ`.
    pub fn forces(&self) -> Vec6<'g> {
        self.vector(Input::Gamma)
    }

    /// The same context with the input `kind` replaced (added if absent).
    pub fn rebind(&self, kind: Input, values: Vec<Expr<'g>>) -> Context<'c, 'g> {
        let mut bound: Vec<_> = self
            .bound
            .iter()
            .filter(|(k, _)| *k != kind)
            .cloned()
            .collect();
        bound.push((kind, values));
        Context {
            mech: self.mech,
            dynamics: self.dynamics,
            geometry: self.geometry,
            graph: self.graph,
            bound,
        }
    }

    /// Six fresh unknowns the outputs must not depend on once differentiated (`M_x`, `M_q`).
    pub fn unknowns(&self) -> Vec<Expr<'g>> {
        (0..6)
            .map(|k| self.graph.input(INTERNAL_INPUTS + k))
            .collect()
    }

    /// The singularity terms of `guard`.
    fn guard(&self, guard: Guard) -> Option<Vec<Expr<'g>>> {
        (guard != Guard::Never).then(|| self.mech.structure().guard_at(guard, self))
    }
}

const JINV: Output = Output {
    name: "jinv",
    shape: Shape::Matrix(6, 6),
    doc: "`J⁻¹`, row `i` for segment `i+1`, columns `[ωx ωy ωz vx vy vz]`",
};
const JAC: Output = Output {
    name: "jacobian",
    shape: Shape::Matrix(6, 6),
    doc: "`J`, rows `[ωx ωy ωz vx vy vz]`, column `i` for segment `i+1`",
};
const GAMMA: Output = Output {
    name: "gamma",
    shape: Shape::Vector(6),
    doc: "`Γ` (N), segment order; positive pushes the rod along `+n_i`",
};

const POSE_MOTION: &[Input] = &[Input::Pose, Input::Twist, Input::Accel];
const JOINT_MOTION: &[Input] = &[
    Input::Actuators,
    Input::ActuatorRates,
    Input::ActuatorAccelerations,
];

/// The RPY angles `[α β γ]` of a rotation whose `r11` and `r33` are positive (every rotation
/// of the workspace): `α = atan(-r23/r33)`, `β = atan(r13 / √(r11² + r12²))`,
/// `γ = atan(-r12/r11)`, each in `(-π/2, π/2)` (eq 15 inverted).
fn rpy<'g>(r: &Mat3<'g>) -> Vec<Expr<'g>> {
    let m = &r.0;
    vec![
        (-(m[1][2] / m[2][2])).atan(),
        (m[0][2] / (m[0][0] * m[0][0] + m[0][1] * m[0][1]).sqrt()).atan(),
        (-(m[0][1] / m[0][0])).atan(),
    ]
}

const TWIST: Output = Output {
    name: "twist",
    shape: Shape::Vector(6),
    doc: "platform twist `(ω; v_C)` at `C`, base frame (rad/s, m/s)",
};
const ACCEL: Output = Output {
    name: "accel",
    shape: Shape::Vector(6),
    doc: "classical platform acceleration `(ω̇; a_C)` (rad/s², m/s²), base frame",
};

/// `R` row-major and `C` of the platform.
const PLACEMENT: [Output; 2] = [
    Output {
        name: "r",
        shape: Shape::Matrix(3, 3),
        doc: "the rotation `R` of the platform frame (eq 15), the placement in the workspace \
              (every `r_kk > 0`)",
    },
    Output {
        name: "c",
        shape: Shape::Vector(3),
        doc: "the platform centre `C` (m), base frame",
    },
];

/// The kernels every model is generated into.
pub const TABLE: &[Decl] = &[
    Decl {
        kernel: Kernel::SingularityTerms,
        title: "The divisors of eq 16, `[r11 r22 r33]`: the pose is singular where one vanishes.",
        doc: "Cheaper than the kernels it guards: one check before them costs a few ns.",
        equations: Cite::Fixed(&["15", "16"]),
        inputs: &[Input::Pose],
        outputs: &[Output {
            name: "r",
            shape: Shape::Vector(3),
            doc: "`[r11 r22 r33]`",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.mech.structure().guard(Guard::Pose, &cx.posed())]),
    },
    Decl {
        kernel: Kernel::InverseKinematics,
        title: "Inverse kinematics: actuator lengths `Q_i1` and the vectors `P_i2`.",
        doc: "",
        equations: Cite::Model(Quantity::InverseKinematics),
        inputs: &[Input::Pose],
        outputs: &[
            Output {
                name: "q",
                shape: Shape::Vector(6),
                doc: "actuator positions (m) in actuator order, as the conventions above define \
                      them (the C5's `Q_i1`: `B_i = A_i + Q_i1 n_i`, zero at the home pose)",
            },
            Output {
                name: "p",
                shape: Shape::Matrix(6, 3),
                doc: "`P_i2` from `B_i` to `C` (m), base frame",
            },
        ],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            let posed = cx.posed();
            vec![
                posed.q.to_vec(),
                posed.p.iter().flat_map(|v| v.to_vec()).collect(),
            ]
        }),
    },
    Decl {
        kernel: Kernel::InverseJacobianPose,
        title: "Inverse Jacobian `J⁻¹` at a pose.",
        doc: "",
        equations: Cite::Model(Quantity::InverseJacobian),
        inputs: &[Input::Pose],
        outputs: &[JINV],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.mech.inverse_jacobian(&cx.posed()).rows()]),
    },
    Decl {
        kernel: Kernel::JacobianPose,
        title: "Jacobian `J` at a pose, in factored form.",
        doc: "",
        equations: Cite::Model(Quantity::Jacobian),
        inputs: &[Input::Pose],
        outputs: &[JAC],
        guard: Guard::Solve,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.mech.jacobian(&cx.posed()).rows()]),
    },
    Decl {
        kernel: Kernel::JointVelocities,
        title: "Actuator rates `Q̇_a = J⁻¹ V`.",
        doc: "",
        equations: Cite::Model(Quantity::JointVelocities),
        inputs: &[Input::Pose, Input::Twist],
        outputs: &[Output {
            name: "qd",
            shape: Shape::Vector(6),
            doc: "`Q̇_i1` (m/s), segment order",
        }],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            vec![cx
                .mech
                .joint_velocities(&cx.posed(), &cx.motion().twist)
                .to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::JointAccelerations,
        title: "Actuator accelerations `Q̈_a` from the platform's motion.",
        doc: "",
        equations: Cite::Model(Quantity::JointAccelerations),
        inputs: POSE_MOTION,
        outputs: &[Output {
            name: "qdd",
            shape: Shape::Vector(6),
            doc: "`Q̈_i1` (m/s²), segment order",
        }],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            vec![cx
                .mech
                .joint_accelerations(&cx.posed(), &cx.motion())
                .to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::LegWrench,
        title: "The legs' loads as one wrench `Φ` at `C`, such that `Γ = Jᵀ (F_{N+1} + Φ)`.",
        doc: "",
        equations: Cite::Model(Quantity::LegWrench),
        inputs: POSE_MOTION,
        outputs: &[Output {
            name: "phi",
            shape: Shape::Vector(6),
            doc: "`Φ = (n; f)` at `C`, base frame (N·m, N)",
        }],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            vec![cx
                .mech
                .leg_wrench(cx.dynamics, &cx.posed(), &cx.motion())
                .to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::PlatformWrench,
        title: "The platform's wrench `F_{N+1} = Λ_C V̇ + C_C + G_C` at `C`.",
        doc: "",
        equations: Cite::Model(Quantity::PlatformWrench),
        inputs: POSE_MOTION,
        outputs: &[Output {
            name: "f",
            shape: Shape::Vector(6),
            doc: "`F_{N+1} = (n; f)` (N·m, N), base frame",
        }],
        guard: Guard::Never,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            let (posed, motion) = (cx.posed(), cx.motion());
            let frame = Frame::new(posed.r, &motion.twist.top(), &motion.accel.top());
            vec![platform_wrench(cx.dynamics, &frame, &motion.twist, &motion.accel).to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::TaskInertia,
        title:
            "Task-space inertia `M_x` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`: symmetric positive definite.",
        doc: "`M_x = ∂(J⁻ᵀ Γ)/∂(ω̇; a_C)`, the exact derivative of the inverse dynamics.",
        equations: Cite::Model(Quantity::TaskSpace),
        inputs: &[Input::Pose],
        outputs: &[Output {
            name: "m",
            shape: Shape::Matrix(6, 6),
            doc: "`M_x` (kg, kg·m, kg·m²), rows and columns `[ωx ωy ωz vx vy vz]`, base frame",
        }],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.mech.task_inertia(cx.dynamics, &cx.posed()).rows()]),
    },
    Decl {
        kernel: Kernel::TaskBias,
        title:
            "Task-space bias `h` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`: Coriolis, centrifugal, gravity.",
        doc: "",
        equations: Cite::Model(Quantity::TaskSpace),
        inputs: &[Input::Pose, Input::Twist],
        outputs: &[Output {
            name: "h",
            shape: Shape::Vector(6),
            doc: "`h = (n; f)` at `C`, base frame (N·m, N)",
        }],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            vec![cx
                .mech
                .task_bias(cx.dynamics, &cx.posed(), &cx.motion().twist)
                .to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::ForwardDynamics,
        title:
            "Forward dynamics: the platform's acceleration `(ω̇; a_C)` under actuator forces `Γ`.",
        doc: "`M_x (ω̇; a_C) = J⁻ᵀ Γ - h`, solved by an unrolled `LDLᵀ` (no pivoting: `M_x` is \
              symmetric positive definite).",
        equations: Cite::Model(Quantity::ForwardDynamics),
        inputs: &[Input::Pose, Input::Twist, Input::Gamma],
        outputs: &[Output {
            name: "accel",
            shape: Shape::Vector(6),
            doc: "classical platform acceleration `(ω̇; a_C)` (rad/s², m/s²), base frame",
        }],
        // The solve's terms too: a hexapod's hold on the platform comes with the acceleration
        // (its rows are the kernel's own) rather than from a second kernel call.
        guard: Guard::Solve,
        reads: Reads::Robot,
        batch: true,
        chapter: None,
        build: Build::Robot(|cx| {
            vec![cx
                .mech
                .forward_dynamics(cx.dynamics, &cx.posed(), &cx.motion().twist, &cx.forces())
                .to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::InverseDynamics,
        title: "Inverse dynamics end to end: actuator forces `Γ` from the platform state.",
        doc: "",
        equations: Cite::Model(Quantity::InverseDynamics),
        inputs: POSE_MOTION,
        outputs: &[GAMMA],
        guard: Guard::Solve,
        reads: Reads::Robot,
        batch: true,
        chapter: None,
        build: Build::Robot(|cx| {
            vec![cx
                .mech
                .inverse_dynamics(cx.dynamics, &cx.posed(), &cx.motion())
                .to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::ForwardKinematics,
        title: "Forward kinematics in closed form: the platform's `R` and `C` from the actuator \
                positions.",
        doc: "No trigonometry and no linear solve: eq 16's pair differences fix each column of \
              `R` up to one unknown, orthogonality makes the three unknowns a rational function \
              of `a = (Q2 - Q1)/2L`, `b = (Q4 - Q3)/2L`, `c = (Q6 - Q5)/2L`, and the half-sums \
              give `C` (docs/joint-space.md).",
        equations: Cite::Fixed(&["15", "16"]),
        inputs: &[Input::Actuators],
        outputs: &PLACEMENT,
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            let posed = cx.posed();
            vec![posed.r.rows(), posed.c.to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::RpyAngles,
        title: "The RPY angles `[α β γ]` of a rotation of the workspace (eq 15 inverted).",
        doc: "`α = atan(-r23/r33)`, `β = atan(r13 / √(r11² + r12²))`, `γ = atan(-r12/r11)`, \
              each in `(-π/2, π/2)`: right for every rotation with `r11 > 0` and `r33 > 0`, \
              which every pose of the workspace has (and [`forward_kinematics`] returns).",
        equations: Cite::Fixed(&["15"]),
        inputs: &[Input::Rotation],
        outputs: &[Output {
            name: "angles",
            shape: Shape::Vector(3),
            doc: "`[α β γ]` (rad), `R = Rx(α) Ry(β) Rz(γ)`",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            let r = cx.input(Input::Rotation);
            vec![rpy(&Mat::from_fn(|i, j| r[3 * i + j]))]
        }),
    },
    Decl {
        kernel: Kernel::PlatformTwist,
        title: "The platform twist from the actuator rates, `V = J Q̇_a`.",
        doc: "Through the model's factored `J` (no 6×6 solve), at the pose of the forward \
              kinematics.",
        equations: Cite::Model(Quantity::Jacobian),
        inputs: &[Input::Actuators, Input::ActuatorRates],
        outputs: &[TWIST],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.motion().twist.to_vec()]),
    },
    Decl {
        kernel: Kernel::PlatformAcceleration,
        title: "The platform's classical acceleration from the actuators' motion.",
        doc: "`(ω̇; a_C) = J (Q̈_a - h)`, `h` the actuator accelerations at zero platform \
              acceleration: the model's second-order kinematics solved the way `J` is, no \
              6×6 solve.",
        equations: Cite::Model(Quantity::JointAccelerations),
        inputs: JOINT_MOTION,
        outputs: &[ACCEL],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.motion().accel.to_vec()]),
    },
    Decl {
        kernel: Kernel::PlatformState,
        title: "The platform state (pose, twist, acceleration) from the actuators' motion.",
        doc: "The forward kinematics, the RPY angles of its `R`, `V = J Q̇_a` and \
              `(ω̇; a_C) = J (Q̈_a - h)` in one kernel.",
        equations: Cite::Model(Quantity::JointAccelerations),
        inputs: JOINT_MOTION,
        outputs: &[
            Output {
                name: "pose",
                shape: Shape::Vector(6),
                doc: "platform pose `[α β γ xc yc zc]` (rad, m), RPY as eq 15",
            },
            TWIST,
            ACCEL,
        ],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            let (posed, motion) = (cx.posed(), cx.motion());
            let mut pose = rpy(&posed.r);
            pose.extend(posed.c.to_vec());
            vec![pose, motion.twist.to_vec(), motion.accel.to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::InverseDynamicsJoint,
        title: "Inverse dynamics from what the encoders measure: `Γ` from the actuators' \
                positions, rates and accelerations.",
        doc: "The forward kinematics, then the model's inverse dynamics at the state found, \
              without trigonometry.",
        equations: Cite::Model(Quantity::InverseDynamics),
        inputs: JOINT_MOTION,
        outputs: &[GAMMA],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: true,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.inverse_dynamics().to_vec()]),
    },
    Decl {
        kernel: Kernel::JointInertia,
        title: "Joint-space inertia `M_q = Jᵀ M_x J` of `Γ = M_q Q̈_a + c_q`: symmetric positive \
                definite.",
        doc: "`M_q = ∂Γ/∂Q̈_a`, the exact derivative of the joint-space inverse dynamics.",
        equations: Cite::Model(Quantity::TaskSpace),
        inputs: &[Input::Actuators],
        outputs: &[Output {
            name: "m",
            shape: Shape::Matrix(6, 6),
            doc: "`M_q` (kg), rows and columns in segment order",
        }],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            let unknown = cx.unknowns();
            let gamma = cx
                .rebind(Input::ActuatorAccelerations, unknown.clone())
                .inverse_dynamics();
            vec![jacobian_wrt(cx.graph(), &gamma.to_vec(), &unknown).rows()]
        }),
    },
    Decl {
        kernel: Kernel::JointBias,
        title: "Joint-space bias `c_q` of `Γ = M_q Q̈_a + c_q`: Coriolis, centrifugal, gravity.",
        doc: "`Γ` at `Q̈_a = 0`.",
        equations: Cite::Model(Quantity::TaskSpace),
        inputs: &[Input::Actuators, Input::ActuatorRates],
        outputs: &[Output {
            name: "c",
            shape: Shape::Vector(6),
            doc: "`c_q` (N), segment order",
        }],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![cx.inverse_dynamics().to_vec()]),
    },
    Decl {
        kernel: Kernel::LimitGeometry,
        title: "What the robot's limits bound, at a pose: each ball's position `Q_i1` on its \
                actuator, its offset on its plate, and the cosine of its tilt.",
        doc: "The plate's offset is `Rᵀ (B_i - C) - A_i`, where the ball sits in the platform \
              frame against where it sits at the home pose, along the plate's two axes (the \
              platform axes other than its normal, in the order x, y, z). The tilt is the angle \
              between the rod's axis `n_i` and the plate's normal `m_i`: its cosine is \
              `n_i · m_i = r_kk`. Every limit of `c5_robot::Limits` but speed and force is a \
              bound on one of these.",
        equations: Cite::Fixed(&["15", "16", "27"]),
        inputs: &[Input::Pose],
        outputs: &[
            Output {
                name: "q",
                shape: Shape::Vector(6),
                doc: "`Q_i1` (m), segment order",
            },
            Output {
                name: "plate",
                shape: Shape::Vector(12),
                doc: "each ball's offset on its plate (m), two per segment: \
                      `[u1a, u1b, u2a, u2b, …]`",
            },
            Output {
                name: "tilt_cos",
                shape: Shape::Vector(6),
                doc: "`cos` of each ball's tilt, `n_i · m_i`",
            },
        ],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: true,
        chapter: None,
        build: Build::Robot(|cx| {
            let posed = cx.posed();
            let rt = posed.r.transpose();
            let mut plate = Vec::with_capacity(12);
            let mut tilt = Vec::with_capacity(6);
            for i in 0..6 {
                // `P_i2 = C - B_i`: the ball from the centre is `-P_i2`.
                let offset =
                    -(rt * posed.p[i]) - geometry::anchor(geometry::half_spacing(cx.geometry), i);
                let k = c5_robot::AXIS[i];
                plate.extend((0..3).filter(|&a| a != k).map(|a| offset[a]));
                tilt.push(geometry::divisor(&posed.r, i));
            }
            vec![posed.q.to_vec(), plate, tilt]
        }),
    },
];

/// Whether every model has `kernel` (it is in [`TABLE`] or an identification kernel), with one
/// signature for all.
pub fn is_shared(kernel: Kernel) -> bool {
    TABLE
        .iter()
        .chain(&super::regressor::KERNELS)
        .chain(&super::derivatives::KERNELS)
        .any(|d| d.kernel == kernel)
}

/// Which robot parameters are kernel inputs; the others are folded in as constants.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub enum ParameterSet {
    /// Every parameter folded (the fastest kernels).
    #[default]
    None,
    /// Every parameter an input, in the order of the mechanism's parameter vector
    /// ([`Structure::parameter_names`](super::Structure::parameter_names); the C5's
    /// `Robot::kernel_parameters`): one kernel set for any robot of the mechanism.
    All,
    /// These parameters (names of
    /// [`Structure::parameter_names`](super::Structure::parameter_names)) are inputs, in the
    /// order given.
    Named(Vec<String>),
}

impl ParameterSet {
    /// Indices into the parameter vector, whose names are `names`, of the parameters that are
    /// inputs, in the order of the kernels' `params` argument.
    ///
    /// # Errors
    /// [`Error::UnknownParameter`] or [`Error::DuplicateParameter`] for a bad name.
    pub fn indices(&self, names: &[String]) -> Result<Vec<usize>, Error> {
        match self {
            ParameterSet::None => Ok(vec![]),
            ParameterSet::All => Ok((0..names.len()).collect()),
            ParameterSet::Named(chosen) => {
                let mut out = Vec::with_capacity(chosen.len());
                for name in chosen {
                    let index = names
                        .iter()
                        .position(|n| n == name)
                        .ok_or_else(|| Error::UnknownParameter { name: name.clone() })?;
                    if out.contains(&index) {
                        return Err(Error::DuplicateParameter { name: name.clone() });
                    }
                    out.push(index);
                }
                Ok(out)
            }
        }
    }
}

/// The mechanism's parameters as the kernels see them: folded constants, or entries of the
/// `params` input (`params[k]` is the parameter `indices[k]` of the vector `values`).
fn symbolic_parameters<'g>(
    g: &'g Graph,
    values: &[f64],
    indices: &[usize],
    params: Option<&Vec<Expr<'g>>>,
) -> Vec<Expr<'g>> {
    values
        .iter()
        .enumerate()
        .map(
            |(k, &v)| match (indices.iter().position(|&i| i == k), params) {
                (Some(pos), Some(p)) => p[pos],
                _ => g.constant(v),
            },
        )
        .collect()
}

/// The robot kernels of `mechanism` (the table's that its structure has, and its mechanics'
/// own), its parameters as `parameters` says; with `suffix` appended to the names of those that
/// read parameters when some are inputs. With a non-empty suffix (a second set beside a folded
/// one), the kernels that read no parameter are left out.
///
/// # Errors
/// A bad [`ParameterSet`].
pub fn specs(
    mechanism: &Mechanism,
    parameters: &ParameterSet,
    suffix: &str,
) -> Result<Vec<Entry>, Error> {
    let (mech, structure) = (mechanism.mechanics, mechanism.structure());
    let indices = parameters.indices(&structure.parameter_names())?;
    Ok(TABLE
        .iter()
        .filter(|d| structure.has_kernel(d.kernel))
        .chain(mech.extra_kernels())
        .filter(|d| match (d.build, d.reads) {
            (Build::Free(_), _) => false,
            (_, Reads::Robot) => true,
            _ => suffix.is_empty(),
        })
        .map(|d| spec(d, mechanism, &indices, suffix, None))
        .collect())
}

/// The kernels of `mechanism` that read its geometry alone (kinematic calibration's), whose
/// geometry is their `params` input whatever else is folded: what a mechanism generated with
/// its `*_params` kernels alone adds to them.
pub fn geometry_specs(mechanism: &Mechanism) -> Vec<Entry> {
    mechanism
        .mechanics
        .extra_kernels()
        .iter()
        .filter(|d| matches!((d.build, d.reads), (Build::Robot(_), Reads::Geometry)))
        .map(|d| spec(d, mechanism, &[], "", None))
        .collect()
}

/// The derivative kernels of `mechanism` ([`super::derivatives::KERNELS`], those its structure
/// has, and its own), its parameters as `parameters` says, named with `suffix` when some are
/// inputs.
///
/// # Errors
/// A bad [`ParameterSet`].
pub fn derivative_specs(
    mechanism: &Mechanism,
    parameters: &ParameterSet,
    suffix: &str,
) -> Result<Vec<Entry>, Error> {
    let structure = mechanism.structure();
    let indices = parameters.indices(&structure.parameter_names())?;
    Ok(super::derivatives::KERNELS
        .iter()
        .filter(|d| structure.has_kernel(d.kernel))
        .chain(mechanism.mechanics.extra_derivative_kernels())
        .map(|d| spec(d, mechanism, &indices, suffix, None))
        .collect())
}

/// The free-input kernels of `mechanism` (the paper model's equations with the components of
/// `P_i2` as free inputs, the setting the chapter's operation counts assume); none for a
/// mechanism without them.
pub fn chapter_specs(mechanism: &Mechanism) -> Vec<Entry> {
    mechanism
        .mechanics
        .extra_kernels()
        .iter()
        .filter(|d| matches!(d.build, Build::Free(_)))
        .map(|d| spec(d, mechanism, &[], "", None))
        .collect()
}

/// The engine's specification of `decl` for `mechanism`: the parameters `indices` are its
/// `params` input, the others folded; `base` gives the columns of a [`Columns::Base`]
/// regressor.
pub(crate) fn spec(
    decl: &Decl,
    mechanism: &Mechanism,
    indices: &[usize],
    suffix: &str,
    base: Option<Vec<usize>>,
) -> Entry {
    let (mech, structure) = (mechanism.mechanics, mechanism.structure());
    let family = mech.name();
    let equations: Vec<String> = match decl.equations {
        Cite::Fixed(e) => e.iter().map(|s| s.to_string()).collect(),
        Cite::Model(q) => mech.equations(q).iter().map(|s| s.to_string()).collect(),
    };
    let actuators = structure.actuators();
    let mut inputs: Vec<Arg> = decl.inputs.iter().map(|i| i.arg(actuators)).collect();
    let mut outputs: Vec<Arg> = decl
        .outputs
        .iter()
        .map(|o| Arg::output(o.name, o.shape, o.doc))
        .collect();
    let mut doc = format!(
        "Model: {family}. {}\n{}",
        mech.summary(),
        structure.conventions()
    );
    if !decl.doc.is_empty() {
        doc.push('\n');
        doc.push_str(decl.doc);
    }
    let setting = decl
        .inputs
        .iter()
        .find_map(|i| i.setting())
        .unwrap_or(Setting::Pose);
    let objective = match decl.build {
        Build::Free(_) => Objective::ChapterCount,
        _ => Objective::Speed,
    };
    let indices: Vec<usize> = match decl.reads {
        Reads::Nothing => Vec::new(),
        Reads::Robot => indices.to_vec(),
        Reads::Geometry => (0..structure.geometry_parameters()).collect(),
    };
    let params_at = (!indices.is_empty()).then(|| {
        let all = structure.parameter_names();
        inputs.push(Arg::new(
            "params",
            Shape::Vector(indices.len()),
            indices.iter().map(|&i| all[i].clone()).collect(),
            structure.parameter_doc(decl.reads),
        ));
        inputs.len() - 1
    });
    match decl.reads {
        Reads::Nothing => {}
        Reads::Robot => doc.push_str(if params_at.is_some() {
            "\nThe robot's parameters listed in `params` are inputs; the others are folded in."
        } else {
            "\nThe robot's parameters are folded in as constants."
        }),
        Reads::Geometry => doc.push_str("\nThe geometry and gravity are `params`."),
    }
    if decl.guard != Guard::Never {
        let (output, note) = structure.guard_output(decl.guard);
        outputs.push(Arg::output(output.name, output.shape, output.doc));
        doc.push_str(note);
    }
    let id = KernelId {
        kernel: decl.kernel,
        parameters: params_at.is_some() && decl.reads == Reads::Robot,
    };
    let name = if id.parameters {
        format!("{}{suffix}", decl.kernel.name())
    } else {
        decl.kernel.name().to_string()
    };
    let values = mechanism.parameters.clone();
    let geometry_len = structure.geometry_parameters();
    let (build, guard, kinds) = (decl.build, decl.guard, decl.inputs);
    let spec = KernelSpec {
        name,
        family: family.to_string(),
        setting,
        equations,
        title: decl.title.to_string(),
        doc,
        chapter: decl.chapter,
        objective,
        inputs,
        outputs,
        build: match build {
            Build::Free(f) => Box::new(f),
            Build::Robot(_) | Build::Regressor(_) => Box::new(move |g, i| {
                let sym = symbolic_parameters(g, &values, &indices, params_at.map(|k| &i[k]));
                let dynamics = structure.dynamics(&sym);
                let cx = Context {
                    mech,
                    dynamics: &dynamics,
                    geometry: &sym[..geometry_len],
                    graph: g,
                    bound: kinds.iter().copied().zip(i.iter().cloned()).collect(),
                };
                let mut results = match build {
                    Build::Robot(f) => f(&cx),
                    Build::Regressor(columns) => {
                        let chosen = match columns {
                            Columns::Standard => None,
                            Columns::Base => Some(base.as_deref().unwrap_or(&[])),
                        };
                        vec![super::regressor::rows(&cx, chosen)]
                    }
                    Build::Free(f) => f(g, i),
                };
                results.extend(cx.guard(guard));
                results
            }),
        },
    };
    Entry {
        id,
        spec,
        batch: decl.batch,
        folded: decl.reads == Reads::Robot && params_at.is_none(),
    }
}

/// `M = ∂w/∂x`, the Jacobian of `w` with respect to six unknowns `x` (fresh inputs of the
/// graph): the exact derivative, which for `w` affine in `x` is its matrix.
pub fn jacobian_wrt<'g>(g: &'g Graph, w: &[Expr<'g>], x: &[Expr<'g>]) -> crate::linalg::Mat6<'g> {
    let columns: Vec<Vec<Expr<'g>>> = x.iter().map(|&u| g.derivatives(w, u)).collect();
    Mat::from_fn(|r, c| columns[c][r])
}

/// `kernel` of `mechanism`, its description folded in, compiled: what the models' tests
/// evaluate.
#[cfg(test)]
pub(crate) fn compiled(mechanism: &Mechanism, kernel: Kernel) -> crate::Program {
    specs(mechanism, &ParameterSet::None, "")
        .unwrap()
        .into_iter()
        .find(|e| e.id.kernel == kernel)
        .unwrap()
        .spec
        .compile()
        .unwrap()
        .program
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Model, Robot};

    fn named(names: &[&str]) -> ParameterSet {
        ParameterSet::Named(names.iter().map(|s| s.to_string()).collect())
    }

    #[test]
    fn named_parameters_keep_the_order_given() {
        let names = Robot::<f64>::kernel_parameter_names();
        let at = |n: &str| names.iter().position(|x| x == n).unwrap();
        let indices = named(&["gravity_z", "gravity_x", "platform_mass"])
            .indices(&names)
            .unwrap();
        assert_eq!(
            indices,
            vec![at("gravity_z"), at("gravity_x"), at("platform_mass")]
        );
        let code = crate::Config::new()
            .runtime_parameters(named(&["gravity_z", "gravity_x"]))
            .generate_to_string()
            .unwrap();
        assert!(code.contains("let [gravity_z, gravity_x] = *params;"));
    }

    #[test]
    fn a_delta_file_generates_the_deltas_kernels_folded_and_with_parameters() {
        let delta = c5_robot::Description::from_toml(
            &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/delta.toml"))
                .unwrap(),
            "delta.toml",
        )
        .unwrap();
        for parameters in [ParameterSet::None, ParameterSet::All] {
            let code = crate::Config::new()
                .description(delta.clone())
                .runtime_parameters(parameters)
                .generate_to_string()
                .unwrap();
            for kernel in ["inverse_dynamics", "forward_dynamics", "forward_kinematics"] {
                assert!(code.contains(&format!("pub fn {kernel}(")), "{kernel}");
            }
            assert!(code.contains("position: &[f64; 3]"));
        }
    }

    #[test]
    fn unknown_and_repeated_names_are_refused() {
        let names = Robot::<f64>::kernel_parameter_names();
        let e = named(&["gravity_w"])
            .indices(&names)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("unknown parameter `gravity_w`"), "{e}");
        let e = named(&["gravity_x", "gravity_x"])
            .indices(&names)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "parameter `gravity_x` is named twice");
    }

    #[test]
    fn kernel_names_are_unique() {
        let mut names: Vec<_> = Kernel::ALL.iter().map(|k| k.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Kernel::ALL.len());
    }

    #[test]
    fn a_build_that_reads_an_undeclared_input_fails_the_generation() {
        let decl = Decl {
            kernel: Kernel::InverseDynamics,
            title: "",
            doc: "",
            equations: Cite::Fixed(&[]),
            inputs: &[Input::Pose],
            outputs: &[GAMMA],
            guard: Guard::Never,
            reads: Reads::Robot,
            batch: false,
            chapter: None,
            build: Build::Robot(|cx| vec![cx.forces().to_vec()]),
        };
        let mechanism = Mechanism::c5(&Robot::default(), Model::Consistent);
        let entry = spec(&decl, &mechanism, &[], "", None);
        let e = entry.spec.compile().unwrap_err().to_string();
        assert!(e.contains("undeclared input Gamma"), "{e}");
    }
}
