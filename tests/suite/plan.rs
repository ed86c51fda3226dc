//! The minimum-effort planner (`c5_runtime::plan`): it converges on a short move (each round's
//! cost strictly decreasing, the end at the goal to 1e-6, the forces within their limit), its
//! forces drive the robot's own forward dynamics to the goal when integrated finely
//! (mechanics, not the planner's model of itself), and it spends less effort than the quintic
//! move of the same duration, which is one of the moves it chooses among. Each holds for every
//! mechanism with derivative kernels: the C5 and the Gough-Stewart platform.

use c5_robot::GoughStewart as HexapodDescription;
use c5_runtime::dynamics::{rk4_step, PlantState};
use c5_runtime::plan::{plan, PlanError, Problem, Settings};
use c5_runtime::trajectory::LinearMove;
use c5_runtime::{Error, GoughStewart, Pose, Robot, RusHexapod, SpatialRobot, State, C5};

/// The robots the planner serves, each with its home pose: the C5's is the origin, the
/// hexapod's above its base.
fn robots() -> Vec<(Box<dyn SpatialRobot>, [f64; 6])> {
    let hexapod = HexapodDescription::example();
    let home = hexapod.home();
    vec![
        (Box::new(C5::new(Robot::default()).unwrap()), [0.0; 6]),
        (Box::new(GoughStewart::new(hexapod).unwrap()), home),
    ]
}

/// A short turned move of the centre, from `home`.
fn problem(home: [f64; 6], force_limit: Option<f64>) -> Problem {
    let deg = std::f64::consts::PI / 180.0;
    let from = |offset: [f64; 6]| Pose::from_array(std::array::from_fn(|i| home[i] + offset[i]));
    Problem {
        start: from([10.0 * deg, 15.0 * deg, 20.0 * deg, 0.0, 0.0, 0.0]),
        goal: from([10.0 * deg, 15.0 * deg, 20.0 * deg, 0.02, 0.015, 0.025]),
        duration: 0.3,
        steps: 60,
        force_limit,
    }
}

/// `Σ dt |Γ|²` of forces held over steps of `dt`.
fn effort(forces: &[[f64; 6]], dt: f64) -> f64 {
    forces.iter().flatten().map(|f| f * f * dt).sum()
}

#[test]
fn a_short_move_converges_to_the_goal_within_the_limits() {
    for (robot, home) in robots() {
        converges_within_the_limits(robot.as_ref(), problem(home, None));
    }
}

fn converges_within_the_limits(robot: &dyn SpatialRobot, problem: Problem) {
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
fn open_loop_error(robot: &dyn SpatialRobot, problem: &Problem) -> f64 {
    let p = plan(robot, problem, &Settings::default()).unwrap();
    let dt = problem.duration / problem.steps as f64;
    let mut plant = PlantState::new(&problem.start, &State::default().twist);
    let mut t = 0.0;
    for forces in &p.forces {
        for _ in 0..10 {
            plant = rk4_step(robot, &plant, t, dt / 10.0, |_, _| Ok(*forces)).unwrap();
            t += dt / 10.0;
        }
    }
    let (end, goal) = (plant.pose().to_array(), problem.goal.to_array());
    end.iter()
        .zip(&goal)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_plans_forces_drive_the_robot_to_the_goal() {
    for (robot, home) in robots() {
        let robot = robot.as_ref();
        // The plan integrates by explicit Euler: open loop, the robot misses the goal by that
        // step's error, which falls with the step (first order), and nothing else.
        let coarse = open_loop_error(robot, &problem(home, None));
        let fine = open_loop_error(
            robot,
            &Problem {
                steps: 600,
                ..problem(home, None)
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
    for (robot, home) in robots() {
        less_effort_than_the_quintic(robot.as_ref(), problem(home, None));
    }
}

fn less_effort_than_the_quintic(robot: &dyn SpatialRobot, problem: Problem) {
    let p = plan(robot, &problem, &Settings::default()).unwrap();
    let dt = problem.duration / problem.steps as f64;
    let quintic = LinearMove {
        start: problem.start,
        end: problem.goal.center,
        duration: problem.duration,
    };
    let quintic_forces: Vec<[f64; 6]> = (0..problem.steps)
        .map(|k| {
            robot
                .inverse_dynamics(&quintic.state((k as f64 + 0.5) * dt))
                .unwrap()
        })
        .collect();
    let (planned, reference) = (effort(&p.forces, dt), effort(&quintic_forces, dt));
    assert!(
        planned < reference,
        "{}: plan {planned}, quintic {reference}",
        robot.mechanism()
    );
}

#[test]
fn bad_problems_are_refused_by_name() {
    let robot = C5::new(Robot::default()).unwrap();
    let mut p = problem([0.0; 6], None);
    p.duration = 0.0;
    let e = plan(&robot, &p, &Settings::default()).unwrap_err();
    assert!(matches!(e, PlanError::Invalid(why) if why.contains("duration")));
    let mut p = problem([0.0; 6], Some(-1.0));
    p.steps = 10;
    let e = plan(&robot, &p, &Settings::default()).unwrap_err();
    assert!(matches!(e, PlanError::Invalid(why) if why.contains("force_limit")));
}

/// A mechanism without derivative kernels (the rotary hexapod) is refused by name before any
/// step is taken.
#[test]
fn a_robot_without_derivatives_is_refused_by_name() {
    let rus = RusHexapod::new(c5_robot::RusHexapod::example()).unwrap();
    let home = rus.home().to_array();
    let e = plan(&rus, &problem(home, None), &Settings::default()).unwrap_err();
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
