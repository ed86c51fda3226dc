//! The weighted least-squares fit: Levenberg-Marquardt per leg on the generated residuals and
//! their exact Jacobians, then each estimate's standard deviation.

use super::nominal::Residuals;
use super::observability::{self, LegDesign};
use super::{residual_sigma, CalibrationError, Measurement, Nominal, Options, Parameter, Report};
use crate::{platform, Description, Model};
use alloc::vec::Vec;
use nalgebra::{DMatrix, DVector};

/// The step (in scales) below which a leg's fit has converged: a hundredth of a nanometre at
/// the default scale, far below any instrument's noise.
const STEP_TOLERANCE: f64 = 1e-8;

/// The residuals and their Jacobians at every measurement, for one geometry.
struct Evaluation {
    at: Vec<Residuals>,
}

impl Evaluation {
    fn of(nominal: &Nominal, robot: &Description, data: &[Measurement]) -> Self {
        let parameters = robot.kernel_parameters();
        Evaluation {
            at: data
                .iter()
                .map(|m| nominal.residuals(&parameters, &m.pose, &m.q))
                .collect(),
        }
    }

    fn residuals(self) -> Vec<Vec<f64>> {
        self.at.into_iter().map(|r| r.residual).collect()
    }
}

/// Each residual's standard deviation: the encoder's noise and the pose's, carried by `∂q/∂X`.
fn sigmas(at: &Evaluation, options: &Options) -> Vec<Vec<f64>> {
    at.at
        .iter()
        .map(|r| {
            let width = r.pose.len() / r.residual.len();
            r.pose
                .chunks(width)
                .map(|row| residual_sigma(row, &options.noise))
                .collect()
        })
        .collect()
}

/// Leg `leg`'s whitened, scaled Jacobian (one row per measurement) and whitened residuals.
fn whitened(
    at: &Evaluation,
    sigma: &[Vec<f64>],
    leg: usize,
    fitted: usize,
    scale: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let n = at.at.len();
    let j = DMatrix::from_fn(n, fitted, |row, k| {
        at.at[row].geometry[fitted * leg + k] * scale / sigma[row][leg]
    });
    let r = DVector::from_fn(n, |row, _| at.at[row].residual[leg] / sigma[row][leg]);
    (j, r)
}

/// The Levenberg-Marquardt step on the free parameters, in scales (zero on the fixed).
fn step(j: &DMatrix<f64>, r: &DVector<f64>, free: &[usize], lambda: f64) -> Option<DVector<f64>> {
    let jf = j.select_columns(free);
    let mut a = jf.transpose() * &jf;
    for k in 0..free.len() {
        a[(k, k)] *= 1.0 + lambda;
    }
    let g = jf.transpose() * r;
    let delta = a.cholesky()?.solve(&(-g));
    let mut full = DVector::zeros(j.ncols());
    for (k, &c) in free.iter().enumerate() {
        full[c] = delta[k];
    }
    Some(full)
}

fn cost(at: &Evaluation, sigma: &[Vec<f64>], leg: usize) -> f64 {
    at.at
        .iter()
        .zip(sigma)
        .map(|(r, s)| (r.residual[leg] / s[leg]).powi(2))
        .sum()
}

/// Each leg's Levenberg-Marquardt iterations from the nominal geometry, the legs fitted side
/// by side (one evaluation of every measurement per iteration); the geometry found, the
/// evaluation there and the iterations taken.
fn iterate(
    nominal: &Nominal,
    data: &[Measurement],
    options: &Options,
    sigma: &[Vec<f64>],
    designs: &[LegDesign],
    start: Evaluation,
) -> (Description, Evaluation, usize) {
    let (legs, fitted) = (designs.len(), nominal.fitted().len());
    let scale = options.scale;
    let mut robot = nominal.description();
    let mut at = start;
    let mut lambda = alloc::vec![1e-3; legs];
    let mut done = alloc::vec![false; legs];
    let mut iterations = 0;
    while iterations < options.iterations && !done.iter().all(|&d| d) {
        iterations += 1;
        let mut trial = robot.clone();
        let mut sizes = alloc::vec![0.0f64; legs];
        let active: Vec<usize> = (0..legs).filter(|&leg| !done[leg]).collect();
        for &leg in &active {
            let (j, r) = whitened(&at, sigma, leg, fitted, scale);
            let Some(delta) = step(&j, &r, &designs[leg].free, lambda[leg]) else {
                done[leg] = true;
                continue;
            };
            let theta: Vec<f64> = robot
                .fitted_values(leg)
                .iter()
                .zip(delta.iter())
                .map(|(t, d)| t + d * scale)
                .collect();
            sizes[leg] = delta.amax();
            trial.set_fitted_values(leg, &theta);
        }
        let next = Evaluation::of(nominal, &trial, data);
        for &leg in &active {
            if cost(&next, sigma, leg) <= cost(&at, sigma, leg) {
                robot.set_fitted_values(leg, &trial.fitted_values(leg));
                lambda[leg] = (lambda[leg] * 0.1).max(1e-12);
                done[leg] = sizes[leg] < STEP_TOLERANCE;
            } else {
                lambda[leg] *= 10.0;
                done[leg] = sizes[leg] < STEP_TOLERANCE || lambda[leg] > 1e12;
            }
        }
        at = Evaluation::of(nominal, &robot, data);
    }
    (robot, at, iterations)
}

pub(super) fn run(
    nominal: &Nominal,
    data: &[Measurement],
    options: &Options,
) -> Result<Report, CalibrationError> {
    let (legs, fitted) = (nominal.actuators(), nominal.fitted());
    let scale = options.scale;
    let start = Evaluation::of(nominal, &nominal.description(), data);
    // The weights stay those of the nominal geometry, so every iteration minimises one cost.
    let sigma = sigmas(&start, options);
    let designs: Vec<LegDesign> = (0..legs)
        .map(|leg| {
            let (j, _) = whitened(&start, &sigma, leg, fitted.len(), scale);
            observability::analyse(leg, &j, fitted, options)
        })
        .collect();
    let unobservable: Vec<_> = designs
        .iter()
        .flat_map(|d| d.unobservable.iter().cloned())
        .collect();
    if options.strict && !unobservable.is_empty() {
        return Err(CalibrationError::Unobservable {
            combinations: unobservable,
        });
    }
    let (robot, at, iterations) = iterate(nominal, data, options, &sigma, &designs, start);
    platform::load(robot.clone(), Model::Consistent).map_err(CalibrationError::Robot)?;

    let nominal_robot = nominal.description();
    let residuals_before = Evaluation::of(nominal, &nominal_robot, data).residuals();
    let free_count: usize = designs.iter().map(|d| d.free.len()).sum();
    let dof = (legs * data.len()).saturating_sub(free_count).max(1);
    let variance_factor = (0..legs).map(|leg| cost(&at, &sigma, leg)).sum::<f64>() / dof as f64;
    let mut parameters = Vec::with_capacity(legs * fitted.len());
    for (leg, design) in designs.iter().enumerate() {
        let (j, _) = whitened(&at, &sigma, leg, fitted.len(), scale);
        let std_devs = observability::std_devs(&j, &design.free, variance_factor);
        let (before, after) = (nominal_robot.fitted_values(leg), robot.fitted_values(leg));
        for (k, f) in fitted.iter().enumerate() {
            parameters.push(Parameter {
                name: f.name(leg + 1),
                leg: leg + 1,
                angle: f.angle,
                nominal: before[k],
                estimate: after[k],
                std_dev: std_devs[k].map(|s| s * scale),
            });
        }
    }
    Ok(Report {
        robot,
        parameters,
        angular: nominal.angular(),
        residuals_before,
        residuals_after: at.residuals(),
        singular_values: designs.into_iter().map(|d| d.singular_values).collect(),
        unobservable,
        variance_factor,
        iterations,
    })
}
