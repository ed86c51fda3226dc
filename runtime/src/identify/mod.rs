//! Identification: the dynamics is linear in the robot's inertial parameters and friction,
//! `Γ = Y(state) π`, so measured motion and forces give the parameters by least squares.
//!
//! Not every standard parameter shows in the forces: the generator finds the base parameters,
//! the combinations that do (`c5-codegen`'s QR with column pivoting of `Y` stacked over
//! states), and generates the base regressor `Y_b` with `Γ = Y_b β`. [`BaseParameters`] names
//! them and says what each groups; [`C5::base_regressor`] evaluates `Y_b`; [`Identifier`]
//! accumulates samples and estimates `β` with its standard deviations.
//!
//! Friction is the usual `Γ_f,i = Fv_i Q̇_i1 + Fc_i sign(Q̇_i1)`: the forces the actuators
//! apply are `Y_b β`, inertial and gravity loads plus friction.

pub mod encoder_log;
mod estimator;
pub mod excite;
pub mod filter;

pub use estimator::{Estimate, Identifier, IdentifyError};

use crate::{check_divisors, Error, Kernels, Model, State, C5};
pub use c5_robot::{standard_parameter_names, Friction, STANDARD_PARAMETERS};
use nalgebra::{DMatrix, SMatrix};

/// A model's base parameters: names, what each groups, and `β = B π`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaseParameters {
    model: Model,
    names: &'static [&'static str],
    relations: &'static [&'static str],
    of_standard: &'static [&'static [(usize, f64)]],
}

impl BaseParameters {
    /// The base parameters of `model`.
    pub fn of(model: Model) -> Self {
        let kernels = crate::kernels(model);
        BaseParameters {
            model,
            names: kernels.base_parameters(),
            relations: kernels.base_relations(),
            of_standard: kernels.base_of_standard(),
        }
    }

    pub fn model(&self) -> Model {
        self.model
    }

    /// `n_b`, the number of base parameters.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Never: every model has base parameters.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Their names, `platform_ixx_R` for one that groups others, else the standard name.
    pub fn names(&self) -> &'static [&'static str] {
        self.names
    }

    /// What each groups, `rod1_mass_R = rod1_mass + joint1_mass`.
    pub fn relations(&self) -> &'static [&'static str] {
        self.relations
    }

    /// `β = B π` for the standard parameters `standard` (order of [`standard_parameter_names`]).
    ///
    /// # Errors
    /// [`Error::WrongLength`] if `standard` is not [`STANDARD_PARAMETERS`] long,
    /// [`Error::NonFinite`] if it holds a non-finite value.
    pub fn from_standard(&self, standard: &[f64]) -> Result<Vec<f64>, Error> {
        if standard.len() != STANDARD_PARAMETERS {
            return Err(Error::WrongLength {
                input: "standard parameters",
                expected: STANDARD_PARAMETERS,
                got: standard.len(),
            });
        }
        crate::check_finite("standard parameters", standard)?;
        Ok(self
            .of_standard
            .iter()
            .map(|terms| terms.iter().map(|&(k, c)| c * standard[k]).sum())
            .collect())
    }

    /// The base parameters of a robot with the actuators' `friction`.
    pub fn of_robot(&self, robot: &crate::Robot, friction: &[Friction; 6]) -> Vec<f64> {
        let standard = robot.standard_parameters(friction);
        self.of_standard
            .iter()
            .map(|terms| terms.iter().map(|&(k, c)| c * standard[k]).sum())
            .collect()
    }
}

/// `[L gx gy gz]`, what the regressors read of the robot: the first of its parameter vector.
fn geometry(c5: &C5) -> [f64; c5_robot::GEOMETRY_PARAMETERS] {
    core::array::from_fn(|k| c5.parameters()[k])
}

impl C5 {
    /// The base parameters of this robot's model.
    pub fn base_parameters(&self) -> BaseParameters {
        BaseParameters::of(self.model())
    }

    /// `Y_b` at `state` into `out`, row-major (`6 × n_b`, row `i` for actuator `i+1`): `Γ = Y_b β`
    /// with friction. For streaming without allocation; [`C5::base_regressor`] returns a
    /// matrix.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `6 n_b` long.
    pub fn base_regressor_into(&self, state: &State, out: &mut [f64]) -> Result<(), Error> {
        let nb = self.base_parameters().len();
        if out.len() != 6 * nb {
            return Err(Error::WrongLength {
                input: "out",
                expected: 6 * nb,
                got: out.len(),
            });
        }
        let [x, v, a] = Self::checked_motion(state)?;
        let g = geometry(self);
        let r = self
            .kernels()
            .base_regressor_into(&x, &v, &a, &g, out)
            .ok_or(Error::WrongLength {
                input: "out",
                expected: 6 * nb,
                got: out.len(),
            })?;
        check_divisors(r)?;
        match out.iter().all(|y| y.is_finite()) {
            true => Ok(()),
            false => Err(Error::NonFiniteResult {
                output: "base regressor",
            }),
        }
    }

    /// `Y_b` at `state` (`6 × n_b`): the forces of any robot of this geometry are `Y_b β`.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn base_regressor(&self, state: &State) -> Result<DMatrix<f64>, Error> {
        let nb = self.base_parameters().len();
        let mut rows = vec![0.0; 6 * nb];
        self.base_regressor_into(state, &mut rows)?;
        Ok(DMatrix::from_row_slice(6, nb, &rows))
    }

    /// `Y` at `state` (`6 × 142`, columns in the order of [`standard_parameter_names`]):
    /// `Γ = Y π` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn regressor(&self, state: &State) -> Result<SMatrix<f64, 6, STANDARD_PARAMETERS>, Error> {
        let [x, v, a] = Self::checked_motion(state)?;
        let g = geometry(self);
        let (y, r) = self.kernels().regressor(&x, &v, &a, &g);
        check_divisors(r)?;
        let m = SMatrix::<f64, 6, STANDARD_PARAMETERS>::from_fn(|i, j| y[i][j]);
        match m.iter().all(|y| y.is_finite()) {
            true => Ok(m),
            false => Err(Error::NonFiniteResult {
                output: "regressor",
            }),
        }
    }
}
