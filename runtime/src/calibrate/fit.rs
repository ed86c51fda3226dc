//! The weighted least-squares fit: Levenberg-Marquardt per leg on the generated residuals and
//! their exact Jacobians, then each estimate's standard deviation.

use super::observability::{self, LegDesign};
use super::{
    leg_parameters, parameter_name, residual_sigma, with_leg_parameters, CalibrationError,
    Measurement, Options, Parameter, Report, PER_LEG,
};
use crate::gough_stewart::{Description, GoughStewart};
use alloc::vec::Vec;
use c5_generated::f64::gough_stewart::{calibration_residuals, GEOMETRY_PARAMETERS};
use nalgebra::{DMatrix, DVector};

/// The step (in scales) below which a leg's fit has converged: a hundredth of a nanometre at
/// the default scale, far below any instrument's noise.
const STEP_TOLERANCE: f64 = 1e-8;

/// The residuals and the geometry Jacobian at every measurement.
struct Evaluation {
    residuals: Vec<[f64; 6]>,
    jacobians: Vec<[[f64; PER_LEG]; 6]>,
    pose_jacobians: Vec<[[f64; 6]; 6]>,
}

fn evaluate(robot: &Description, data: &[Measurement]) -> Evaluation {
    let mut geometry = [0.0; GEOMETRY_PARAMETERS];
    geometry.copy_from_slice(&robot.kernel_parameters()[..GEOMETRY_PARAMETERS]);
    let mut out = Evaluation {
        residuals: Vec::with_capacity(data.len()),
        jacobians: Vec::with_capacity(data.len()),
        pose_jacobians: Vec::with_capacity(data.len()),
    };
    for m in data {
        let (r, j, jx) = calibration_residuals(&m.pose.to_array(), &m.q, &geometry);
        out.residuals.push(r);
        out.jacobians.push(j);
        out.pose_jacobians.push(jx);
    }
    out
}

/// Each residual's standard deviation: the encoder's noise and the pose's, carried by `∂ρ/∂X`.
fn sigmas(at: &Evaluation, options: &Options) -> Vec<[f64; 6]> {
    at.pose_jacobians
        .iter()
        .map(|jx| core::array::from_fn(|i| residual_sigma(&jx[i], &options.noise)))
        .collect()
}

/// Leg `leg`'s whitened, scaled Jacobian (one row per measurement) and whitened residuals.
fn whitened(
    at: &Evaluation,
    sigma: &[[f64; 6]],
    leg: usize,
    scale: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let n = at.residuals.len();
    let j = DMatrix::from_fn(n, PER_LEG, |row, k| {
        at.jacobians[row][leg][k] * scale / sigma[row][leg]
    });
    let r = DVector::from_fn(n, |row, _| at.residuals[row][leg] / sigma[row][leg]);
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
    let mut full = DVector::zeros(PER_LEG);
    for (k, &c) in free.iter().enumerate() {
        full[c] = delta[k];
    }
    Some(full)
}

fn cost(at: &Evaluation, sigma: &[[f64; 6]], leg: usize) -> f64 {
    at.residuals
        .iter()
        .zip(sigma)
        .map(|(r, s)| (r[leg] / s[leg]).powi(2))
        .sum()
}

pub(super) fn run(
    nominal: &Description,
    data: &[Measurement],
    options: &Options,
) -> Result<Report, CalibrationError> {
    let scale = options.scale;
    let start = evaluate(nominal, data);
    // The weights stay those of the nominal geometry, so every iteration minimises one cost.
    let sigma = sigmas(&start, options);
    let designs: Vec<LegDesign> = (0..6)
        .map(|leg| {
            let (j, _) = whitened(&start, &sigma, leg, scale);
            observability::analyse(leg, &j, options)
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

    let mut robot = *nominal;
    let mut at = start;
    let mut lambda = [1e-3; 6];
    let mut done = [false; 6];
    let mut iterations = 0;
    while iterations < options.iterations && !done.iter().all(|&d| d) {
        iterations += 1;
        let mut trial = robot;
        let mut steps = [[0.0; PER_LEG]; 6];
        let active: Vec<usize> = (0..6).filter(|&leg| !done[leg]).collect();
        for &leg in &active {
            let (j, r) = whitened(&at, &sigma, leg, scale);
            let Some(delta) = step(&j, &r, &designs[leg].free, lambda[leg]) else {
                done[leg] = true;
                continue;
            };
            let mut theta = leg_parameters(&robot, leg);
            for k in 0..PER_LEG {
                steps[leg][k] = delta[k];
                theta[k] += delta[k] * scale;
            }
            with_leg_parameters(&mut trial, leg, &theta);
        }
        let next = evaluate(&trial, data);
        for &leg in &active {
            let size = steps[leg].iter().fold(0.0f64, |m, d| m.max(d.abs()));
            if cost(&next, &sigma, leg) <= cost(&at, &sigma, leg) {
                with_leg_parameters(&mut robot, leg, &leg_parameters(&trial, leg));
                lambda[leg] = (lambda[leg] * 0.1).max(1e-12);
                done[leg] = size < STEP_TOLERANCE;
            } else {
                lambda[leg] *= 10.0;
                done[leg] = size < STEP_TOLERANCE || lambda[leg] > 1e12;
            }
        }
        at = evaluate(&robot, data);
    }
    GoughStewart::new(robot).map_err(CalibrationError::Robot)?;

    let residuals_before = evaluate(nominal, data).residuals;
    let free_count: usize = designs.iter().map(|d| d.free.len()).sum();
    let dof = (6 * data.len()).saturating_sub(free_count).max(1);
    let variance_factor = (0..6).map(|leg| cost(&at, &sigma, leg)).sum::<f64>() / dof as f64;
    let mut parameters = Vec::with_capacity(6 * PER_LEG);
    for (leg, design) in designs.iter().enumerate() {
        let (j, _) = whitened(&at, &sigma, leg, scale);
        let std_devs = observability::std_devs(&j, &design.free, variance_factor);
        let (before, after) = (leg_parameters(nominal, leg), leg_parameters(&robot, leg));
        for k in 0..PER_LEG {
            parameters.push(Parameter {
                name: parameter_name(leg, k),
                leg: leg + 1,
                nominal: before[k],
                estimate: after[k],
                std_dev: std_devs[k].map(|s| s * scale),
            });
        }
    }
    Ok(Report {
        robot,
        parameters,
        residuals_before,
        residuals_after: at.residuals,
        singular_values: core::array::from_fn(|leg| designs[leg].singular_values),
        unobservable,
        variance_factor,
        iterations,
    })
}
