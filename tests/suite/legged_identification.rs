//! Identification of the legged mechanisms (the Gough-Stewart platform, the rotary hexapod,
//! the Delta), one set of checks over `Mechanism` run on each, in its platform's coordinates:
//! the regressor times the standard parameters is the inverse dynamics plus friction; the
//! base parameters the runtime finds for a geometry no generated file folds in carry its
//! forces; an unseen robot's masses, friction and inertias come back from noise-free motion
//! and forces along an exciting trajectory designed on its geometry alone.

use crate::support::rng;
use c5_runtime::identify::excite::{self, Envelope, Search};
use c5_runtime::identify::{Friction, Identifier};
use c5_runtime::{Delta, GoughStewart, Mechanism, ParallelRobot, Pose, RusHexapod, State};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// One legged mechanism's robots for the checks.
struct Case {
    /// The robot whose forces are measured.
    truth: Box<dyn Mechanism>,
    /// Its geometry with the checked-in example's masses: what an identifier knows.
    blank: Box<dyn Mechanism>,
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
        truth: GoughStewart::new(robot).unwrap().into_mechanism(),
        blank: GoughStewart::new(blank).unwrap().into_mechanism(),
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
        truth: RusHexapod::new(robot).unwrap().into_mechanism(),
        blank: RusHexapod::new(blank).unwrap().into_mechanism(),
        state: super::rus_hexapod::near_home,
    }
}

fn delta(r: &mut ChaCha8Rng) -> Case {
    let robot = super::delta::jittered(r);
    let example = c5_robot::Delta::example();
    let mut blank = robot;
    blank.platform = example.platform;
    for (arm, nominal) in blank.arms.iter_mut().zip(&example.arms) {
        arm.crank = nominal.crank;
        arm.rod = nominal.rod;
    }
    Case {
        truth: Delta::new(robot).unwrap().into_mechanism(),
        blank: Delta::new(blank).unwrap().into_mechanism(),
        state: level_near_home,
    }
}

/// A level platform's state within 5 cm of `home`: it translates only.
fn level_near_home(r: &mut ChaCha8Rng, home: &Pose) -> State {
    let mut state = State::default();
    state.pose.center = core::array::from_fn(|k| home.center[k] + r.gen_range(-0.05..0.05));
    state.twist.velocity = core::array::from_fn(|_| r.gen_range(-0.5..0.5));
    state.accel.linear = core::array::from_fn(|_| r.gen_range(-5.0..5.0));
    state
}

fn cases(seed: u64) -> Vec<(&'static str, Case)> {
    let mut r = rng(seed);
    vec![
        ("gough-stewart", hexapod(&mut r)),
        ("rus-hexapod", rotary_hexapod(&mut r)),
        ("delta", delta(&mut r)),
    ]
}

/// The pose `robot` rests at, as the six-coordinate state types hold it.
fn home(robot: &dyn Mechanism) -> Pose {
    let rest = vec![0.0; robot.freedom().dimension()];
    robot.state_of([&robot.home(), &rest, &rest]).unwrap().pose
}

fn random_friction(r: &mut ChaCha8Rng, robot: &dyn Mechanism) -> Vec<Friction> {
    (0..robot.freedom().dimension())
        .map(|_| Friction {
            viscous: r.gen_range(1.0..20.0),
            coulomb: r.gen_range(0.5..5.0),
        })
        .collect()
}

/// What the actuators of `robot` with `friction` apply at `state`: the inverse dynamics plus
/// friction on the actuator rates.
fn measured(robot: &dyn Mechanism, friction: &[Friction], state: &State) -> Vec<f64> {
    let [x, v, a] = robot.coordinates_of(state).unwrap();
    let n = x.len();
    let (mut gamma, mut qd) = (vec![0.0; n], vec![0.0; n]);
    robot.inverse_dynamics(&x, &v, &a, &mut gamma).unwrap();
    robot.joint_velocities(&x, &v, &mut qd).unwrap();
    (0..n)
        .map(|i| gamma[i] + friction[i].viscous * qd[i] + friction[i].coulomb * qd[i].signum())
        .collect()
}

/// `|got - want| < tolerance · max(|want|, 1)` for every actuator.
fn assert_forces(what: &str, got: &[f64], want: &[f64], tolerance: f64) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (i, (got, want)) in got.iter().zip(want).enumerate() {
        assert!(
            (got - want).abs() < tolerance * want.abs().max(1.0),
            "{what}, actuator {}: {got} vs {want}",
            i + 1,
        );
    }
}

/// `Y π = Γ + Γ_f` with `π` the description's standard parameters and friction.
#[test]
fn the_regressor_times_the_parameters_is_the_inverse_dynamics() {
    let mut r = rng(13);
    for (name, case) in cases(12) {
        let robot = &*case.truth;
        let n = robot.freedom().dimension();
        let friction = random_friction(&mut r, robot);
        let pi = robot.standard_parameters(&friction).unwrap();
        for _ in 0..50 {
            let s = (case.state)(&mut r, &home(robot));
            let [x, v, a] = robot.coordinates_of(&s).unwrap();
            let y = robot.standard_regressor([&x, &v, &a]).unwrap();
            assert_eq!((y.nrows(), y.ncols()), (n, pi.len()), "{name}");
            let predicted: Vec<f64> = (0..n)
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
            let n = robot.freedom().dimension();
            let friction = random_friction(&mut r, robot);
            let base = robot.base_parameters().unwrap();
            let pi = robot.standard_parameters(&friction).unwrap();
            let standard = pi.len();
            assert_eq!(base.standard_names().len(), standard, "{name}");
            assert!(
                base.len() < standard,
                "{name}: {} base parameters",
                base.len()
            );
            let beta = base.from_standard(&pi).unwrap();
            let mut yb = vec![0.0; n * beta.len()];
            for _ in 0..30 {
                let s = (case.state)(&mut r, &home(robot));
                let [x, v, a] = robot.coordinates_of(&s).unwrap();
                robot.base_regressor_into([&x, &v, &a], &mut yb).unwrap();
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
        let friction = random_friction(&mut r, truth);
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
            let state = trajectory.state(trajectory.period() * (k as f64 + 0.5) / n as f64);
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
            let state = (case.state)(&mut r, &home(truth));
            let got = estimate.forces(blank, &state).unwrap();
            assert_forces(name, &got, &measured(truth, &friction, &state), 1e-7);
        }
    }
}

/// Forces not one per actuator, a state that turns a platform that only translates, and
/// friction not one per actuator are refused by name, and the refused sample is not counted.
#[test]
fn samples_of_the_wrong_size_or_freedom_are_refused() {
    let delta = Delta::new(c5_robot::Delta::example()).unwrap();
    let mut identifier = Identifier::new(delta.as_mechanism()).unwrap();
    assert_eq!(identifier.actuators(), 3);
    let state = level_near_home(&mut rng(3), &home(delta.as_mechanism()));
    let err = identifier.add(&state, &[0.0; 6]).unwrap_err();
    assert!(err.to_string().contains("gamma"), "{err}");
    let mut turned = state;
    turned.pose.gamma = 0.1;
    let err = identifier.add(&turned, &[0.0; 3]).unwrap_err();
    assert!(err.to_string().contains("only translates"), "{err}");
    assert_eq!(identifier.samples(), 0);
    identifier.add(&state, &[0.1, 0.2, 0.3]).unwrap();
    assert_eq!(identifier.samples(), 1);
    let err = delta
        .as_mechanism()
        .standard_parameters(&[Friction::default(); 6])
        .unwrap_err();
    assert!(err.to_string().contains("friction"), "{err}");
}
