//! Identification: the regressors reproduce the inverse dynamics, and the estimator recovers a
//! robot from its motion and forces, with honest standard deviations.

use crate::support;

use c5_runtime::identify::excite::{self, Envelope, Search};
use c5_runtime::identify::{
    BaseParameters, Friction, Identifier, IdentifyError, STANDARD_PARAMETERS,
};
use c5_runtime::trajectory::{Fourier, LinearMove};
use c5_runtime::ParallelRobot;
use c5_runtime::{Model, Robot, State, C5};
use rand::Rng;
use rand_distr_free::gaussian;
use support::{random_robot, random_state, rng};

/// Box-Muller, so the tests need no distribution crate.
mod rand_distr_free {
    use rand::Rng;
    pub fn gaussian(r: &mut impl Rng) -> f64 {
        let (u, v): (f64, f64) = (r.gen_range(f64::EPSILON..1.0), r.gen_range(0.0..1.0));
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

fn random_friction(r: &mut impl Rng) -> [Friction; 6] {
    std::array::from_fn(|_| Friction {
        viscous: r.gen_range(1.0..20.0),
        coulomb: r.gen_range(0.5..5.0),
    })
}

/// What the actuators of `c5` with `friction` apply at `state`: the inverse dynamics plus
/// friction on the joint rates.
fn measured(c5: &C5, friction: &[Friction; 6], state: &State) -> [f64; 6] {
    let gamma = c5.inverse_dynamics(state).unwrap();
    let qd = c5.joint_velocities(&state.pose, &state.twist).unwrap();
    std::array::from_fn(|i| {
        gamma[i] + friction[i].viscous * qd[i] + friction[i].coulomb * qd[i].signum()
    })
}

fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn the_regressors_times_the_parameters_are_the_inverse_dynamics_with_friction() {
    let mut r = rng(90);
    for model in Model::ALL {
        for _ in 0..5 {
            let robot = random_robot(&mut r);
            let friction = random_friction(&mut r);
            let c5 = C5::with_model(robot, model).unwrap();
            let pi = robot.standard_parameters(&friction);
            let beta = c5
                .base_parameters()
                .of_robot(c5.as_mechanism(), &friction)
                .unwrap();
            for _ in 0..20 {
                let state = random_state(&mut r);
                let want = measured(&c5, &friction, &state);
                let y = c5.regressor(&state).unwrap();
                let yb = c5.base_regressor(&state).unwrap();
                let scale = largest(&want).max(1.0);
                for i in 0..6 {
                    let full: f64 = (0..STANDARD_PARAMETERS).map(|j| y[(i, j)] * pi[j]).sum();
                    let base: f64 = (0..beta.len()).map(|j| yb[(i, j)] * beta[j]).sum();
                    assert!(
                        (full - want[i]).abs() < 1e-12 * scale,
                        "{model}: {full} vs {}",
                        want[i]
                    );
                    assert!(
                        (base - want[i]).abs() < 1e-12 * scale,
                        "{model}: {base} vs {}",
                        want[i]
                    );
                }
            }
        }
    }
}

#[test]
fn the_base_parameters_are_few_and_read_as_relations() {
    let consistent = BaseParameters::of(Model::Consistent);
    let paper = BaseParameters::of(Model::Paper);
    assert_eq!((consistent.len(), paper.len()), (46, 52));
    assert!(consistent
        .relations()
        .iter()
        .any(|r| r == "rod1_mass_R = rod1_mass + joint1_mass"));
    // The paper model moves body 2 unlike its rod, so their masses stay apart.
    let named = |name: &str| paper.names().iter().any(|n| n == name);
    assert!(named("joint1_mass") && named("rod1_mass"));
}

/// A short exciting trajectory for the tests (the CLI searches longer).
fn excitation(c5: &C5) -> Fourier {
    let search = Search {
        candidates: 60,
        samples: 200,
        ..Search::default()
    };
    excite::design(c5.as_mechanism(), &Envelope::default(), &search)
        .unwrap()
        .trajectory
}

fn samples(trajectory: &Fourier, n: usize) -> impl Iterator<Item = State> + '_ {
    (0..n).map(move |k| trajectory.state(trajectory.period() * (k as f64 + 0.5) / n as f64))
}

#[test]
fn noise_free_data_identify_a_robot_that_predicts_unseen_forces() {
    let mut r = rng(91);
    for model in Model::ALL {
        let robot = random_robot(&mut r);
        let friction = random_friction(&mut r);
        let truth = C5::with_model(robot, model).unwrap();
        // The identifier knows only the geometry: start from the default robot's masses.
        let geometry_only = Robot {
            half_spacing: robot.half_spacing,
            gravity: robot.gravity,
            ..Robot::default()
        };
        let blank = C5::with_model(geometry_only, model).unwrap();
        let trajectory = excitation(&blank);
        let mut identifier = Identifier::new(blank.as_mechanism()).unwrap();
        for state in samples(&trajectory, 2000) {
            identifier
                .add(&state, &measured(&truth, &friction, &state))
                .unwrap();
        }
        let estimate = identifier.estimate().unwrap();
        assert!(
            estimate.condition_number < 1e4,
            "{}",
            estimate.condition_number
        );
        let beta = blank
            .base_parameters()
            .of_robot(truth.as_mechanism(), &friction)
            .unwrap();
        let err = estimate
            .values
            .iter()
            .zip(&beta)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("{model}: parameters off by {err:.1e} (absolute)");
        // docs/identification.md states 1.1e-10 (consistent) and 5e-11 (paper); held to 10x.
        let stated = if model == Model::Consistent {
            1.1e-10
        } else {
            5e-11
        };
        assert!(err < 10.0 * stated, "{model}: parameters off by {err}");
        // Unseen states, away from the trajectory.
        let mut worst: f64 = 0.0;
        for _ in 0..50 {
            let state = random_state(&mut r);
            let want = measured(&truth, &friction, &state);
            let got = estimate.forces(blank.as_mechanism(), &state).unwrap();
            let rel = (0..6).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max)
                / largest(&want).max(1.0);
            worst = worst.max(rel);
        }
        println!("{model}: unseen forces off by {worst:.1e} relative");
        // docs/identification.md states 7e-12; held to 10x.
        assert!(
            worst < 7e-11,
            "{model}: prediction off by {worst:e} relative"
        );
    }
}

#[test]
fn the_reported_standard_deviations_match_the_spread_over_noisy_draws() {
    let mut r = rng(92);
    let robot = random_robot(&mut r);
    let friction = random_friction(&mut r);
    let c5 = C5::new(robot).unwrap();
    let trajectory = excitation(&c5);
    let states: Vec<State> = samples(&trajectory, 600).collect();
    let clean: Vec<[f64; 6]> = states.iter().map(|s| measured(&c5, &friction, s)).collect();
    // Each actuator its own noise level, as real force sensors have.
    let sigma = [0.5, 1.0, 2.0, 0.5, 1.0, 2.0];
    let draws = 300;
    let nb = c5.base_parameters().len();
    let mut values = vec![Vec::with_capacity(draws); nb];
    let mut reported = vec![0.0; nb];
    for _ in 0..draws {
        let mut identifier = Identifier::new(c5.as_mechanism()).unwrap();
        for (state, gamma) in states.iter().zip(&clean) {
            let noisy: [f64; 6] = std::array::from_fn(|i| gamma[i] + sigma[i] * gaussian(&mut r));
            identifier.add(state, &noisy).unwrap();
        }
        let e = identifier.estimate().unwrap();
        for j in 0..nb {
            values[j].push(e.values[j]);
            reported[j] += e.std_dev[j] / draws as f64;
        }
        for (rms, sigma) in e.residual_rms.iter().zip(sigma) {
            assert!((rms / sigma - 1.0).abs() < 0.15, "{:?}", e.residual_rms);
        }
    }
    for j in 0..nb {
        let mean = values[j].iter().sum::<f64>() / draws as f64;
        let spread =
            (values[j].iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (draws - 1) as f64).sqrt();
        let ratio = spread / reported[j];
        assert!(
            (0.7..1.3).contains(&ratio),
            "{}: spread {spread:e} against reported {:e}",
            c5.base_parameters().names()[j],
            reported[j]
        );
    }
}

#[test]
fn too_few_samples_are_refused() {
    let c5 = C5::new(Robot::default()).unwrap();
    let mut identifier = Identifier::new(c5.as_mechanism()).unwrap();
    let mut r = rng(93);
    for _ in 0..5 {
        let state = random_state(&mut r);
        identifier.add(&state, &[1.0; 6]).unwrap();
    }
    assert!(matches!(
        identifier.estimate(),
        Err(IdentifyError::TooFewSamples { samples: 5, .. })
    ));
}

#[test]
fn section_9_cannot_identify_the_rotational_parameters_and_says_which() {
    let c5 = C5::new(Robot::default()).unwrap();
    let mut identifier = Identifier::new(c5.as_mechanism()).unwrap();
    let motion = LinearMove::section9();
    for k in 0..=1000 {
        let state = motion.state(k as f64 / 1000.0);
        identifier
            .add(&state, &c5.inverse_dynamics(&state).unwrap())
            .unwrap();
    }
    match identifier.estimate() {
        Err(IdentifyError::Unidentifiable { parameters, .. }) => {
            // The orientation never changes: no inertia is excited, and the first moments
            // act as constant loads, one per pose, that the masses' weights mimic.
            for name in [
                "platform_ixx_R",
                "platform_izz_R",
                "platform_mx",
                "joint3_my",
            ] {
                assert!(
                    parameters.iter().any(|p| p == name),
                    "{name}: {parameters:?}"
                );
            }
            // The masses and the friction are excited by the straight move.
            assert!(
                !parameters
                    .iter()
                    .any(|p| p.contains("mass") || p.starts_with('f')),
                "{parameters:?}"
            );
        }
        other => panic!("expected unidentifiable parameters, got {other:?}"),
    }
}

#[test]
fn bad_samples_are_refused_and_lose_nothing() {
    let c5 = C5::new(Robot::default()).unwrap();
    let mut identifier = Identifier::new(c5.as_mechanism()).unwrap();
    let mut state = State::default();
    assert!(identifier.add(&state, &[f64::NAN; 6]).is_err());
    state.pose.beta = std::f64::consts::FRAC_PI_2;
    state.pose.gamma = std::f64::consts::FRAC_PI_2;
    assert!(identifier.add(&state, &[0.0; 6]).is_err());
    assert_eq!(identifier.samples(), 0);
}
