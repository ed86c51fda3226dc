//! Identification of the legged mechanisms (the Gough-Stewart platform, the rotary hexapod),
//! one set of checks over `ParallelRobot` run on each: the regressor times the standard
//! parameters is the inverse dynamics plus friction; the base parameters the runtime finds
//! for a geometry no generated file folds in carry its forces; an unseen robot's masses,
//! friction and inertias come back from noise-free motion and forces along an exciting
//! trajectory designed on its geometry alone.

use crate::support::rng;
use c5_runtime::identify::excite::{self, Envelope, Search};
use c5_runtime::identify::{Friction, Identifier};
use c5_runtime::{GoughStewart, ParallelRobot, Pose, RusHexapod, State};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// One legged mechanism's robots for the checks.
struct Case {
    /// The robot whose forces are measured.
    truth: Box<dyn ParallelRobot>,
    /// Its geometry with the checked-in example's masses: what an identifier knows.
    blank: Box<dyn ParallelRobot>,
    /// A state about home.
    state: fn(&mut ChaCha8Rng, &Pose) -> State,
}

fn hexapod(r: &mut ChaCha8Rng) -> Case {
    let robot = super::gough_stewart::random_hexapod(r);
    let example = c5_robot::GoughStewart::example();
    let mut blank = robot;
    blank.platform = example.platform;
    for (leg, nominal) in blank.legs.iter_mut().zip(&example.legs) {
        leg.cylinder = nominal.cylinder;
        leg.rod = nominal.rod;
    }
    Case {
        truth: Box::new(GoughStewart::new(robot).unwrap()),
        blank: Box::new(GoughStewart::new(blank).unwrap()),
        state: super::gough_stewart::random_state,
    }
}

fn rotary_hexapod(r: &mut ChaCha8Rng) -> Case {
    let robot = super::rus_hexapod::jittered(r);
    let example = c5_robot::RusHexapod::example();
    let mut blank = robot;
    blank.platform = example.platform;
    for (leg, nominal) in blank.legs.iter_mut().zip(&example.legs) {
        leg.crank = nominal.crank;
        leg.rod = nominal.rod;
    }
    Case {
        truth: Box::new(RusHexapod::new(robot).unwrap()),
        blank: Box::new(RusHexapod::new(blank).unwrap()),
        state: super::rus_hexapod::near_home,
    }
}

fn cases(seed: u64) -> Vec<(&'static str, Case)> {
    let mut r = rng(seed);
    vec![
        ("gough-stewart", hexapod(&mut r)),
        ("rus-hexapod", rotary_hexapod(&mut r)),
    ]
}

fn random_friction(r: &mut ChaCha8Rng) -> [Friction; 6] {
    std::array::from_fn(|_| Friction {
        viscous: r.gen_range(1.0..20.0),
        coulomb: r.gen_range(0.5..5.0),
    })
}

/// What the actuators of `robot` with `friction` apply at `state`: the inverse dynamics plus
/// friction on the actuator rates.
fn measured(robot: &dyn ParallelRobot, friction: &[Friction; 6], state: &State) -> [f64; 6] {
    let gamma = robot.inverse_dynamics(state).unwrap();
    let qd = robot.joint_velocities(&state.pose, &state.twist).unwrap();
    std::array::from_fn(|i| {
        gamma[i] + friction[i].viscous * qd[i] + friction[i].coulomb * qd[i].signum()
    })
}

/// `|got - want| < tolerance · max(|want|, 1)` for every actuator.
fn assert_forces(what: &str, got: &[f64], want: &[f64; 6], tolerance: f64) {
    for i in 0..6 {
        assert!(
            (got[i] - want[i]).abs() < tolerance * want[i].abs().max(1.0),
            "{what}, actuator {}: {} vs {}",
            i + 1,
            got[i],
            want[i]
        );
    }
}

/// `Y π = Γ + Γ_f` with `π` the description's standard parameters and friction.
#[test]
fn the_regressor_times_the_parameters_is_the_inverse_dynamics() {
    let mut r = rng(13);
    for (name, case) in cases(12) {
        let robot = &*case.truth;
        let friction = random_friction(&mut r);
        let pi = robot.standard_parameters(&friction);
        for _ in 0..50 {
            let s = (case.state)(&mut r, &robot.home());
            let y = robot.standard_regressor(&s).unwrap();
            assert_eq!((y.nrows(), y.ncols()), (6, pi.len()), "{name}");
            let predicted: Vec<f64> = (0..6)
                .map(|i| (0..pi.len()).map(|j| y[(i, j)] * pi[j]).sum())
                .collect();
            assert_forces(name, &predicted, &measured(robot, &friction, &s), 1e-10);
        }
    }
}

/// The generated base regressor's columns were found on the checked-in example; the
/// groupings the runtime finds for another geometry make `Y_b β = Γ` hold on robots it has
/// not seen.
#[test]
fn the_base_parameters_of_unseen_robots_carry_their_forces() {
    let mut r = rng(15);
    for seed in [15, 16, 17] {
        for (name, case) in cases(seed) {
            let robot = &*case.truth;
            let friction = random_friction(&mut r);
            let base = robot.base_parameters().unwrap();
            let standard = robot.standard_parameters(&friction).len();
            assert_eq!(base.standard_names().len(), standard, "{name}");
            assert!(
                base.len() < standard,
                "{name}: {} base parameters",
                base.len()
            );
            let beta = base.of_robot(robot, &friction).unwrap();
            let mut yb = vec![0.0; 6 * beta.len()];
            for _ in 0..30 {
                let s = (case.state)(&mut r, &robot.home());
                robot.base_regressor_into(&s, &mut yb).unwrap();
                let got: Vec<f64> = yb
                    .chunks(beta.len())
                    .map(|row| row.iter().zip(&beta).map(|(y, b)| y * b).sum())
                    .collect();
                assert_forces(name, &got, &measured(robot, &friction, &s), 1e-10);
            }
        }
    }
}

/// A robot's masses, friction and inertias come back from noise-free motion and forces along
/// an exciting trajectory designed on its geometry alone, and predict its forces on unseen
/// states.
#[test]
fn identification_recovers_an_unseen_robot() {
    let mut r = rng(16);
    for (name, case) in cases(16) {
        let (truth, blank) = (&*case.truth, &*case.blank);
        let friction = random_friction(&mut r);
        let search = Search {
            candidates: 60,
            samples: 200,
            ..Search::default()
        };
        let trajectory = excite::design(blank, &Envelope::default(), &search)
            .unwrap()
            .trajectory;
        let mut identifier = Identifier::new(blank).unwrap();
        let n = 2000;
        for k in 0..n {
            let state = trajectory.state(trajectory.period * (k as f64 + 0.5) / n as f64);
            identifier
                .add(&state, &measured(truth, &friction, &state))
                .unwrap();
        }
        let estimate = identifier.estimate().unwrap();
        assert_eq!(estimate.model, name);
        assert!(
            estimate.condition_number < 1e5,
            "{name}: condition number {}",
            estimate.condition_number
        );
        let beta = blank
            .base_parameters()
            .unwrap()
            .of_robot(truth, &friction)
            .unwrap();
        let largest = beta.iter().fold(0.0f64, |m, b| m.max(b.abs()));
        for (j, (got, want)) in estimate.values.iter().zip(&beta).enumerate() {
            assert!(
                (got - want).abs() < 1e-7 * largest,
                "{name}, {}: {got} vs {want}",
                estimate.names[j]
            );
        }
        for _ in 0..50 {
            let state = (case.state)(&mut r, &truth.home());
            let got = estimate.forces(blank, &state).unwrap();
            assert_forces(name, &got, &measured(truth, &friction, &state), 1e-7);
        }
    }
}
