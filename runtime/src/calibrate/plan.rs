//! Where to measure: poses inside the robot's limits that make its geometry best observable
//! (a greedy D-optimal selection), and simulated measurements for trials.

use super::{CalibrationError, Measurement, Noise, Options, PER_LEG};
use crate::gough_stewart::GoughStewart;
use crate::{Error, Pose};
use alloc::vec::Vec;
use c5_generated::f64::gough_stewart::{calibration_residuals, GEOMETRY_PARAMETERS};
use nalgebra::{SMatrix, SVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// How many candidate poses the selection draws from.
const CANDIDATES: usize = 3000;
/// The most draws spent finding them.
const DRAWS: usize = 200_000;
/// The half-width of the box of orientations drawn (rad).
const ANGLES: f64 = 0.35;
/// The half-width of the box of positions drawn, over the base joints' mean radius.
const POSITIONS: f64 = 0.5;
/// The least pivot ratio of a candidate (the legs' firm hold on the platform).
const HOLD: f64 = 0.05;

type Row = SVector<f64, PER_LEG>;
type Information = SMatrix<f64, PER_LEG, PER_LEG>;

/// `n` poses inside `robot`'s limits (its `[limits]`, and away from singularities) that make
/// its geometry best observable: drawn at random around home (`seed`), then chosen one by one
/// to raise most the determinant of each leg's information matrix (whitened by
/// `options.noise`, scaled by `options.scale`).
///
/// # Errors
/// [`CalibrationError::TooFewMeasurements`] for `n` below the minimum, or when fewer than `n`
/// poses inside the limits are found.
pub fn plan(
    robot: &GoughStewart,
    n: usize,
    options: &Options,
    seed: u64,
) -> Result<Vec<Pose>, CalibrationError> {
    if n < super::MIN_MEASUREMENTS {
        return Err(CalibrationError::TooFewMeasurements {
            got: n,
            least: super::MIN_MEASUREMENTS,
        });
    }
    let candidates = candidates(robot, seed);
    if candidates.len() < n {
        return Err(CalibrationError::TooFewMeasurements {
            got: candidates.len(),
            least: n,
        });
    }
    let rows: Vec<[Row; 6]> = candidates.iter().map(|p| rows(robot, p, options)).collect();
    // A small prior keeps the information invertible before seven poses are in.
    let mut inverse = [Information::identity() * 1e6; 6];
    let mut taken = alloc::vec![false; candidates.len()];
    let mut chosen = Vec::with_capacity(n);
    for _ in 0..n {
        let gain = |c: usize| -> f64 {
            (0..6)
                .map(|leg| {
                    let j = &rows[c][leg];
                    (1.0 + (j.transpose() * inverse[leg] * j)[0]).ln()
                })
                .sum()
        };
        let best = (0..candidates.len())
            .filter(|&c| !taken[c])
            .map(|c| (c, gain(c)))
            .fold((0, f64::NEG_INFINITY), |b, x| if x.1 > b.1 { x } else { b })
            .0;
        taken[best] = true;
        chosen.push(candidates[best]);
        for (leg, m) in inverse.iter_mut().enumerate() {
            // Sherman-Morrison: (M + j jᵀ)⁻¹.
            let j = &rows[best][leg];
            let mj = *m * j;
            *m -= mj * mj.transpose() / (1.0 + (j.transpose() * mj)[0]);
        }
    }
    Ok(chosen)
}

/// Poses drawn uniformly in a box around home, kept where the robot can go.
fn candidates(robot: &GoughStewart, seed: u64) -> Vec<Pose> {
    let home = robot.home().to_array();
    let radius = robot
        .robot()
        .legs
        .iter()
        .map(|l| l.base[0].hypot(l.base[1]))
        .sum::<f64>()
        / 6.0;
    let reach = POSITIONS * radius;
    let half = [ANGLES, ANGLES, ANGLES, reach, reach, reach];
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(CANDIDATES);
    for _ in 0..DRAWS {
        if out.len() == CANDIDATES {
            break;
        }
        let x: [f64; 6] = core::array::from_fn(|k| home[k] + rng.gen_range(-half[k]..half[k]));
        let pose = Pose::from_array(x);
        let reachable = robot.check_limits(&pose).is_ok()
            && robot
                .singularity_terms(&pose)
                .is_ok_and(|t| t[6..].iter().all(|&p| p > HOLD));
        if reachable {
            out.push(pose);
        }
    }
    out
}

/// Each leg's whitened, scaled row of the geometry Jacobian at `pose`.
fn rows(robot: &GoughStewart, pose: &Pose, options: &Options) -> [Row; 6] {
    let mut geometry = [0.0; GEOMETRY_PARAMETERS];
    geometry.copy_from_slice(&robot.parameters()[..GEOMETRY_PARAMETERS]);
    let x = pose.to_array();
    let (q, _) = robot
        .inverse_kinematics(pose)
        .unwrap_or(([0.0; 6], [[0.0; 3]; 6]));
    let (_, j, jx) = calibration_residuals(&x, &q, &geometry);
    core::array::from_fn(|leg| {
        let sigma = super::residual_sigma(&jx[leg], &options.noise);
        Row::from_fn(|k, _| j[leg][k] * options.scale / sigma)
    })
}

/// What an instrument and the encoders would report at `poses` of the robot `truth`: its
/// encoders' readings with `noise.encoder`, and each pose with `noise.position` and
/// `noise.angle`, drawn from `seed`. For trials of a calibration (how many poses of what noise
/// buy what accuracy) and tests.
///
/// # Errors
/// A pose where `truth`'s inverse kinematics fails (non-finite, singular).
pub fn simulate(
    truth: &GoughStewart,
    poses: &[Pose],
    noise: &Noise,
    seed: u64,
) -> Result<Vec<Measurement>, Error> {
    let normal = |sigma: f64| {
        Normal::new(0.0, sigma).map_err(|_| Error::Invalid {
            what: "noise",
            rule: "every noise level must be finite and not negative",
        })
    };
    let (angle, position, encoder) = (
        normal(noise.angle)?,
        normal(noise.position)?,
        normal(noise.encoder)?,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    poses
        .iter()
        .map(|pose| {
            let (q, _) = truth.inverse_kinematics(pose)?;
            let x = pose.to_array();
            let measured: [f64; 6] = core::array::from_fn(|k| {
                let d = if k < 3 { &angle } else { &position };
                x[k] + d.sample(&mut rng)
            });
            Ok(Measurement {
                pose: Pose::from_array(measured),
                q: q.map(|v| v + encoder.sample(&mut rng)),
            })
        })
        .collect()
}
