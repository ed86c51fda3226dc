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

mod estimator;
pub mod excite;

pub use estimator::{Estimate, Identifier, IdentifyError};

use crate::{check_divisors, Error, Model, State, C5};
use c5_generated::f64::{consistent, paper};
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
        match model {
            Model::Consistent => BaseParameters {
                model,
                names: &consistent::BASE_PARAMETERS,
                relations: &consistent::BASE_RELATIONS,
                of_standard: &consistent::BASE_OF_STANDARD,
            },
            Model::Paper => BaseParameters {
                model,
                names: &paper::BASE_PARAMETERS,
                relations: &paper::BASE_RELATIONS,
                of_standard: &paper::BASE_OF_STANDARD,
            },
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

/// `[L gx gy gz]`, what the regressors read of the robot.
fn geometry(c5: &C5) -> [f64; 4] {
    let r = c5.robot();
    [r.half_spacing, r.gravity[0], r.gravity[1], r.gravity[2]]
}

/// Copies a kernel's `6 × N` rows into `out`, row-major.
fn copy_rows<const N: usize>(rows: &[[f64; N]; 6], out: &mut [f64]) {
    for (i, row) in rows.iter().enumerate() {
        out[i * N..(i + 1) * N].copy_from_slice(row);
    }
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
        let r = match self.model() {
            Model::Consistent => {
                let (y, r) = consistent::base_regressor(&x, &v, &a, &g);
                copy_rows(&y, out);
                r
            }
            Model::Paper => {
                let (y, r) = paper::base_regressor(&x, &v, &a, &g);
                copy_rows(&y, out);
                r
            }
        };
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
        let (y, r) = match self.model() {
            Model::Consistent => consistent::regressor(&x, &v, &a, &g),
            Model::Paper => paper::regressor(&x, &v, &a, &g),
        };
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
