//! The minimum-effort planner (`c5_runtime::plan`): it converges on a short move (each round's
//! cost strictly decreasing, the end at the goal to 1e-6, the forces within their limit), its
//! forces drive the robot's own forward dynamics to the goal when integrated finely
//! (mechanics, not the planner's model of itself), and it spends less effort than the quintic
//! move of the same duration, which is one of the moves it chooses among. Each holds for every
//! mechanism with derivative kernels, in its platform's coordinates: the C5, the Gough-Stewart
//! platform and the Delta. A longer move, where the minimum effort lies at a singular pose,
//! stays in the workspace asked for.

use c5_robot::Description;
use c5_runtime::plan::{plan, quintic_forces, PlanError, Problem, Settings, LEAST_CLEARANCE};
use c5_runtime::platform::load;
use c5_runtime::{Error, Mechanism, Model, Robot};

/// The robots the planner serves, each loaded as a mechanism.
fn robots() -> Vec<Box<dyn Mechanism>> {
    [
        Description::C5(Robot::default()),
        Description::GoughStewart(c5_robot::GoughStewart::example()),
        Description::Delta(c5_robot::Delta::example()),
    ]
    .into_iter()
    .map(|d| load(d, Model::Consistent).unwrap())
    .collect()
}

/// A short move of the centre from the robot's home, turned where the platform turns.
fn problem(robot: &dyn Mechanism, force_limit: Option<f64>) -> Problem {
    let deg = std::f64::consts::PI / 180.0;
    let home = robot.home();
    let n = home.len();
    let from = |centre: [f64; 3]| -> Vec<f64> {
        let turned = [10.0 * deg, 15.0 * deg, 20.0 * deg];
        let offset: Vec<f64> = turned[..n - 3].iter().chain(&centre).copied().collect();
        home.iter().zip(offset).map(|(h, o)| h + o).collect()
    };
    Problem {
        start: from([0.0; 3]),
        goal: from([0.02, 0.015, 0.025]),
        duration: 0.3,
        steps: 60,
        force_limit,
        least_clearance: LEAST_CLEARANCE,
    }
}

/// `Σ dt |Γ|²` of forces held over steps of `dt`.
fn effort(forces: &[Vec<f64>], dt: f64) -> f64 {
    forces.iter().flatten().map(|f| f * f * dt).sum()
}

#[test]
fn a_short_move_converges_to_the_goal_within_the_limits() {
    for robot in robots() {
        converges_within_the_limits(robot.as_ref(), problem(robot.as_ref(), None));
    }
}

fn converges_within_the_limits(robot: &dyn Mechanism, problem: Problem) {
    let free = plan(robot, &problem, &Settings::default()).unwrap();
    assert!(free.goal_error <= 1e-6, "goal error {:e}", free.goal_error);
    for round in &free.costs {
        assert!(round.windows(2).all(|w| w[1] < w[0]), "{round:?}");
    }
    assert!(free.iterations < Settings::default().max_iterations);
    let peak = free
        .forces
        .iter()
        .flatten()
        .fold(0.0_f64, |m, f| m.max(f.abs()));
    // A limit below the free plan's peak force binds, and is kept.
    let limit = 0.9 * peak;
    let limited = Problem {
        force_limit: Some(limit),
        ..problem.clone()
    };
    let bound = plan(robot, &limited, &Settings::default()).unwrap();
    assert!(bound.goal_error <= 1e-6);
    assert!(
        bound.force_excess <= 1e-6,
        "excess {:e} N",
        bound.force_excess
    );
    let dt = problem.duration / problem.steps as f64;
    // Keeping the limit costs effort: the free plan is the cheaper.
    assert!(effort(&free.forces, dt) < effort(&bound.forces, dt));
}

/// How far from the goal the robot ends under the plan's forces, integrated by RK4 at a tenth
/// of the plan's step (the robot's own forward dynamics, not the planner's Euler model).
fn open_loop_error(robot: &dyn Mechanism, problem: &Problem) -> f64 {
    let p = plan(robot, problem, &Settings::default()).unwrap();
    let dt = problem.duration / problem.steps as f64;
    let mut pose = problem.start.clone();
    let mut twist = vec![0.0; pose.len()];
    for forces in &p.forces {
        for _ in 0..10 {
            robot
                .step_held(&mut pose, &mut twist, forces, dt / 10.0)
                .unwrap();
        }
    }
    pose.iter()
        .zip(&problem.goal)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_plans_forces_drive_the_robot_to_the_goal() {
    for robot in robots() {
        let robot = robot.as_ref();
        // The plan integrates by explicit Euler: open loop, the robot misses the goal by that
        // step's error, which falls with the step (first order), and nothing else.
        let coarse = open_loop_error(robot, &problem(robot, None));
        let fine = open_loop_error(
            robot,
            &Problem {
                steps: 600,
                ..problem(robot, None)
            },
        );
        let distance = 0.025_f64.hypot(0.02).hypot(0.015);
        let name = robot.mechanism();
        assert!(
            coarse > 5.0 * fine,
            "{name}: 60 steps: {coarse:e}, 600 steps: {fine:e}"
        );
        assert!(
            fine < 0.02 * distance,
            "{name}: 600 steps: {fine:e} from the goal"
        );
    }
}

#[test]
fn the_plan_spends_less_effort_than_the_quintic() {
    for robot in robots() {
        let robot = robot.as_ref();
        let problem = problem(robot, None);
        let p = plan(robot, &problem, &Settings::default()).unwrap();
        let dt = problem.duration / problem.steps as f64;
        let quintic = quintic_forces(robot, &problem).unwrap();
        let (planned, reference) = (effort(&p.forces, dt), effort(&quintic, dt));
        assert!(
            planned < reference,
            "{}: plan {planned}, quintic {reference}",
            robot.mechanism()
        );
    }
}

/// Section 9's move of the centre (4, 3, 5 cm) from the example Delta's home in a second: the
/// effort is least where a crank and its rods align and the arm holds the platform's weight
/// with no torque, so the plan, free, sags towards that edge of the reach.
fn delta_sagging_move(least_clearance: f64) -> (Box<dyn Mechanism>, Problem) {
    let delta = load(
        Description::Delta(c5_robot::Delta::example()),
        Model::Consistent,
    )
    .unwrap();
    let home = delta.home();
    let goal = home
        .iter()
        .zip([0.04, 0.03, 0.05])
        .map(|(h, d)| h + d)
        .collect();
    let problem = Problem {
        start: home,
        goal,
        duration: 1.0,
        steps: 200,
        force_limit: None,
        least_clearance,
    };
    (delta, problem)
}

#[test]
fn the_plan_keeps_the_clearance_asked_where_the_least_effort_is_singular() {
    let (delta, problem) = delta_sagging_move(LEAST_CLEARANCE);
    let delta = delta.as_ref();
    let kept = plan(delta, &problem, &Settings::default()).unwrap();
    assert!(kept.goal_error <= 1e-8, "goal error {:e}", kept.goal_error);
    // The constraint binds: the plan runs along the bound, and not below it.
    assert!(
        (kept.least_clearance - LEAST_CLEARANCE).abs() <= 1e-4,
        "least clearance {:e}",
        kept.least_clearance
    );
    let least = kept
        .states
        .iter()
        .map(|s| {
            let [pose, ..] = delta.coordinates_of(s).unwrap();
            delta.singularity_clearance(&pose).unwrap()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(least >= LEAST_CLEARANCE - 1e-6, "a state at {least:e}");
    // Free of it, the plan goes nearer the singular pose than the bound allows.
    let (_, free) = delta_sagging_move(0.0);
    let nearer = match plan(delta, &free, &Settings::default()) {
        Ok(p) => p.least_clearance,
        Err(PlanError::NotConverged {
            least_clearance, ..
        }) => least_clearance,
        Err(e) => panic!("{e}"),
    };
    assert!(nearer < 0.1 * LEAST_CLEARANCE, "free: {nearer:e}");
}

#[test]
fn bad_problems_are_refused_by_name() {
    let robots = robots();
    let robot = robots[0].as_ref();
    let mut p = problem(robot, None);
    p.duration = 0.0;
    let e = plan(robot, &p, &Settings::default()).unwrap_err();
    assert!(matches!(e, PlanError::Invalid(why) if why.contains("duration")));
    let mut p = problem(robot, Some(-1.0));
    p.steps = 10;
    let e = plan(robot, &p, &Settings::default()).unwrap_err();
    assert!(matches!(e, PlanError::Invalid(why) if why.contains("force_limit")));
    // A Delta's poses have three coordinates: six are refused, not truncated.
    let delta = robots[2].as_ref();
    let e = plan(delta, &problem(robot, None), &Settings::default()).unwrap_err();
    assert!(
        matches!(e, PlanError::Invalid(why) if why.contains("coordinates")),
        "{e}"
    );
    // A negative clearance, and a start closer to a singular pose than the clearance asked.
    let mut p = problem(robot, None);
    p.least_clearance = -0.1;
    let e = plan(robot, &p, &Settings::default()).unwrap_err();
    assert!(matches!(e, PlanError::Invalid(why) if why.contains("least_clearance")));
    let home_clearance = robot.singularity_clearance(&robot.home()).unwrap();
    let mut p = problem(robot, None);
    p.start = robot.home();
    p.least_clearance = 1.01 * home_clearance;
    let e = plan(robot, &p, &Settings::default()).unwrap_err();
    assert!(
        matches!(e, PlanError::Invalid(why) if why.contains("least clearance")),
        "{e}"
    );
}

/// A mechanism without derivative kernels (the rotary hexapod) is refused by name before any
/// step is taken.
#[test]
fn a_robot_without_derivatives_is_refused_by_name() {
    let rus = load(
        Description::RusHexapod(c5_robot::RusHexapod::example()),
        Model::Consistent,
    )
    .unwrap();
    let e = plan(
        rus.as_ref(),
        &problem(rus.as_ref(), None),
        &Settings::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            PlanError::Dynamics(Error::Unsupported {
                what: "derivatives",
                ..
            })
        ),
        "{e}"
    );
}
