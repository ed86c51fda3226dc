//! The Gough-Stewart platform's regressors and base parameters.
//!
//! Its base regressor's columns are those the generator found for the example hexapod; which
//! standard parameters fold into each, and with what coefficients, depends on the geometry (a
//! rod's mass joins the platform's at its joint `p_i`), so [`GoughStewart::base_parameters`]
//! finds them for this robot from its own regressor.

use super::{BaseParameters, Friction};
use crate::gough_stewart::check_terms;
use crate::{Acceleration, Error, GoughStewart, Pose, State, Twist, C5};
use alloc::string::{String, ToString};
use alloc::vec::Vec;
use c5_generated::f64::gough_stewart as kernels;
use c5_robot::gough_stewart::GEOMETRY_PARAMETERS as GEOMETRY;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The standard parameters: the inertial ones, then viscous and Coulomb friction per actuator.
pub const STANDARD_PARAMETERS: usize = kernels::STANDARD_PARAMETERS.len();

/// The base parameters the generated base regressor has columns for.
pub const BASE_PARAMETERS: usize = kernels::BASE_PARAMETERS.len();

/// How many seeded states the groupings are found from (six equations each).
const GROUPING_STATES: usize = 40;

impl GoughStewart {
    /// The geometry and gravity, what the regressors read of the parameter vector.
    fn geometry(&self) -> [f64; GEOMETRY] {
        core::array::from_fn(|k| self.parameters()[k])
    }

    /// `Y` at `state` (`6 × 70`, row `i` for actuator `i+1`, columns in the order of
    /// [`BaseParameters::standard_names`]): `Γ = Y π` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn regressor(&self, state: &State) -> Result<[[f64; STANDARD_PARAMETERS]; 6], Error> {
        let [x, v, a] = C5::checked_motion(state)?;
        let (y, guard) = kernels::regressor(&x, &v, &a, &self.geometry());
        check_terms(&guard)?;
        finite_rows("regressor", y)
    }

    /// `Y_b` at `state` into `out`, row-major (`6 × n_b`): `Γ = Y_b β` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `6 n_b` long.
    pub fn base_regressor_into(&self, state: &State, out: &mut [f64]) -> Result<(), Error> {
        if out.len() != 6 * BASE_PARAMETERS {
            return Err(Error::WrongLength {
                input: "out",
                expected: 6 * BASE_PARAMETERS,
                got: out.len(),
            });
        }
        let [x, v, a] = C5::checked_motion(state)?;
        let (y, guard) = kernels::base_regressor(&x, &v, &a, &self.geometry());
        check_terms(&guard)?;
        out.copy_from_slice(finite_rows("base regressor", y)?.as_flattened());
        Ok(())
    }

    /// `Y_b` at `state` (`6 × n_b`).
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn base_regressor(&self, state: &State) -> Result<DMatrix<f64>, Error> {
        let mut rows = alloc::vec![0.0; 6 * BASE_PARAMETERS];
        self.base_regressor_into(state, &mut rows)?;
        Ok(DMatrix::from_row_slice(6, BASE_PARAMETERS, &rows))
    }

    /// The standard parameters `π` of this robot with the actuators' `friction`.
    pub fn standard_parameters(&self, friction: &[Friction; 6]) -> Vec<f64> {
        self.robot().standard_parameters(friction)
    }

    /// This robot's base parameters: the generated base regressor's columns, each with the
    /// standard parameters this geometry folds into it (found from the regressor on seeded
    /// states about home; a few hundred microseconds).
    ///
    /// # Errors
    /// [`Error::Unsupported`] if this geometry has base parameters the generated regressor
    /// lacks (none found so far; its test draws random hexapods).
    pub fn base_parameters(&self) -> Result<BaseParameters, Error> {
        let standard: Vec<String> = kernels::STANDARD_PARAMETERS
            .iter()
            .map(|s| s.to_string())
            .collect();
        let leads: Vec<usize> = kernels::BASE_OF_STANDARD.iter().map(|t| t[0].0).collect();
        let y = self.stacked_regressor(GROUPING_STATES);
        BaseParameters::from_regressor(crate::gough_stewart::MECHANISM, standard, &leads, &y)
    }

    /// `Y` stacked over `n` seeded states about home (singular ones passed over).
    fn stacked_regressor(&self, n: usize) -> DMatrix<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(0x6e5a);
        let home = self.home().to_array();
        let reach = [0.2, 0.2, 0.2, 0.03, 0.03, 0.03];
        let mut rows: Vec<[f64; STANDARD_PARAMETERS]> = Vec::with_capacity(6 * n);
        let mut draw = |scale: &[f64; 6]| -> [f64; 6] {
            core::array::from_fn(|k| scale[k] * rng.gen_range(-1.0..1.0))
        };
        for _ in 0..8 * n {
            let offset = draw(&reach);
            let pose: [f64; 6] = core::array::from_fn(|k| home[k] + offset[k]);
            let state = State {
                pose: Pose::from_array(pose),
                twist: Twist::from_array(draw(&[1.0; 6])),
                accel: Acceleration::from_array(draw(&[5.0; 6])),
            };
            if let Ok(y) = self.regressor(&state) {
                rows.extend(y);
                if rows.len() == 6 * n {
                    break;
                }
            }
        }
        DMatrix::from_fn(rows.len(), STANDARD_PARAMETERS, |r, k| rows[r][k])
    }
}

/// `y` if every entry is finite.
fn finite_rows<const W: usize>(
    output: &'static str,
    y: [[f64; W]; 6],
) -> Result<[[f64; W]; 6], Error> {
    match y.iter().flatten().all(|v| v.is_finite()) {
        true => Ok(y),
        false => Err(Error::NonFiniteResult { output }),
    }
}
