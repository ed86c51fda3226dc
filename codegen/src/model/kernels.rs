//! The kernel table: which kernels a model is generated into, declared as data.
//!
//! Every model gets [`POSE_KERNELS`] (plus its own [`Mechanics::extra_kernels`]); a [`Decl`]
//! says what a kernel is called, which equations it computes, from which inputs, into which
//! outputs, and whether it returns the divisors of eq 16. [`specs`] turns the table into the
//! engine's [`KernelSpec`]s for one model, robot and parameter set.

use super::bodies::{platform_wrench, Dynamics, Frame};
use super::geometry::{self, Motion, Posed};
use super::{Mechanics, Model, Quantity};
use crate::dag::{Expr, Graph};
use crate::error::Error;
use crate::kernel::{Arg, ChapterCount, KernelSpec, Objective, Setting, Shape};
use crate::linalg::{Vec6, Vector};
use c5_robot::Robot;

/// An input of a kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// The platform pose `[α β γ xc yc zc]`.
    Pose,
    /// The platform twist `(ω; v_C)`.
    Twist,
    /// The classical platform acceleration `(ω̇; a_C)`.
    Accel,
    /// The chapter's setting: the six vectors `P_i2` as free inputs.
    P,
    /// The chapter's setting: `P_12` alone.
    P1,
    /// The spatial platform acceleration `V̇_{N+1}` (eqs 43-48).
    SpatialAccel,
    /// A wrench `K` at `C`.
    Wrench,
    /// The actuator forces `Γ`.
    Gamma,
}

fn names(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

impl Input {
    pub(crate) fn arg(self) -> Arg {
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
            // Not `gamma`: the pose's third element has that name.
            Input::Gamma => Arg::new(
                "forces",
                Shape::Vector(6),
                (1..=6).map(|i| format!("g{i}")).collect(),
                "actuator forces `Γ` (N), segment order; positive pushes the rod along `+n_i`",
            ),
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

/// Whether a kernel returns the divisors of eq 16 as its last result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Guard {
    Never,
    /// It goes through eq 16 whatever the model.
    Eq16,
    /// When the model divides by them for this quantity ([`Mechanics::divides_by_eq16`]).
    Model(Quantity),
}

/// Builds a pose-setting kernel's outputs from the bodies' standard parameters, the expanded pose
/// and the motion (zero where the kernel takes none).
pub type PoseBuild =
    for<'g> fn(&dyn Mechanics, &Dynamics<'g>, &Posed<'g>, &Motion<'g>) -> Vec<Vec<Expr<'g>>>;

/// Builds a chapter-setting kernel's outputs from its free inputs.
pub type FreeBuild = for<'g> fn(&'g Graph, &[Vec<Expr<'g>>]) -> Vec<Vec<Expr<'g>>>;

/// How a kernel's outputs are built.
#[derive(Clone, Copy)]
pub enum Build {
    /// From the platform state (the pose first), the robot folded or partly inputs.
    Pose {
        build: PoseBuild,
        /// Whether the kernel reads robot parameters (it then has a `_params` twin).
        robot: bool,
    },
    /// From free inputs (the chapter's setting): no robot parameter.
    Free(FreeBuild),
}

/// One kernel, declared.
#[derive(Clone, Copy)]
pub struct Decl {
    pub name: &'static str,
    /// One line saying what the kernel computes.
    pub title: &'static str,
    /// Further documentation (may be empty).
    pub doc: &'static str,
    pub equations: Cite,
    pub inputs: &'static [Input],
    pub outputs: &'static [Output],
    pub guard: Guard,
    /// The chapter's published count, for the kernels audited against its table.
    pub chapter: Option<ChapterCount>,
    pub build: Build,
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
const DIVISORS: Output = Output {
    name: "r",
    shape: Shape::Vector(3),
    doc: "`[r11 r22 r33]`, the divisors of eq 16: the other results are meaningless where one \
          is near zero",
};

/// The pose-setting kernels every model is generated into.
pub const POSE_KERNELS: &[Decl] = &[
    Decl {
        name: "singularity_terms",
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
        chapter: None,
        build: Build::Pose {
            build: |_, _, posed, _| vec![geometry::divisors(&posed.r)],
            robot: false,
        },
    },
    Decl {
        name: "inverse_kinematics",
        title: "Inverse kinematics: actuator lengths `Q_i1` and the vectors `P_i2`.",
        doc: "",
        equations: Cite::Fixed(&["15", "16", "27"]),
        inputs: &[Input::Pose],
        outputs: &[
            Output {
                name: "q",
                shape: Shape::Vector(6),
                doc: "`Q_i1` (m), segment order: `B_i = A_i + Q_i1 n_i`, zero at the home pose",
            },
            Output {
                name: "p",
                shape: Shape::Matrix(6, 3),
                doc: "`P_i2` from `B_i` to `C` (m), base frame",
            },
        ],
        guard: Guard::Eq16,
        chapter: None,
        build: Build::Pose {
            build: |_, _, posed, _| {
                vec![
                    posed.q.to_vec(),
                    posed.p.iter().flat_map(|v| v.to_vec()).collect(),
                ]
            },
            robot: true,
        },
    },
    Decl {
        name: "inverse_jacobian_pose",
        title: "Inverse Jacobian `J⁻¹` at a pose.",
        doc: "",
        equations: Cite::Model(Quantity::InverseJacobian),
        inputs: &[Input::Pose],
        outputs: &[JINV],
        guard: Guard::Model(Quantity::InverseJacobian),
        chapter: None,
        build: Build::Pose {
            build: |m, _, posed, _| vec![m.inverse_jacobian(posed).rows()],
            robot: true,
        },
    },
    Decl {
        name: "jacobian_pose",
        title: "Jacobian `J` at a pose, in factored form.",
        doc: "",
        equations: Cite::Model(Quantity::Jacobian),
        inputs: &[Input::Pose],
        outputs: &[JAC],
        guard: Guard::Model(Quantity::Jacobian),
        chapter: None,
        build: Build::Pose {
            build: |m, _, posed, _| vec![m.jacobian(posed).rows()],
            robot: true,
        },
    },
    Decl {
        name: "joint_velocities",
        title: "Actuator rates `Q̇_a = J⁻¹ V`.",
        doc: "",
        equations: Cite::Model(Quantity::JointVelocities),
        inputs: &[Input::Pose, Input::Twist],
        outputs: &[Output {
            name: "qd",
            shape: Shape::Vector(6),
            doc: "`Q̇_i1` (m/s), segment order",
        }],
        guard: Guard::Model(Quantity::JointVelocities),
        chapter: None,
        build: Build::Pose {
            build: |m, _, posed, motion| vec![m.joint_velocities(posed, &motion.twist).to_vec()],
            robot: true,
        },
    },
    Decl {
        name: "joint_accelerations",
        title: "Actuator accelerations `Q̈_a` from the platform's motion.",
        doc: "",
        equations: Cite::Model(Quantity::JointAccelerations),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[Output {
            name: "qdd",
            shape: Shape::Vector(6),
            doc: "`Q̈_i1` (m/s²), segment order",
        }],
        guard: Guard::Model(Quantity::JointAccelerations),
        chapter: None,
        build: Build::Pose {
            build: |m, _, posed, motion| vec![m.joint_accelerations(posed, motion).to_vec()],
            robot: true,
        },
    },
    Decl {
        name: "leg_wrench",
        title: "The legs' loads as one wrench `Φ` at `C`, such that `Γ = Jᵀ (F_{N+1} + Φ)`.",
        doc: "",
        equations: Cite::Model(Quantity::LegWrench),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[Output {
            name: "phi",
            shape: Shape::Vector(6),
            doc: "`Φ = (n; f)` at `C`, base frame (N·m, N)",
        }],
        guard: Guard::Model(Quantity::LegWrench),
        chapter: None,
        build: Build::Pose {
            build: |m, dynamics, posed, motion| {
                vec![m.leg_wrench(dynamics, posed, motion).to_vec()]
            },
            robot: true,
        },
    },
    Decl {
        name: "platform_wrench",
        title: "The platform's wrench `F_{N+1} = Λ_C V̇ + C_C + G_C` at `C`.",
        doc: "",
        equations: Cite::Fixed(&["52", "54", "55", "56", "57"]),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[Output {
            name: "f",
            shape: Shape::Vector(6),
            doc: "`F_{N+1} = (n; f)` (N·m, N), base frame",
        }],
        guard: Guard::Never,
        chapter: None,
        build: Build::Pose {
            build: |_, dynamics, posed, motion| {
                let frame = Frame::new(posed.r, &motion.twist.top(), &motion.accel.top());
                vec![platform_wrench(dynamics, &frame, &motion.twist, &motion.accel).to_vec()]
            },
            robot: true,
        },
    },
    Decl {
        name: "task_inertia",
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
        guard: Guard::Model(Quantity::TaskSpace),
        chapter: None,
        build: Build::Pose {
            build: |m, dynamics, posed, _| vec![m.task_inertia(dynamics, posed).rows()],
            robot: true,
        },
    },
    Decl {
        name: "task_bias",
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
        guard: Guard::Model(Quantity::TaskSpace),
        chapter: None,
        build: Build::Pose {
            build: |m, dynamics, posed, motion| {
                vec![m.task_bias(dynamics, posed, &motion.twist).to_vec()]
            },
            robot: true,
        },
    },
    Decl {
        name: "forward_dynamics",
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
        guard: Guard::Model(Quantity::ForwardDynamics),
        chapter: None,
        build: Build::Pose {
            build: |m, dynamics, posed, motion| {
                // `motion.accel` holds `Γ` here: the third input of this kernel.
                vec![m
                    .forward_dynamics(dynamics, posed, &motion.twist, &motion.accel)
                    .to_vec()]
            },
            robot: true,
        },
    },
    Decl {
        name: "inverse_dynamics",
        title: "Inverse dynamics end to end: actuator forces `Γ` from the platform state.",
        doc: "",
        equations: Cite::Model(Quantity::InverseDynamics),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[GAMMA],
        guard: Guard::Model(Quantity::InverseDynamics),
        chapter: None,
        build: Build::Pose {
            build: |m, dynamics, posed, motion| {
                vec![m.inverse_dynamics(dynamics, posed, motion).to_vec()]
            },
            robot: true,
        },
    },
];

/// Which robot parameters are kernel inputs; the others are folded in as constants.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub enum ParameterSet {
    /// Every parameter folded (the fastest kernels).
    #[default]
    None,
    /// Every parameter an input, in the order of [`Robot::kernel_parameters`] (one kernel set
    /// for any robot).
    All,
    /// These parameters (names of [`Robot::kernel_parameter_names`]) are inputs, in the order
    /// given.
    Named(Vec<String>),
}

impl ParameterSet {
    /// Indices into [`Robot::kernel_parameters`] of the parameters that are inputs, in the order
    /// of the kernels' `params` argument.
    ///
    /// # Errors
    /// [`Error::UnknownParameter`] or [`Error::DuplicateParameter`] for a bad name.
    pub fn indices(&self) -> Result<Vec<usize>, Error> {
        let names = Robot::<f64>::kernel_parameter_names();
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

/// The robot's kernel parameters as the kernels see them: folded constants, or entries of the
/// `params` input (`params[k]` is the parameter `indices[k]` of [`Robot::kernel_parameters`]).
fn symbolic_parameters<'g>(
    g: &'g Graph,
    robot: &Robot,
    indices: &[usize],
    params: Option<&Vec<Expr<'g>>>,
) -> Vec<Expr<'g>> {
    robot
        .kernel_parameters()
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

const ORDER_NOTE: &str = "Actuators are in segment order 1..6; the chapter lists them 6..1.";

fn vec6<'g>(v: &[Expr<'g>]) -> Vec6<'g> {
    Vector(std::array::from_fn(|i| v[i]))
}

/// The pose-setting kernels of `model` for `robot` (the table, and the model's own), with
/// `suffix` appended to the names of those that read robot parameters. With a non-empty
/// suffix (a second set beside a folded one), the kernels that read no parameter are left out.
///
/// # Errors
/// A bad [`ParameterSet`].
pub fn specs(
    model: Model,
    robot: &Robot,
    parameters: &ParameterSet,
    suffix: &str,
) -> Result<Vec<KernelSpec>, Error> {
    let mech = super::mechanics(model);
    let indices = parameters.indices()?;
    Ok(POSE_KERNELS
        .iter()
        .chain(mech.extra_kernels())
        .filter(|d| match d.build {
            Build::Pose { robot, .. } => suffix.is_empty() || robot,
            Build::Free(_) => false,
        })
        .map(|d| spec(d, mech, robot, &indices, suffix))
        .collect())
}

/// The chapter-setting kernels: the paper model's equations with the components of `P_i2` as
/// free inputs, the setting the chapter's operation counts assume.
pub fn chapter_specs() -> Vec<KernelSpec> {
    let mech = super::mechanics(Model::Paper);
    mech.extra_kernels()
        .iter()
        .filter(|d| matches!(d.build, Build::Free(_)))
        .map(|d| spec(d, mech, &Robot::default(), &[], ""))
        .collect()
}

fn spec(
    decl: &Decl,
    mech: &'static dyn Mechanics,
    robot: &Robot,
    indices: &[usize],
    suffix: &str,
) -> KernelSpec {
    let model = mech.model();
    let guarded = match decl.guard {
        Guard::Never => false,
        Guard::Eq16 => true,
        Guard::Model(q) => mech.divides_by_eq16(q),
    };
    let equations = match decl.equations {
        Cite::Fixed(e) => e,
        Cite::Model(q) => mech.equations(q),
    };
    let mut inputs: Vec<Arg> = decl.inputs.iter().map(|i| i.arg()).collect();
    let mut outputs: Vec<Arg> = decl
        .outputs
        .iter()
        .map(|o| Arg::output(o.name, o.shape, o.doc))
        .collect();
    let mut doc = format!("Model: {model}. {}\n{ORDER_NOTE}", mech.summary());
    if !decl.doc.is_empty() {
        doc.push('\n');
        doc.push_str(decl.doc);
    }
    let (setting, objective) = match decl.build {
        Build::Pose { .. } => (Setting::Pose, Objective::Speed),
        Build::Free(_) => (Setting::Chapter, Objective::ChapterCount),
    };
    let reads_robot = matches!(decl.build, Build::Pose { robot: true, .. });
    let params_at = (reads_robot && !indices.is_empty()).then(|| {
        let all = Robot::<f64>::kernel_parameter_names();
        inputs.push(Arg::new(
            "params",
            Shape::Vector(indices.len()),
            indices.iter().map(|&i| all[i].clone()).collect(),
            "robot parameters (`Robot::kernel_parameters`: each body's first moment `m c` and \
             inertia about its reference point), in the order of the names in this signature",
        ));
        inputs.len() - 1
    });
    if reads_robot {
        doc.push_str(if params_at.is_some() {
            "\nThe robot's parameters listed in `params` are inputs; the others are folded in."
        } else {
            "\nThe robot's parameters are folded in as constants."
        });
    }
    if guarded {
        outputs.push(Arg::output(DIVISORS.name, DIVISORS.shape, DIVISORS.doc));
        doc.push_str("\nThe last result holds the divisors of eq 16 for a singularity check.");
    }
    let position = |input: Input| decl.inputs.iter().position(|&i| i == input);
    // The third motion input of a kernel is the acceleration, or the forces `Γ` of the forward
    // dynamics; it reaches the build as `motion.accel`.
    let (twist_at, accel_at) = (
        position(Input::Twist),
        position(Input::Accel).or(position(Input::Gamma)),
    );
    let robot = *robot;
    let indices = indices.to_vec();
    let build = decl.build;
    KernelSpec {
        name: format!("{}{suffix}", decl.name),
        model,
        setting,
        equations: equations.iter().map(|s| s.to_string()).collect(),
        title: decl.title.to_string(),
        doc,
        chapter: decl.chapter,
        objective,
        inputs,
        outputs,
        build: Box::new(move |g, i| match build {
            Build::Free(f) => f(g, i),
            Build::Pose { build, .. } => {
                let sym = symbolic_parameters(g, &robot, &indices, params_at.map(|k| &i[k]));
                let posed = geometry::pose(sym[0], &i[0]);
                let motion = Motion {
                    twist: twist_at.map_or_else(|| Vec6::zeros(g), |k| vec6(&i[k])),
                    accel: accel_at.map_or_else(|| Vec6::zeros(g), |k| vec6(&i[k])),
                };
                let dynamics = Dynamics::from_kernel_parameters(g, &sym);
                let mut results = build(mech, &dynamics, &posed, &motion);
                if guarded {
                    results.push(geometry::divisors(&posed.r));
                }
                results
            }
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(names: &[&str]) -> ParameterSet {
        ParameterSet::Named(names.iter().map(|s| s.to_string()).collect())
    }

    #[test]
    fn named_parameters_keep_the_order_given() {
        let names = Robot::<f64>::kernel_parameter_names();
        let at = |n: &str| names.iter().position(|x| x == n).unwrap();
        let indices = named(&["gravity_z", "gravity_x", "platform_mass"])
            .indices()
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
    fn unknown_and_repeated_names_are_refused() {
        let e = named(&["gravity_w"]).indices().unwrap_err().to_string();
        assert!(e.starts_with("unknown parameter `gravity_w`"), "{e}");
        let e = named(&["gravity_x", "gravity_x"])
            .indices()
            .unwrap_err()
            .to_string();
        assert_eq!(e, "parameter `gravity_x` is named twice");
    }
}
