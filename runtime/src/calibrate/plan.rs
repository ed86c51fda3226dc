//! Where to measure: poses inside the robot's limits that make its geometry best observable
//! (a greedy D-optimal selection), and simulated measurements for trials.

use super::{min_measurements, CalibrationError, Measurement, Noise, Nominal, Options};
use crate::Error;
use alloc::vec::Vec;
use nalgebra::{DMatrix, DVector};
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
/// The least singularity clearance of a candidate (the legs' firm hold on the platform, the
/// joints away from their singular configurations).
const HOLD: f64 = 0.05;
/// How far (in scales) the built robot's lengths may be from the drawing's: a candidate must be
/// in reach of [`BUILT`] robots whose every fitted length is drawn this far from nominal. A
/// crank's reach term `1 - (K/ρ)²` moves by about 0.1 per millimetre of its leg's geometry, so
/// a pose near the nominal robot's reach may be out of the built one's.
const BUILT_WITHIN: f64 = 4.0;
/// How many such robots a candidate must be in reach of.
const BUILT: usize = 8;

/// `n` poses inside `robot`'s limits (its `[limits]`, and away from singularities) that make
/// its geometry best observable: drawn at random around home (`seed`), then chosen one by one
/// to raise most the determinant of each leg's information matrix (whitened by
/// `options.noise`, scaled by `options.scale`).
///
/// # Errors
/// [`CalibrationError::TooFewMeasurements`] for `n` below the minimum, or when fewer than `n`
/// poses inside the limits are found.
pub fn plan(
    robot: &Nominal,
    n: usize,
    options: &Options,
    seed: u64,
) -> Result<Vec<Vec<f64>>, CalibrationError> {
    let least = min_measurements(robot.fitted().len());
    if n < least {
        return Err(CalibrationError::TooFewMeasurements { got: n, least });
    }
    let candidates = candidates(robot, options, seed);
    if candidates.len() < n {
        return Err(CalibrationError::TooFewMeasurements {
            got: candidates.len(),
            least: n,
        });
    }
    let parameters = robot.description().kernel_parameters();
    let rows: Vec<Vec<DVector<f64>>> = candidates
        .iter()
        .map(|(pose, q)| rows(robot, &parameters, pose, q, options))
        .collect();
    let (legs, fitted) = (robot.actuators(), robot.fitted().len());
    // A small prior keeps the information invertible before enough poses are in.
    let mut inverse = alloc::vec![DMatrix::<f64>::identity(fitted, fitted) * 1e6; legs];
    let mut taken = alloc::vec![false; candidates.len()];
    let mut chosen = Vec::with_capacity(n);
    for _ in 0..n {
        let gain = |c: usize| -> f64 {
            (0..legs)
                .map(|leg| (1.0 + quadratic(&inverse[leg], &rows[c][leg])).ln())
                .sum()
        };
        let best = (0..candidates.len())
            .filter(|&c| !taken[c])
            .map(|c| (c, gain(c)))
            .fold((0, f64::NEG_INFINITY), |b, x| if x.1 > b.1 { x } else { b })
            .0;
        taken[best] = true;
        chosen.push(candidates[best].0.clone());
        for (leg, m) in inverse.iter_mut().enumerate() {
            // Sherman-Morrison: (M + j jᵀ)⁻¹.
            let j = &rows[best][leg];
            let mj = &*m * j;
            let denominator = 1.0 + j.dot(&mj);
            *m -= &mj * mj.transpose() / denominator;
        }
    }
    Ok(chosen)
}

/// `jᵀ M j`, without the product `M j` allocated: the selection evaluates it for every
/// candidate and leg at each pick.
fn quadratic(m: &DMatrix<f64>, j: &DVector<f64>) -> f64 {
    let n = j.len();
    (0..n)
        .map(|a| {
            let row: f64 = (0..n).map(|b| m[(a, b)] * j[b]).sum();
            j[a] * row
        })
        .sum()
}

/// Poses drawn uniformly in a box around home (its turns, where the platform turns, and its
/// positions over half the base joints' mean radius; halved while it mostly misses the
/// workspace), kept where the robot and robots built a few millimetres off it can go, each
/// with its actuators' values there.
fn candidates(robot: &Nominal, options: &Options, seed: u64) -> Vec<(Vec<f64>, Vec<f64>)> {
    let mechanism = robot.mechanism();
    let home = mechanism.home();
    let description = robot.description();
    let base_x = robot.fitted().iter().position(|f| f.symbol == "A");
    let legs = robot.actuators();
    let radius = base_x.map_or(0.0, |x| {
        (0..legs)
            .map(|leg| {
                let a = description.fitted_values(leg);
                a[x].hypot(a[x + 1])
            })
            .sum::<f64>()
            / legs as f64
    });
    let turns = home.len().saturating_sub(3);
    let built = variants(robot, BUILT_WITHIN * options.scale, seed);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    // A box that mostly misses the workspace (a small robot's) is halved, down to an eighth.
    for shrink in [1.0, 0.5, 0.25, 0.125] {
        let half: Vec<f64> = (0..home.len())
            .map(|k| {
                shrink
                    * if k < turns {
                        ANGLES
                    } else {
                        POSITIONS * radius
                    }
            })
            .collect();
        out.clear();
        for draw in 0..DRAWS {
            if out.len() == CANDIDATES || (draw == DRAWS / 8 && out.len() < CANDIDATES / 8) {
                break;
            }
            let pose: Vec<f64> = (0..home.len())
                .map(|k| home[k] + rng.gen_range(-half[k]..half[k]))
                .collect();
            let clear =
                |m: &dyn crate::Mechanism| m.singularity_clearance(&pose).is_ok_and(|c| c > HOLD);
            let Some(q) = clear(mechanism).then(|| robot.reach(&pose).ok()).flatten() else {
                continue;
            };
            if built
                .iter()
                .all(|b| clear(b.mechanism()) && b.reach(&pose).is_ok())
            {
                out.push((pose, q));
            }
        }
        if out.len() >= CANDIDATES / 8 {
            break;
        }
    }
    out
}

/// [`BUILT`] robots with every fitted length drawn within `by` of nominal (those that load).
fn variants(robot: &Nominal, by: f64, seed: u64) -> Vec<Nominal> {
    let description = robot.description();
    let fitted = robot.fitted();
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(1));
    (0..BUILT)
        .filter_map(|_| {
            let mut built = description.clone();
            for leg in 0..robot.actuators() {
                let values: Vec<f64> = built
                    .fitted_values(leg)
                    .iter()
                    .zip(fitted)
                    .map(|(v, f)| {
                        if f.angle {
                            *v
                        } else {
                            v + rng.gen_range(-by..by)
                        }
                    })
                    .collect();
                built.set_fitted_values(leg, &values);
            }
            Nominal::new(built).ok()
        })
        .collect()
}

/// Each leg's whitened, scaled row of the geometry Jacobian at `pose`.
fn rows(
    robot: &Nominal,
    parameters: &[f64],
    pose: &[f64],
    q: &[f64],
    options: &Options,
) -> Vec<DVector<f64>> {
    let at = robot.residuals(parameters, pose, q);
    let (legs, fitted) = (q.len(), robot.fitted().len());
    let width = at.pose.len() / legs;
    (0..legs)
        .map(|leg| {
            let sigma =
                super::residual_sigma(&at.pose[width * leg..width * (leg + 1)], &options.noise);
            DVector::from_fn(fitted, |k, _| {
                at.geometry[fitted * leg + k] * options.scale / sigma
            })
        })
        .collect()
}

/// What an instrument and the encoders would report at `poses` of the robot `truth`: its
/// encoders' readings with `noise.encoder`, and each pose with `noise.position` and
/// `noise.angle`, drawn from `seed`. For trials of a calibration (how many poses of what noise
/// buy what accuracy) and tests.
///
/// # Errors
/// A pose of the wrong width, or where `truth`'s inverse kinematics fails (non-finite,
/// singular, out of reach).
pub fn simulate(
    truth: &Nominal,
    poses: &[Vec<f64>],
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
    let mechanism = truth.mechanism();
    let n = truth.actuators();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    poses
        .iter()
        .map(|pose| {
            let mut q = alloc::vec![0.0; n];
            mechanism.actuator_positions(pose, &mut q)?;
            let turns = pose.len().saturating_sub(3);
            let measured = pose
                .iter()
                .enumerate()
                .map(|(k, x)| {
                    let d = if k < turns { &angle } else { &position };
                    x + d.sample(&mut rng)
                })
                .collect();
            Ok(Measurement {
                pose: measured,
                q: q.into_iter()
                    .map(|v| v + encoder.sample(&mut rng))
                    .collect(),
            })
        })
        .collect()
}
