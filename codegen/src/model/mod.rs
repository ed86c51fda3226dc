//! The C5 robot's kernels: which equations each one computes, in which setting, from what.
//!
//! This is the only place that knows both the robot and the kernel list; the engine sees
//! [`KernelSpec`]s and nothing else.

pub mod equations;

use crate::dag::{Expr, Graph};
use crate::kernel::{Arg, ChapterCount, KernelSpec, Objective, Shape};
use crate::linalg::{Vec3, Vec6, Vector};
use crate::robot::Robot;
use equations as eq;

/// Which robot parameters are kernel inputs; the others are folded in as constants.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub enum ParameterSet {
    /// Every parameter folded (the fastest kernels).
    #[default]
    None,
    /// Every parameter an input (one kernel set for any robot).
    All,
    /// These parameters (names of [`Robot::parameter_names`]) are inputs.
    Named(Vec<String>),
}

impl ParameterSet {
    /// Indices into the parameter vector of the parameters that are inputs.
    pub fn indices(&self) -> Vec<usize> {
        let names = Robot::<f64>::parameter_names();
        match self {
            ParameterSet::None => vec![],
            ParameterSet::All => (0..names.len()).collect(),
            ParameterSet::Named(chosen) => names
                .iter()
                .enumerate()
                .filter(|(_, n)| chosen.contains(n))
                .map(|(i, _)| i)
                .collect(),
        }
    }
}

fn pose_arg() -> Arg {
    Arg::new(
        "pose",
        Shape::Vector(6),
        ["alpha", "beta", "gamma", "xc", "yc", "zc"]
            .map(String::from)
            .to_vec(),
        "platform pose `[α β γ xc yc zc]` (rad, m), RPY as eq 15",
    )
}

fn twist_arg() -> Arg {
    Arg::new(
        "twist",
        Shape::Vector(6),
        ["wx", "wy", "wz", "vx", "vy", "vz"]
            .map(String::from)
            .to_vec(),
        "platform twist `(ω; v_C)` at `C`, base frame (rad/s, m/s)",
    )
}

fn accel_arg() -> Arg {
    Arg::new(
        "accel",
        Shape::Vector(6),
        ["wdx", "wdy", "wdz", "ax", "ay", "az"]
            .map(String::from)
            .to_vec(),
        "classical platform acceleration `(ω̇; a_C)`, `a_C = d v_C/dt` (rad/s², m/s²)",
    )
}

fn p_arg() -> Arg {
    let elements = (1..=6)
        .flat_map(|i| ["x", "y", "z"].map(|c| format!("{c}{i}")))
        .collect();
    Arg::new(
        "p",
        Shape::Matrix(6, 3),
        elements,
        "`p[i] = P_i2 = [x_i y_i z_i]`, from `B_i` to `C` for segment `i+1` (eq 27)",
    )
}

fn matrix_rows<'g>(m: &crate::linalg::Mat6<'g>) -> Vec<Expr<'g>> {
    m.rows()
}

fn p_rows<'g>(p: &[Expr<'g>]) -> [Vec3<'g>; 6] {
    std::array::from_fn(|i| Vector([p[3 * i], p[3 * i + 1], p[3 * i + 2]]))
}

fn vec6<'g>(v: &[Expr<'g>]) -> Vec6<'g> {
    Vector(std::array::from_fn(|i| v[i]))
}

const JINV_DOC: &str = "`J⁻¹`, row `i` for segment `i+1`, columns `[ωx ωy ωz vx vy vz]`";
const J_DOC: &str = "`J`, rows `[ωx ωy ωz vx vy vz]`, column `i` for segment `i+1`";
const ORDER_NOTE: &str = "Actuators are in segment order 1..6; the chapter lists them 6..1.";

/// The kernels of the chapter's own setting: the components of `P_i2` are free inputs.
pub fn chapter_kernels() -> Vec<KernelSpec> {
    let spec = |name: &str, eqs: &[&str], title: &str, chapter: (u32, u32)| KernelSpec {
        name: name.to_string(),
        setting: "chapter".to_string(),
        equations: eqs.iter().map(|s| s.to_string()).collect(),
        title: title.to_string(),
        doc: ORDER_NOTE.to_string(),
        chapter: Some(ChapterCount {
            m: chapter.0,
            a: chapter.1,
        }),
        objective: Objective::ChapterCount,
        inputs: vec![p_arg()],
        outputs: vec![],
        build: Box::new(|_, _| vec![]),
    };
    let mut inverse_jacobian = spec(
        "inverse_jacobian",
        &["22"],
        "Inverse Jacobian `J⁻¹` of the paper model, rows `[(n_i × P_i2)ᵀ n_iᵀ]`.",
        (18, 30),
    );
    inverse_jacobian.outputs = vec![Arg::output("jinv", Shape::Matrix(6, 6), JINV_DOC)];
    inverse_jacobian.build =
        Box::new(|_, i| vec![matrix_rows(&eq::inverse_jacobian(&p_rows(&i[0])))]);

    let mut pi1 = spec(
        "pi1",
        &["36", "37", "38", "39"],
        "`Π1`, the map from actuator rates to the joint rates of segment 1, `Q̇_1 = Π1 Q̇_a`.",
        (17, 28),
    );
    pi1.outputs = vec![Arg::output(
        "pi1",
        Shape::Matrix(6, 6),
        "rows `[ẇ_p1 u̇_p1 γ̇_p β̇_p α̇_p Q̇_11]`, column `i` for segment `i+1`",
    )];
    pi1.build = Box::new(|_, i| vec![matrix_rows(&eq::pi1(&p_rows(&i[0])))]);

    let mut jacobian = spec(
        "jacobian",
        &["39", "40", "41"],
        "Jacobian in factored form, `J = J1 Π1`, including `Π1`.",
        (29 + 17, 37 + 28),
    );
    jacobian.doc = format!(
        "{ORDER_NOTE}\nThe chapter's count for eq 40 alone is 29m + 37a; with `Π1` it is 46m + 65a."
    );
    jacobian.outputs = vec![Arg::output("jacobian", Shape::Matrix(6, 6), J_DOC)];
    jacobian.build = Box::new(|_, i| vec![matrix_rows(&eq::jacobian(&p_rows(&i[0])))]);

    let mut qdd = spec(
        "joint_accelerations_segment",
        &["43", "44", "45", "46", "47", "48"],
        "Joint accelerations of segment 1 by projection, `Q̈_1 = [Q̈_12; Q̈_11]`.",
        (10, 10),
    );
    qdd.doc = "Every segment costs the same; segment 1 is generated here.".to_string();
    qdd.inputs = vec![
        Arg::new(
            "p1",
            Shape::Vector(3),
            vec!["x1".into(), "y1".into(), "z1".into()],
            "`P_12 = [x1 y1 z1]` (eq 27)",
        ),
        Arg::new(
            "vdot",
            Shape::Vector(6),
            ["wdx", "wdy", "wdz", "ax", "ay", "az"]
                .map(String::from)
                .to_vec(),
            "spatial platform acceleration `V̇_{N+1} = (ω̇; a_C - ω × v_C)`",
        ),
    ];
    qdd.outputs = vec![Arg::output(
        "qdd",
        Shape::Vector(6),
        "`[ẅ_p1 ü_p1 γ̈_p β̈_p α̈_p Q̈_11]`",
    )];
    qdd.build = Box::new(|_, i| {
        let p = Vector([i[0][0], i[0][1], i[0][2]]);
        vec![eq::joint_accelerations_segment(&p, &vec6(&i[1]), 0).to_vec()]
    });

    let mut step6 = spec(
        "step6_factored",
        &["62"],
        "Step 6 of the inverse dynamics, `Γ = Π1ᵀ J1ᵀ K`, with no linear solve.",
        (65, 67),
    );
    step6.inputs = vec![
        p_arg(),
        Arg::new(
            "k",
            Shape::Vector(6),
            ["knx", "kny", "knz", "kfx", "kfy", "kfz"]
                .map(String::from)
                .to_vec(),
            "`K = F_{N+1} + Φ` at `C`, moment first (N·m, N)",
        ),
    ];
    step6.outputs = vec![Arg::output(
        "gamma",
        Shape::Vector(6),
        "`Γ` (N), segment order",
    )];
    step6.build = Box::new(|_, i| vec![eq::step6_factored(&p_rows(&i[0]), &vec6(&i[1])).to_vec()]);

    vec![inverse_jacobian, pi1, jacobian, qdd, step6]
}

/// The divisors of the equations, so a caller can refuse a singular state before dividing:
/// `r11, r22, r33` (eq 16, pose setting) and `y5 - y6, z1 - z2, x3 - x4` (eq 39, chapter
/// setting; in the pose setting these are the constant `-2L`).
pub fn divisor_kernels() -> Vec<KernelSpec> {
    let mut eq16 = KernelSpec {
        name: "singularity_terms".to_string(),
        setting: "pose".to_string(),
        equations: vec!["15".into(), "16".into()],
        title: "The divisors of eq 16, `[r11 r22 r33]`: the pose is singular where one vanishes."
            .to_string(),
        doc: String::new(),
        chapter: None,
        objective: Objective::Speed,
        inputs: vec![pose_arg()],
        outputs: vec![Arg::output("r", Shape::Vector(3), "`[r11 r22 r33]`")],
        build: Box::new(|_, i| {
            let x = &i[0];
            let sin = Vector([x[0].sin(), x[1].sin(), x[2].sin()]);
            let cos = Vector([x[0].cos(), x[1].cos(), x[2].cos()]);
            let r = eq::rotation(sin, cos);
            vec![vec![r.0[0][0], r.0[1][1], r.0[2][2]]]
        }),
    };
    eq16.doc = "Cheaper than the kernels it guards: one check before them costs a few ns.".into();
    let eq39 = KernelSpec {
        name: "pi1_denominators".to_string(),
        setting: "chapter".to_string(),
        equations: vec!["39".into()],
        title: "The denominators of `Π1`, `[y5 - y6, z1 - z2, x3 - x4]`.".to_string(),
        doc: String::new(),
        chapter: None,
        objective: Objective::ChapterCount,
        inputs: vec![p_arg()],
        outputs: vec![Arg::output(
            "d",
            Shape::Vector(3),
            "`[y5 - y6, z1 - z2, x3 - x4]` (m)",
        )],
        build: Box::new(|_, i| {
            let p = p_rows(&i[0]);
            vec![vec![
                p[4][1] - p[5][1],
                p[0][2] - p[1][2],
                p[2][0] - p[3][0],
            ]]
        }),
    };
    vec![eq16, eq39]
}

/// The robot as the kernels see it: folded constants, or entries of the `params` input.
fn symbolic_robot<'g>(
    g: &'g Graph,
    robot: &Robot,
    inputs: &[usize],
    params: Option<&Vec<Expr<'g>>>,
) -> Robot<Expr<'g>> {
    let values = robot.flatten();
    let flat: Vec<Expr<'g>> = values
        .iter()
        .enumerate()
        .map(
            |(k, &v)| match (inputs.iter().position(|&i| i == k), params) {
                (Some(pos), Some(p)) => p[pos],
                _ => g.constant(v),
            },
        )
        .collect();
    Robot::unflatten(&flat)
}

/// Builds a pose-setting kernel's outputs from the symbolic robot, the expanded pose and the
/// motion inputs (twist, acceleration).
type PoseBuild =
    for<'g> fn(&Robot<Expr<'g>>, &eq::Posed<'g>, &[Vec<Expr<'g>>]) -> Vec<Vec<Expr<'g>>>;

/// The pose-setting kernels that divide by `r11`, `r22` or `r33` (eq 16). The others use
/// `J⁻¹` or `J`, which in the paper model do not depend on the orientation, or only `R`.
const GUARDED: [&str; 4] = [
    "inverse_kinematics",
    "joint_accelerations",
    "leg_wrench",
    "inverse_dynamics",
];

/// The kernels of the pose setting, expanded end to end from the platform state.
///
/// `suffix` is appended to every kernel name (`"_params"` for the runtime-parameter set).
pub fn pose_kernels(robot: &Robot, parameters: &ParameterSet, suffix: &str) -> Vec<KernelSpec> {
    let inputs = parameters.indices();
    let all_names = Robot::<f64>::parameter_names();
    let params_arg = (!inputs.is_empty()).then(|| {
        Arg::new(
            "params",
            Shape::Vector(inputs.len()),
            inputs.iter().map(|&i| all_names[i].clone()).collect(),
            "robot parameters in the order of `Robot::flatten` (those chosen as inputs)",
        )
    });
    let folded = if inputs.is_empty() {
        "The robot's parameters are folded in as constants."
    } else {
        "The robot's parameters listed in `params` are inputs; the others are folded in."
    };
    let mut out = Vec::new();
    let mut add = |name: &str,
                   eqs: &[&str],
                   title: &str,
                   motion: usize,
                   outputs: Vec<Arg>,
                   build: PoseBuild| {
        let mut args = vec![pose_arg(), twist_arg(), accel_arg()];
        args.truncate(motion);
        let n_motion = args.len();
        args.extend(params_arg.clone());
        let robot = *robot;
        let inputs = inputs.clone();
        // Kernels that go through eq 16 also return its divisors, so a caller can refuse a
        // singular pose without a second evaluation of the trigonometry.
        let guarded = GUARDED.contains(&name);
        let mut outputs = outputs;
        let mut doc = format!("{ORDER_NOTE}\n{folded}");
        if guarded {
            outputs.push(Arg::output(
                "r",
                Shape::Vector(3),
                "`[r11 r22 r33]`, the divisors of eq 16: the results are meaningless where one \
                 is near zero",
            ));
            doc.push_str("\nThe last result holds the divisors of eq 16 for a singularity check.");
        }
        out.push(KernelSpec {
            name: format!("{name}{suffix}"),
            setting: "pose".to_string(),
            equations: eqs.iter().map(|s| s.to_string()).collect(),
            title: title.to_string(),
            doc,
            chapter: None,
            objective: Objective::Speed,
            inputs: args,
            outputs,
            build: Box::new(move |g, i| {
                let sym = symbolic_robot(g, &robot, &inputs, i.get(n_motion));
                let posed = eq::pose(&sym, &i[0]);
                let mut results = build(&sym, &posed, &i[1..n_motion]);
                if guarded {
                    let r = &posed.frame.r.0;
                    results.push(vec![r[0][0], r[1][1], r[2][2]]);
                }
                results
            }),
        });
    };
    add(
        "inverse_kinematics",
        &["15", "16", "27"],
        "Inverse kinematics: actuator lengths `Q_i1` and the vectors `P_i2`.",
        1,
        vec![
            Arg::output("q", Shape::Vector(6), "`Q_i1` (m), segment order"),
            Arg::output("p", Shape::Matrix(6, 3), "`P_i2` from `B_i` to `C` (m)"),
        ],
        |_, posed, _| {
            vec![
                posed.q.to_vec(),
                posed.p.iter().flat_map(|v| v.to_vec()).collect(),
            ]
        },
    );
    add(
        "inverse_jacobian_pose",
        &["15", "16", "22", "27"],
        "Inverse Jacobian `J⁻¹` (paper model) at a pose.",
        1,
        vec![Arg::output("jinv", Shape::Matrix(6, 6), JINV_DOC)],
        |_, posed, _| vec![eq::inverse_jacobian(&posed.p).rows()],
    );
    add(
        "jacobian_pose",
        &["15", "16", "27", "39", "40", "41"],
        "Jacobian `J = J1 Π1` at a pose.",
        1,
        vec![Arg::output("jacobian", Shape::Matrix(6, 6), J_DOC)],
        |_, posed, _| vec![eq::jacobian(&posed.p).rows()],
    );
    add(
        "joint_velocities",
        &["20", "22"],
        "Actuator rates `Q̇_a = J⁻¹ V`.",
        2,
        vec![Arg::output(
            "qd",
            Shape::Vector(6),
            "`Q̇_i1` (m/s), segment order",
        )],
        |_, posed, m| vec![eq::joint_velocities(posed, &vec6(&m[0])).to_vec()],
    );
    add(
        "joint_accelerations",
        &["43", "44", "45", "46", "47", "48"],
        "Joint accelerations of every segment by projection.",
        3,
        vec![
            Arg::output("qdd", Shape::Vector(6), "`Q̈_i1` (m/s²), segment order"),
            Arg::output(
                "legs",
                Shape::Matrix(6, 6),
                "row `i`: `Q̈_i = [ẅ_p ü_p γ̈_p β̈_p α̈_p Q̈_i1]` of segment `i+1`",
            ),
        ],
        |_, posed, m| {
            let vdot = eq::spatial_acceleration(&vec6(&m[0]), &vec6(&m[1]));
            let legs: Vec<Vec6<'_>> = (0..6)
                .map(|i| eq::joint_accelerations_segment(&posed.p[i], &vdot, i))
                .collect();
            vec![
                legs.iter().map(|l| l[5]).collect(),
                legs.iter().flat_map(|l| l.to_vec()).collect(),
            ]
        },
    );
    add(
        "leg_wrench",
        &["43", "48", "49", "50", "60"],
        "The legs' contribution `Φ = Σ P̂_i2⁻¹ J_Bi⁻ᵀ T_i` at `C`.",
        3,
        vec![Arg::output(
            "phi",
            Shape::Vector(6),
            "`Φ = (n; f)` at `C` (N·m, N)",
        )],
        |sym, posed, m| {
            let (twist, accel) = (vec6(&m[0]), vec6(&m[1]));
            let vdot = eq::spatial_acceleration(&twist, &accel);
            vec![eq::leg_wrench(sym, posed, &twist, &vdot).to_vec()]
        },
    );
    add(
        "platform_wrench",
        &["52", "54", "55", "56", "57"],
        "The platform's wrench `F_{N+1} = Λ_C V̇ + C_C + G_C` at `C`.",
        3,
        vec![Arg::output(
            "f",
            Shape::Vector(6),
            "`F_{N+1} = (n; f)` (N·m, N)",
        )],
        |sym, posed, m| {
            vec![eq::platform_wrench(sym, &posed.frame, &vec6(&m[0]), &vec6(&m[1])).to_vec()]
        },
    );
    add(
        "inverse_dynamics",
        &["15", "16", "27", "43-48", "49-57", "60", "62"],
        "Inverse dynamics end to end: actuator forces `Γ` from the platform state.",
        3,
        vec![Arg::output(
            "gamma",
            Shape::Vector(6),
            "`Γ` (N), segment order",
        )],
        |sym, posed, m| vec![eq::inverse_dynamics(sym, posed, &vec6(&m[0]), &vec6(&m[1])).to_vec()],
    );
    out
}
