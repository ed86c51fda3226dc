//! Identification: the dynamics is linear in the robot's inertial parameters and friction,
//! `Γ = Y(state) π`, so measured motion and forces give the parameters by least squares.
//!
//! Not every standard parameter shows in the forces: the generator finds the base parameters,
//! the combinations that do (`c5-codegen`'s QR with column pivoting of `Y` stacked over
//! states), and generates the base regressor `Y_b` with `Γ = Y_b β`. [`BaseParameters`] names
//! them and says what each groups; [`C5::base_regressor`] evaluates `Y_b` (every mechanism's
//! through [`Mechanism::base_regressor_into`], in its
//! platform's coordinates); [`Identifier`] accumulates samples of any mechanism and estimates
//! `β` with its standard deviations.
//!
//! Friction is the usual `Γ_f,i = Fv_i Q̇_i1 + Fc_i sign(Q̇_i1)`: the forces the actuators
//! apply are `Y_b β`, inertial and gravity loads plus friction.

pub mod encoder_log;
mod estimator;
pub mod excite;
pub mod filter;
mod grouping;
mod legged;

pub use estimator::{Estimate, Identifier, IdentifyError};

use crate::{check_divisors, Error, Kernels, Mechanism, Model, State, C5};
use alloc::string::{String, ToString};
use alloc::vec::Vec;
pub use c5_robot::{standard_parameter_names, Friction, STANDARD_PARAMETERS};
use nalgebra::{DMatrix, SMatrix};

/// A robot's base parameters: names, what each groups, and `β = B π`.
#[derive(Clone, Debug, PartialEq)]
pub struct BaseParameters {
    model: &'static str,
    standard: Vec<String>,
    names: Vec<String>,
    relations: Vec<String>,
    of_standard: Vec<Vec<(usize, f64)>>,
}

impl BaseParameters {
    /// The base parameters of the C5 under `model` (the same for every C5 geometry).
    pub fn of(model: Model) -> Self {
        let kernels = crate::kernels(model);
        BaseParameters {
            model: model.name(),
            standard: standard_parameter_names(),
            names: kernels
                .base_parameters()
                .iter()
                .map(|s| s.to_string())
                .collect(),
            relations: kernels
                .base_relations()
                .iter()
                .map(|s| s.to_string())
                .collect(),
            of_standard: kernels
                .base_of_standard()
                .iter()
                .map(|t| t.to_vec())
                .collect(),
        }
    }

    /// The base parameters whose columns are `leads` (indices into `standard`, one per base
    /// parameter), each grouping what `y` (the full regressor stacked over states that excite
    /// every direction) says depends on it: `Y = Y_b B`, solved by least squares. For a
    /// mechanism whose groupings depend on its geometry (a hexapod's rod masses join the
    /// platform's at its joints `p_i`).
    ///
    /// # Errors
    /// [`Error::Unsupported`] when `Y_b B` falls short of `Y` (this geometry has base
    /// parameters the generated `Y_b` lacks).
    pub(crate) fn from_regressor(
        model: &'static str,
        standard: Vec<String>,
        leads: &[usize],
        y: &DMatrix<f64>,
    ) -> Result<Self, Error> {
        let groups = grouping::groups(y, leads).ok_or(Error::Unsupported {
            what: "base parameters",
            mechanism: model,
            why: "this geometry's regressor has directions the generated base regressor \
                  lacks; generate the robot's own kernels (c5-codegen kernels --robot FILE)",
        })?;
        let names = groups
            .iter()
            .map(|g| grouping::name(&standard, g))
            .collect();
        let relations = groups
            .iter()
            .map(|g| grouping::relation(&standard, g))
            .collect();
        Ok(BaseParameters {
            model,
            standard,
            names,
            relations,
            of_standard: groups,
        })
    }

    /// The name of the model whose base regressor these are (`consistent`, `gough-stewart`).
    pub fn model(&self) -> &'static str {
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
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// What each groups, `rod1_mass_R = rod1_mass + joint1_mass`.
    pub fn relations(&self) -> &[String] {
        &self.relations
    }

    /// The standard parameters' names, the columns of the full regressor.
    pub fn standard_names(&self) -> &[String] {
        &self.standard
    }

    /// `β = B π` for the standard parameters `standard` (order of
    /// [`BaseParameters::standard_names`]).
    ///
    /// # Errors
    /// [`Error::WrongLength`] if `standard` is not as long as the standard parameters,
    /// [`Error::NonFinite`] if it holds a non-finite value.
    pub fn from_standard(&self, standard: &[f64]) -> Result<Vec<f64>, Error> {
        if standard.len() != self.standard.len() {
            return Err(Error::WrongLength {
                input: "standard parameters",
                expected: self.standard.len(),
                got: standard.len(),
            });
        }
        crate::check_finite("standard parameters", standard)?;
        Ok(self.apply(standard))
    }

    /// The base parameters of `robot`, of any mechanism, with the actuators' `friction` (one
    /// per actuator).
    ///
    /// # Errors
    /// [`Error::WrongLength`] if `friction` is not one per actuator, or if `robot` is of
    /// another mechanism (another number of standard parameters).
    pub fn of_robot(
        &self,
        robot: &dyn Mechanism,
        friction: &[Friction],
    ) -> Result<Vec<f64>, Error> {
        self.from_standard(&robot.standard_parameters(friction)?)
    }

    fn apply(&self, standard: &[f64]) -> Vec<f64> {
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
        let nb = self.kernels().base_parameters().len();
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
        let nb = self.kernels().base_parameters().len();
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
