//! Kinematic calibration of a Gough-Stewart platform on simulated robots whose true geometry
//! the project has not seen: random millimetre errors in every joint centre and offset,
//! measured at planned poses with a laser tracker's noise.

use c5_robot::GoughStewart as Description;
use c5_runtime::calibrate::{
    calibrate, plan, simulate, CalibrationError, Measurement, Noise, Options, Report,
};
use c5_runtime::{GoughStewart, Pose};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The example hexapod with every `A_i`, `p_i` moved by up to 2 mm per component and every
/// encoder offset by up to 3 mm.
fn as_built(seed: u64) -> GoughStewart {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut robot = Description::example();
    for leg in &mut robot.legs {
        for k in 0..3 {
            leg.base[k] += rng.gen_range(-2e-3..2e-3);
            leg.platform[k] += rng.gen_range(-2e-3..2e-3);
        }
        leg.encoder_offset += rng.gen_range(-3e-3..3e-3);
    }
    GoughStewart::new(robot).unwrap()
}

fn nominal() -> GoughStewart {
    GoughStewart::new(Description::example()).unwrap()
}

/// The true parameters `[A p o]` of each leg, in the report's order.
fn truth_of(robot: &GoughStewart) -> Vec<f64> {
    robot
        .robot()
        .legs
        .iter()
        .flat_map(|l| {
            [
                l.base.as_slice(),
                l.platform.as_slice(),
                &[l.encoder_offset],
            ]
            .concat()
        })
        .collect()
}

fn rms(x: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = x.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (sum / n as f64).sqrt()
}

fn calibrated(seed: u64) -> (GoughStewart, Report) {
    let (nominal, truth) = (nominal(), as_built(seed));
    let options = Options::default();
    let poses = plan(&nominal, 60, &options, seed).unwrap();
    let data = simulate(&truth, &poses, &Noise::default(), seed + 100).unwrap();
    let report = calibrate(&nominal, &data, &options).unwrap();
    (truth, report)
}

/// The bar, on three unseen robots: every parameter within four of its reported
/// standard deviations of the truth, the weighted residuals at the noise (variance factor
/// about 1), the leg lengths of unseen poses predicted to a few micrometres (the nominal file:
/// millimetres) and the forward kinematics of unseen readings within 50 µm of the true pose.
#[test]
fn calibration_recovers_unseen_geometries() {
    let nominal = nominal();
    for seed in [11, 12, 13] {
        let (truth, report) = calibrated(seed);
        assert!(report.unobservable.is_empty(), "{:?}", report.unobservable);
        let mut normalised = Vec::new();
        for (p, t) in report.parameters.iter().zip(truth_of(&truth)) {
            let sigma = p.std_dev.unwrap();
            let z = (p.estimate - t) / sigma;
            assert!(
                z.abs() < 4.0,
                "{}: {} vs {t} (σ {sigma:e})",
                p.name,
                p.estimate
            );
            normalised.push(z);
        }
        // The standard deviations are honest: the errors spread as they say.
        let spread = rms(normalised.into_iter());
        assert!((0.5..1.6).contains(&spread), "z rms {spread}");
        assert!(
            (0.7..1.4).contains(&report.variance_factor),
            "{}",
            report.variance_factor
        );

        let fitted = GoughStewart::new(report.robot).unwrap();
        let unseen = plan(&nominal, 40, &Options::default(), seed + 1000).unwrap();
        let mut errors = (Vec::new(), Vec::new());
        for pose in &unseen {
            let (q, _) = truth.inverse_kinematics(pose).unwrap();
            let (q_fit, _) = fitted.inverse_kinematics(pose).unwrap();
            let (q_nominal, _) = nominal.inverse_kinematics(pose).unwrap();
            errors.0.extend((0..6).map(|i| q_fit[i] - q[i]));
            errors.1.extend((0..6).map(|i| q_nominal[i] - q[i]));
        }
        let (fit, nominal_error) = (rms(errors.0.into_iter()), rms(errors.1.into_iter()));
        assert!(fit < 5e-6, "calibrated leg lengths {fit:e} m rms");
        assert!(
            nominal_error > 1e-3,
            "nominal leg lengths {nominal_error:e} m rms"
        );

        let readings = simulate(&truth, &unseen, &Noise::default(), seed + 2000).unwrap();
        let worst = unseen
            .iter()
            .zip(&readings)
            .map(|(pose, m)| {
                let found = fitted.forward_kinematics(&m.q, None).unwrap();
                (0..3)
                    .map(|k| (found.center[k] - pose.center[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(0.0, f64::max);
        assert!(worst < 50e-6, "forward kinematics off by {worst:e} m");
    }
}

/// The fit closes the residuals at the noise level: each leg's RMS falls from millimetres to
/// the micrometres of the noise.
#[test]
fn calibration_brings_the_residuals_to_the_noise() {
    let (_, report) = calibrated(21);
    for (leg, (before, after)) in report.before().iter().zip(report.after()).enumerate() {
        assert!(before.rms > 2e-4, "leg {}: {before:?}", leg + 1);
        assert!(after.rms < 2e-5, "leg {}: {after:?}", leg + 1);
    }
}

/// Poses all at one orientation cannot separate `A_i` from `p_i`: three combinations per leg,
/// each named and fixed at its nominal value; refused with `strict`.
#[test]
fn one_orientation_is_reported_unobservable() {
    let (nominal, truth) = (nominal(), as_built(31));
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let home = nominal.home();
    let poses: Vec<Pose> = (0..40)
        .map(|_| {
            let mut pose = home;
            for k in 0..3 {
                pose.center[k] += rng.gen_range(-0.08..0.08);
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

/// Bad data get a typed error naming the measurement.
#[test]
fn bad_measurements_are_refused() {
    let (nominal, truth) = (nominal(), as_built(41));
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
    bad[6].q.swap(0, 3);
    assert!(matches!(
        calibrate(&nominal, &bad, &options),
        Err(CalibrationError::Mismatch { row: 7, .. })
    ));
    let mut bad = data.clone();
    bad[9].pose.center[2] += 0.5;
    assert!(matches!(
        calibrate(&nominal, &bad, &options),
        Err(CalibrationError::Unreachable { row: 10, .. })
    ));
}
