//! Streaming weighted least squares: the normal equations of each actuator, accumulated sample
//! by sample, so that memory does not grow with the data.
//!
//! Each actuator `i` keeps `A_i = Σ Y_iᵀ Y_i`, `b_i = Σ Y_iᵀ Γ_i` and `Σ Γ_i²` (rows gathered in
//! blocks and added with one matrix product). The estimate is the usual two-step one: ordinary
//! least squares, each actuator's residual variance `σ_i²` from its residuals, then the least
//! squares weighted by `1/σ_i²`, whose inverse normal matrix is the covariance of `β`. The
//! normal matrices are equilibrated (unit diagonal) before they are factored.

use super::BaseParameters;
use crate::platform::Mechanism;
use crate::{check_finite, Error, State};
use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen};
use std::fmt;

/// Samples gathered before they are added to the normal equations in one product.
const BLOCK: usize = 256;

/// Below this ratio of the smallest to the largest eigenvalue of the equilibrated normal
/// matrix (a condition number of the observation matrix above about `3·10⁶`) a direction of
/// the parameters is not identified: the data cannot tell it from noise.
const RANK_TOLERANCE: f64 = 1e-13;

/// Why no estimate could be made.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum IdentifyError {
    /// Fewer samples than the base parameters need (an equation per actuator per sample, and
    /// some to spare for the residual variance).
    TooFewSamples { samples: usize, needed: usize },
    /// The data leave these base parameters (or combinations of them) undetermined: the
    /// motion does not excite them. `condition_number` is that of the observation matrix.
    Unidentifiable {
        parameters: Vec<String>,
        condition_number: f64,
    },
}

impl fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IdentifyError::TooFewSamples { samples, needed } => write!(
                f,
                "too few samples: {samples}, the base parameters need at least {needed}"
            ),
            IdentifyError::Unidentifiable {
                parameters,
                condition_number,
            } => write!(
                f,
                "the data cannot identify {} (condition number {condition_number:.3e}): \
                 use a motion that excites them, e.g. `c5 excite`",
                parameters.join(", ")
            ),
        }
    }
}

impl std::error::Error for IdentifyError {}

/// Identified base parameters.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Estimate {
    /// The model whose base regressor was fitted (`consistent`, `paper`, `gough-stewart`).
    pub model: String,
    /// The base parameters' names ([`BaseParameters::names`]).
    pub names: Vec<String>,
    /// `β`.
    pub values: Vec<f64>,
    /// Standard deviation of each value, from the weighted fit's covariance.
    pub std_dev: Vec<f64>,
    /// `100 σ/|β|` (infinite, written `null`, for a value of zero).
    #[cfg_attr(feature = "serde", serde(with = "infinite_as_null"))]
    pub relative_std_dev_percent: Vec<f64>,
    /// Condition number of the weighted observation matrix with its columns scaled to unit
    /// norm: how well the motion excites the parameters (1 is perfect).
    pub condition_number: f64,
    /// Root mean square of each actuator's residual (N, or N·m for a motor's torque).
    pub residual_rms: Vec<f64>,
    /// Samples used.
    pub samples: usize,
}

impl Estimate {
    /// The actuator forces these parameters predict at `state` on `robot`'s geometry:
    /// `Y_b β`.
    ///
    /// # Errors
    /// [`Error::Unsupported`] if `robot` is of another model than the estimate (or `state`
    /// turns a platform that only translates), [`Error::WrongLength`] if its values are not
    /// as many as its names, and [`Mechanism::base_regressor_into`]'s errors.
    pub fn forces(&self, robot: &dyn Mechanism, state: &State) -> Result<Vec<f64>, Error> {
        if robot.model_name() != self.model {
            return Err(Error::Unsupported {
                what: "forces from these base parameters",
                mechanism: robot.model_name(),
                why: "they were identified on another model",
            });
        }
        let nb = self.names.len();
        if self.values.len() != nb {
            return Err(Error::WrongLength {
                input: "base parameters",
                expected: nb,
                got: self.values.len(),
            });
        }
        let n = robot.freedom().dimension();
        let [x, v, a] = robot.coordinates_of(state)?;
        let mut y = vec![0.0; n * nb];
        robot.base_regressor_into([&x, &v, &a], &mut y)?;
        Ok(y.chunks(nb)
            .map(|row| row.iter().zip(&self.values).map(|(a, b)| a * b).sum())
            .collect())
    }
}

/// Accumulates samples of motion and actuator forces; [`Identifier::estimate`] fits the base
/// parameters to them. Memory: a few `n_b × n_b` matrices, whatever the number of samples.
#[derive(Clone, Debug)]
pub struct Identifier {
    robot: Box<dyn Mechanism>,
    base: BaseParameters,
    /// How many actuators, each an equation per sample.
    actuators: usize,
    /// `A_i`, `b_i`, `Σ Γ_i²` per actuator.
    normal: Vec<DMatrix<f64>>,
    rhs: Vec<DVector<f64>>,
    squares: Vec<f64>,
    samples: usize,
    /// Per actuator, the regressor rows not yet added, one column per sample, and the forces.
    block: Vec<DMatrix<f64>>,
    block_gamma: Vec<DVector<f64>>,
    filled: usize,
    row: Vec<f64>,
}

impl Identifier {
    /// An identifier for `robot`'s model and geometry (its inertial parameters play no part).
    ///
    /// # Errors
    /// [`Mechanism::base_parameters`]' errors.
    pub fn new(robot: &dyn Mechanism) -> Result<Self, Error> {
        let base = robot.base_parameters()?;
        let (nb, n) = (base.len(), robot.freedom().dimension());
        Ok(Identifier {
            robot: robot.clone_mechanism(),
            base,
            actuators: n,
            normal: vec![DMatrix::zeros(nb, nb); n],
            rhs: vec![DVector::zeros(nb); n],
            squares: vec![0.0; n],
            samples: 0,
            block: vec![DMatrix::zeros(nb, BLOCK); n],
            block_gamma: vec![DVector::zeros(BLOCK); n],
            filled: 0,
            row: vec![0.0; n * nb],
        })
    }

    /// The base parameters being identified.
    pub fn base_parameters(&self) -> &BaseParameters {
        &self.base
    }

    /// How many actuators, and so forces per sample.
    pub fn actuators(&self) -> usize {
        self.actuators
    }

    /// Samples added so far.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Adds a sample: the platform's state and the measured actuator forces (N, or N·m for a
    /// motor's torque), one per actuator.
    ///
    /// # Errors
    /// Non-finite inputs, forces not one per actuator, a state that turns a platform that
    /// only translates, or a singular pose; the sample is then not added.
    pub fn add(&mut self, state: &State, gamma: &[f64]) -> Result<(), Error> {
        if self.robot.freedom().turns() {
            // Six coordinates are the state as it is: no allocation in the sample loop.
            let (x, v, a) = (
                state.pose.to_array(),
                state.twist.to_array(),
                state.accel.to_array(),
            );
            return self.add_motion([&x, &v, &a], gamma);
        }
        let [x, v, a] = self.robot.coordinates_of(state)?;
        self.add_motion([&x, &v, &a], gamma)
    }

    /// [`Identifier::add`] with the state in the platform's coordinates `[pose, twist,
    /// acceleration]` (as [`Mechanism`] takes them), allocating nothing.
    ///
    /// # Errors
    /// As [`Identifier::add`], and slices of the wrong length.
    pub fn add_motion(&mut self, motion: [&[f64]; 3], gamma: &[f64]) -> Result<(), Error> {
        if gamma.len() != self.actuators {
            return Err(Error::WrongLength {
                input: "gamma",
                expected: self.actuators,
                got: gamma.len(),
            });
        }
        check_finite("gamma", gamma)?;
        self.robot.base_regressor_into(motion, &mut self.row)?;
        let nb = self.base.len();
        for (i, &force) in gamma.iter().enumerate() {
            self.block[i]
                .column_mut(self.filled)
                .copy_from_slice(&self.row[i * nb..(i + 1) * nb]);
            self.block_gamma[i][self.filled] = force;
            self.squares[i] += force * force;
        }
        self.filled += 1;
        self.samples += 1;
        if self.filled == BLOCK {
            let (normal, rhs) = (&mut self.normal, &mut self.rhs);
            add_block(&self.block, &self.block_gamma, BLOCK, normal, rhs);
            self.filled = 0;
        }
        Ok(())
    }

    /// Fits the base parameters to the samples.
    ///
    /// # Errors
    /// [`IdentifyError::TooFewSamples`], or [`IdentifyError::Unidentifiable`] naming the base
    /// parameters the data leave undetermined.
    pub fn estimate(&self) -> Result<Estimate, IdentifyError> {
        let (nb, actuators) = (self.base.len(), self.actuators);
        let n = self.samples;
        let needed = (nb + 1).div_ceil(actuators) + 1;
        if n < needed {
            return Err(IdentifyError::TooFewSamples { samples: n, needed });
        }
        let (mut normal, mut rhs) = (self.normal.clone(), self.rhs.clone());
        add_block(
            &self.block,
            &self.block_gamma,
            self.filled,
            &mut normal,
            &mut rhs,
        );
        let dof = n as f64 - nb as f64 / actuators as f64;
        let ordinary = self.solve(&normal, &rhs, &vec![1.0; actuators])?;
        let weights: Vec<f64> = (0..actuators)
            .map(|i| {
                let residual = self.residual_squares(&normal[i], &rhs[i], i, &ordinary.values);
                // Noise-free data leave only rounding: floor the variance relative to the
                // forces.
                1.0 / (residual / dof).max(1e-24 * self.squares[i] / n as f64 + f64::MIN_POSITIVE)
            })
            .collect();
        let weighted = self.solve(&normal, &rhs, &weights)?;
        let residual_rms = (0..actuators)
            .map(|i| {
                let squares = self.residual_squares(&normal[i], &rhs[i], i, &weighted.values);
                (squares / n as f64).sqrt()
            })
            .collect();
        let relative_std_dev_percent = weighted
            .values
            .iter()
            .zip(&weighted.std_dev)
            .map(|(v, s)| 100.0 * s / v.abs())
            .collect();
        Ok(Estimate {
            model: self.robot.model_name().to_string(),
            names: self.base.names().iter().map(|s| s.to_string()).collect(),
            values: weighted.values.iter().copied().collect(),
            std_dev: weighted.std_dev.iter().copied().collect(),
            relative_std_dev_percent,
            condition_number: weighted.condition_number,
            residual_rms,
            samples: n,
        })
    }

    /// `Σ (Γ_i - Y_i β)²` from the normal equations (clamped at zero against rounding).
    fn residual_squares(
        &self,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        i: usize,
        beta: &DVector<f64>,
    ) -> f64 {
        (self.squares[i] - 2.0 * beta.dot(b) + beta.dot(&(a * beta))).max(0.0)
    }

    /// The least squares with actuator `i`'s equations weighted by `weights[i]`.
    fn solve(
        &self,
        normal: &[DMatrix<f64>],
        rhs: &[DVector<f64>],
        weights: &[f64],
    ) -> Result<Fit, IdentifyError> {
        let nb = self.base.len();
        let mut a = DMatrix::zeros(nb, nb);
        let mut b = DVector::zeros(nb);
        for i in 0..self.actuators {
            a += &normal[i] * weights[i];
            b += &rhs[i] * weights[i];
        }
        let Equilibrated {
            scaled,
            scale,
            eigen,
            condition_number,
        } = self.equilibrate(&a)?;
        let largest = eigen.eigenvalues.max();
        // NaN eigenvalues (never from finite samples) count as rank deficient too.
        let smallest = eigen.eigenvalues.min();
        if smallest.is_nan() || smallest <= RANK_TOLERANCE * largest {
            let names = self.base.names();
            return Err(IdentifyError::Unidentifiable {
                parameters: weak_directions(&eigen, largest)
                    .into_iter()
                    .map(|k| names[k].to_string())
                    .collect(),
                condition_number,
            });
        }
        // Positive definite after the eigenvalue check, barring rounding at the threshold.
        let cholesky = Cholesky::new(scaled).ok_or(IdentifyError::Unidentifiable {
            parameters: Vec::new(),
            condition_number,
        })?;
        let scaled_b = b.component_mul(&scale);
        let values = cholesky.solve(&scaled_b).component_mul(&scale);
        let inverse = cholesky.inverse();
        let std_dev = DVector::from_fn(nb, |j, _| inverse[(j, j)].max(0.0).sqrt() * scale[j]);
        Ok(Fit {
            values,
            std_dev,
            condition_number,
        })
    }

    /// `S A S` with unit diagonal, and its eigen-decomposition. A zero column was never
    /// excited.
    fn equilibrate(&self, a: &DMatrix<f64>) -> Result<Equilibrated, IdentifyError> {
        let nb = self.base.len();
        let mut scale = DVector::zeros(nb);
        let mut never = Vec::new();
        for j in 0..nb {
            let d = a[(j, j)];
            if d > 0.0 && d.is_finite() {
                scale[j] = 1.0 / d.sqrt();
            } else {
                never.push(self.base.names()[j].to_string());
            }
        }
        if !never.is_empty() {
            // Also name what the excited columns leave undetermined among themselves.
            let excited: Vec<usize> = (0..nb).filter(|&j| scale[j] > 0.0).collect();
            let sub = DMatrix::from_fn(excited.len(), excited.len(), |r, c| {
                a[(excited[r], excited[c])] * scale[excited[r]] * scale[excited[c]]
            });
            let eigen = SymmetricEigen::new(sub);
            let largest = eigen.eigenvalues.max();
            let weak = weak_directions(&eigen, largest);
            never.extend(
                weak.into_iter()
                    .map(|k| self.base.names()[excited[k]].to_string()),
            );
            return Err(IdentifyError::Unidentifiable {
                parameters: never,
                condition_number: f64::INFINITY,
            });
        }
        let scaled = DMatrix::from_fn(nb, nb, |r, c| a[(r, c)] * scale[r] * scale[c]);
        let eigen = SymmetricEigen::new(scaled.clone());
        let condition_number = (eigen.eigenvalues.max() / eigen.eigenvalues.min().max(0.0)).sqrt();
        Ok(Equilibrated {
            scaled,
            scale,
            eigen,
            condition_number,
        })
    }

    /// The condition number of the (unweighted) observation matrix of the samples so far, its
    /// columns scaled to unit norm: how well the motion excites the base parameters, whatever
    /// the forces. Infinite when a base parameter is not excited at all.
    pub fn condition_number(&self) -> f64 {
        let (mut normal, mut rhs) = (self.normal.clone(), self.rhs.clone());
        add_block(
            &self.block,
            &self.block_gamma,
            self.filled,
            &mut normal,
            &mut rhs,
        );
        let nb = self.base.len();
        let a = normal.iter().fold(DMatrix::zeros(nb, nb), |sum, n| sum + n);
        self.equilibrate(&a)
            .map_or(f64::INFINITY, |e| e.condition_number)
    }
}

/// A normal matrix scaled to unit diagonal.
struct Equilibrated {
    scaled: DMatrix<f64>,
    scale: DVector<f64>,
    eigen: SymmetricEigen<f64, nalgebra::Dyn>,
    condition_number: f64,
}

/// One least-squares solution.
struct Fit {
    values: DVector<f64>,
    std_dev: DVector<f64>,
    condition_number: f64,
}

/// Adds the first `filled` columns of each actuator's block to its normal equations.
fn add_block(
    block: &[DMatrix<f64>],
    gamma: &[DVector<f64>],
    filled: usize,
    normal: &mut [DMatrix<f64>],
    rhs: &mut [DVector<f64>],
) {
    if filled == 0 {
        return;
    }
    for i in 0..block.len() {
        let rows = block[i].columns(0, filled);
        let forces = gamma[i].rows(0, filled);
        normal[i].gemm(1.0, &rows, &rows.transpose(), 1.0);
        rhs[i].gemv(1.0, &rows, &forces, 1.0);
    }
}

/// The indices (into the eigenvectors) that dominate the directions of (nearly) zero
/// eigenvalue.
fn weak_directions(eigen: &SymmetricEigen<f64, nalgebra::Dyn>, largest: f64) -> Vec<usize> {
    let mut weak: Vec<usize> = Vec::new();
    for (k, &lambda) in eigen.eigenvalues.iter().enumerate() {
        if lambda > RANK_TOLERANCE * largest {
            continue;
        }
        let v = eigen.eigenvectors.column(k);
        let peak = v.amax();
        for (j, x) in v.iter().enumerate() {
            if x.abs() >= 0.3 * peak && !weak.contains(&j) {
                weak.push(j);
            }
        }
    }
    weak.sort_unstable();
    weak
}

/// JSON has no infinity: an infinite relative deviation is written `null` and read back.
#[cfg(feature = "serde")]
mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        let finite: Vec<Option<f64>> = v.iter().map(|x| x.is_finite().then_some(*x)).collect();
        finite.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        let v: Vec<Option<f64>> = Vec::deserialize(d)?;
        Ok(v.into_iter().map(|x| x.unwrap_or(f64::INFINITY)).collect())
    }
}
