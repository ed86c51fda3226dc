//! Kinematic calibration of every legged mechanism (the Gough-Stewart platform, the rotary
//! hexapod, the Delta) on simulated robots whose true geometry the project has not seen: random
//! millimetre errors in every fitted parameter, measured at planned poses with a laser
//! tracker's noise.

use c5_runtime::calibrate::{
    calibrate, plan, simulate, CalibrationError, Measurement, Noise, Nominal, Options, Report,
};
use c5_runtime::{Description, Mechanism};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The examples of every mechanism calibration serves.
fn examples() -> [Description; 3] {
    [
        Description::GoughStewart(c5_robot::GoughStewart::example()),
        Description::RusHexapod(c5_robot::RusHexapod::example()),
        Description::Delta(c5_robot::Delta::example()),
    ]
}

/// `robot` with every fitted length moved by up to 2 mm and every encoder offset by up to 3
/// mm or 3 mrad.
fn as_built(robot: &Description, seed: u64) -> Description {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut built = robot.clone();
    let fitted = robot.fitted().unwrap();
    for leg in 0..legs(robot) {
        let values: Vec<f64> = built
            .fitted_values(leg)
            .iter()
            .zip(fitted)
            .map(|(v, f)| {
                let size = if f.symbol == "o" { 3e-3 } else { 2e-3 };
                v + rng.gen_range(-size..size)
            })
            .collect();
        assert!(built.set_fitted_values(leg, &values));
    }
    built
}

fn legs(robot: &Description) -> usize {
    match robot {
        Description::Delta(_) => 3,
        _ => 6,
    }
}

/// The true fitted parameters of each leg, in the report's order.
fn truth_of(robot: &Description) -> Vec<f64> {
    (0..legs(robot))
        .flat_map(|leg| robot.fitted_values(leg))
        .collect()
}

fn rms(x: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = x.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (sum / n as f64).sqrt()
}

fn nominal(robot: &Description) -> Nominal {
    Nominal::new(robot.clone()).unwrap()
}

fn calibrated(robot: &Description, seed: u64) -> (Nominal, Report) {
    let (nominal, truth) = (nominal(robot), nominal(&as_built(robot, seed)));
    let options = Options::default();
    let poses = plan(&nominal, 60, &options, seed).unwrap();
    let data = simulate(&truth, &poses, &Noise::default(), seed + 100).unwrap();
    let report = calibrate(&nominal, &data, &options).unwrap();
    (truth, report)
}

fn actuators(robot: &dyn Mechanism, pose: &[f64]) -> Vec<f64> {
    let mut q = vec![0.0; robot.freedom().dimension()];
    robot.actuator_positions(pose, &mut q).unwrap();
    q
}

/// The bar, on unseen robots of each mechanism: every parameter within four of its
/// reported standard deviations of the truth, the weighted residuals at the noise (variance
/// factor about 1), the actuators of unseen poses predicted a hundred times better than the
/// nominal file does, and the forward kinematics of unseen readings within 100 µm of the true
/// position.
#[test]
fn calibration_recovers_unseen_geometries() {
    for robot in examples() {
        let name = robot.mechanism();
        let nominal = nominal(&robot);
        for seed in [11, 12] {
            let (truth, report) = calibrated(&robot, seed);
            assert!(
                report.unobservable.is_empty(),
                "{name}: {:?}",
                report.unobservable
            );
            let mut normalised = Vec::new();
            for (p, t) in report.parameters.iter().zip(truth_of(&truth.description())) {
                let sigma = p.std_dev.unwrap();
                let z = (p.estimate - t) / sigma;
                assert!(
                    z.abs() < 4.0,
                    "{name} {}: {} vs {t} (σ {sigma:e})",
                    p.name,
                    p.estimate
                );
                normalised.push(z);
            }
            // The standard deviations are honest: the errors spread as they say.
            let spread = rms(normalised.into_iter());
            assert!((0.5..1.6).contains(&spread), "{name}: z rms {spread}");
            assert!(
                (0.7..1.4).contains(&report.variance_factor),
                "{name}: {}",
                report.variance_factor
            );

            let fitted = self::nominal(&report.robot);
            let unseen = plan(&nominal, 40, &Options::default(), seed + 1000).unwrap();
            let mut errors = (Vec::new(), Vec::new());
            for pose in &unseen {
                let q = actuators(truth.mechanism(), pose);
                let q_fit = actuators(fitted.mechanism(), pose);
                let q_nominal = actuators(nominal.mechanism(), pose);
                errors.0.extend(q.iter().zip(&q_fit).map(|(a, b)| b - a));
                errors
                    .1
                    .extend(q.iter().zip(&q_nominal).map(|(a, b)| b - a));
            }
            let (fit, nominal_error) = (rms(errors.0.into_iter()), rms(errors.1.into_iter()));
            assert!(
                fit < nominal_error / 100.0,
                "{name}: calibrated actuators {fit:e} rms, nominal {nominal_error:e}"
            );

            let readings = simulate(&truth, &unseen, &Noise::default(), seed + 2000).unwrap();
            let worst = unseen
                .iter()
                .zip(&readings)
                .map(|(pose, m)| {
                    let mut found = vec![0.0; pose.len()];
                    fitted
                        .mechanism()
                        .forward_kinematics(&m.q, Some(pose), &mut found)
                        .unwrap();
                    let position = pose.len() - 3;
                    (position..pose.len())
                        .map(|k| (found[k] - pose[k]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                })
                .fold(0.0, f64::max);
            // The Gough-Stewart platform: 20-30 µm; the rotary hexapod, whose short cranks
            // magnify its geometry's uncertainty: 50-70 µm.
            eprintln!("{name} seed {seed}: forward kinematics within {worst:.3e} m");
            assert!(
                worst < 100e-6,
                "{name}: forward kinematics off by {worst:e} m"
            );
        }
    }
}

/// The fit closes the residuals at the noise level: each leg's RMS falls from the nominal
/// geometry's errors to the noise, by more than ten times.
#[test]
fn calibration_brings_the_residuals_to_the_noise() {
    for robot in examples() {
        let (_, report) = calibrated(&robot, 21);
        for (leg, (before, after)) in report.before().iter().zip(report.after()).enumerate() {
            assert!(
                after.rms < before.rms / 10.0,
                "{} leg {}: {before:?} to {after:?}",
                robot.mechanism(),
                leg + 1
            );
        }
    }
    let (_, report) = calibrated(&examples()[0], 21);
    for (before, after) in report.before().iter().zip(report.after()) {
        assert!(
            before.rms > 2e-4 && after.rms < 2e-5,
            "{before:?} {after:?}"
        );
    }
}

/// The written description carries the fitted values, and the rotary legs' residuals are
/// angles.
#[test]
fn the_report_says_its_units_and_carries_the_calibrated_robot() {
    for robot in examples() {
        let (_, report) = calibrated(&robot, 51);
        assert_eq!(
            report.angular,
            !matches!(robot, Description::GoughStewart(_))
        );
        let per_leg = robot.fitted().unwrap().len();
        assert_eq!(report.parameters.len(), per_leg * legs(&robot));
        for (k, p) in report.parameters.iter().enumerate() {
            assert_eq!(
                report.robot.fitted_values(k / per_leg)[k % per_leg],
                p.estimate
            );
        }
    }
}

/// Poses all at one orientation cannot separate `A_i` from `p_i`: three combinations per leg,
/// each named and fixed at its nominal value; refused with `strict`.
#[test]
fn one_orientation_is_reported_unobservable() {
    let robot = &examples()[0];
    let (nominal, truth) = (nominal(robot), nominal(&as_built(robot, 31)));
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let home = nominal.mechanism().home();
    let poses: Vec<Vec<f64>> = (0..40)
        .map(|_| {
            let mut pose = home.clone();
            for x in &mut pose[3..] {
                *x += rng.gen_range(-0.08..0.08);
            }
            pose
        })
        .collect();
    let data = simulate(&truth, &poses, &Noise::default(), 32).unwrap();
    let report = calibrate(&nominal, &data, &Options::default()).unwrap();
    assert_eq!(report.unobservable.len(), 18, "{:#?}", report.unobservable);
    for leg in 1..=6 {
        let fixed: Vec<_> = report
            .unobservable
            .iter()
            .filter(|u| u.leg == leg)
            .collect();
        assert_eq!(fixed.len(), 3);
        for u in fixed {
            // Each pairs a base coordinate with the platform's: A - R p is what one orientation
            // sees.
            let names: Vec<&str> = u.combination.iter().map(|(n, _)| n.as_str()).collect();
            assert!(names.iter().any(|n| n.starts_with('A')), "{u}");
            assert!(names.iter().any(|n| n.starts_with('p')), "{u}");
            let parameter = report
                .parameters
                .iter()
                .find(|p| p.name == u.fixed)
                .unwrap();
            assert_eq!(parameter.estimate, parameter.nominal);
            assert!(parameter.std_dev.is_none());
        }
    }
    let strict = Options {
        strict: true,
        ..Options::default()
    };
    match calibrate(&nominal, &data, &strict) {
        Err(CalibrationError::Unobservable { combinations }) => {
            assert_eq!(combinations.len(), 18)
        }
        other => panic!("{other:?}"),
    }
}

/// Bad data get a typed error naming the measurement, for every mechanism; the C5, whose legs
/// have no joint centres to fit, is refused.
#[test]
fn bad_measurements_are_refused() {
    for robot in examples() {
        let (nominal, truth) = (nominal(&robot), nominal(&as_built(&robot, 41)));
        let options = Options::default();
        let poses = plan(&nominal, 20, &options, 41).unwrap();
        let data = simulate(&truth, &poses, &Noise::default(), 42).unwrap();
        assert!(matches!(
            calibrate(&nominal, &data[..5], &options),
            Err(CalibrationError::TooFewMeasurements { got: 5, .. })
        ));
        let mut bad: Vec<Measurement> = data.clone();
        bad[3].q[2] = f64::NAN;
        assert_eq!(
            calibrate(&nominal, &bad, &options).unwrap_err(),
            CalibrationError::NonFinite { row: 4 }
        );
        let mut bad = data.clone();
        bad[5].q.pop();
        assert!(matches!(
            calibrate(&nominal, &bad, &options),
            Err(CalibrationError::WrongWidth { row: 6, .. })
        ));
        // A reading a whole metre or radian off: in other units, or another column's.
        let mut bad = data.clone();
        bad[6].q[0] += 1.0;
        assert!(matches!(
            calibrate(&nominal, &bad, &options),
            Err(CalibrationError::Mismatch { row: 7, .. })
        ));
        let mut bad = data.clone();
        let z = bad[9].pose.len() - 1;
        bad[9].pose[z] += 0.5;
        assert!(matches!(
            calibrate(&nominal, &bad, &options),
            Err(CalibrationError::Unreachable { row: 10, .. })
        ));
    }
    assert!(matches!(
        Nominal::new(Description::default()),
        Err(CalibrationError::Robot(
            c5_runtime::Error::Unsupported { .. }
        ))
    ));
}
