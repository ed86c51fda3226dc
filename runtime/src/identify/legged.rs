//! The legged mechanisms' regressors and base parameters (the Gough-Stewart platform, the
//! rotary hexapod, the Delta), written once over each mechanism's generated regressors
//! (`c5_generated::legged::Regressors`) and in its platform's coordinates.
//!
//! Their base regressors' columns are those the generator found for the checked-in example of
//! each; which standard parameters fold into each, and with what coefficients, depends on the
//! geometry (a rod's mass joins the platform's at its ball joint `p_i`), so `base_parameters`
//! finds them for the robot at hand from its own regressor.

use crate::legged::{
    Coordinates, Freedoms, LeggedDescription, LeggedRobot, Motion, Platform, StateOf,
};
use crate::Error;
use alloc::vec::Vec;
use c5_generated::legged::{Legs, Regressors};
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How many seeded states the groupings are found from (six equations each).
const GROUPING_STATES: usize = 40;

impl<D: LeggedDescription<N>, const N: usize> LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
{
    /// `Y` at `state` (row `i` for actuator `i+1`, columns in the order of
    /// `BaseParameters::standard_names`): `Γ = Y π` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn regressor(&self, state: &StateOf<N>) -> Result<[StandardRow<D, N>; N], Error> {
        self.regressor_at(&state.checked("state")?)
    }

    /// `Y` at the platform's coordinates `[pose, twist, acceleration]`, checked finite.
    pub(crate) fn regressor_at(
        &self,
        [x, v, a]: &Motion<N>,
    ) -> Result<[StandardRow<D, N>; N], Error> {
        let y = self.checked(D::Kernels::regressor(x, v, a, &self.params))?;
        finite_rows("regressor", y)
    }

    /// `Y_b` at `state` into `out`, row-major (`n × n_b` for `n` actuators): `Γ = Y_b β` with
    /// friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `n n_b` long.
    pub fn base_regressor_into(&self, state: &StateOf<N>, out: &mut [f64]) -> Result<(), Error> {
        let width = D::Kernels::BASE_PARAMETERS.len();
        if out.len() != N * width {
            return Err(Error::WrongLength {
                input: "out",
                expected: N * width,
                got: out.len(),
            });
        }
        let [x, v, a] = state.checked("state")?;
        let y = self.checked(D::Kernels::base_regressor(&x, &v, &a, &self.params))?;
        for (row, slot) in finite_rows("base regressor", y)?
            .iter()
            .zip(out.chunks_exact_mut(width))
        {
            slot.copy_from_slice(row.as_ref());
        }
        Ok(())
    }

    /// `Y_b` at `state` (`n × n_b`).
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn base_regressor(&self, state: &StateOf<N>) -> Result<DMatrix<f64>, Error> {
        let width = D::Kernels::BASE_PARAMETERS.len();
        let mut rows = alloc::vec![0.0; N * width];
        self.base_regressor_into(state, &mut rows)?;
        Ok(DMatrix::from_row_slice(N, width, &rows))
    }

    /// The standard parameters `π` of this robot with the actuators' `friction`.
    pub fn standard_parameters(&self, friction: &[crate::identify::Friction; N]) -> Vec<f64> {
        self.robot().standard_parameters(friction)
    }

    /// This robot's base parameters: the generated base regressor's columns, each with the
    /// standard parameters this geometry folds into it (found from the regressor on seeded
    /// states about home; a few hundred microseconds).
    ///
    /// # Errors
    /// [`Error::Unsupported`] if this geometry has base parameters the generated regressor
    /// lacks.
    pub fn base_parameters(&self) -> Result<crate::identify::BaseParameters, Error> {
        let standard = D::Kernels::STANDARD_PARAMETERS
            .iter()
            .map(alloc::string::ToString::to_string)
            .collect();
        let leads: Vec<usize> = D::Kernels::BASE_OF_STANDARD
            .iter()
            .map(|t| t[0].0)
            .collect();
        let y = stacked_regressor(
            self.home_array(),
            &D::IDENTIFICATION_REACH,
            D::Kernels::STANDARD_PARAMETERS.len(),
            |motion| {
                self.regressor_at(motion).map(|y| {
                    y.iter()
                        .flat_map(|row| row.as_ref().iter().copied())
                        .collect()
                })
            },
        );
        crate::identify::BaseParameters::from_regressor(D::Kernels::MECHANISM, standard, &leads, &y)
    }
}

/// A row of the standard regressor of the description `D`'s kernels.
pub type StandardRow<D, const N: usize> =
    <<D as LeggedDescription<N>>::Kernels as Regressors<N>>::StandardRow;

/// `Y` (`width` columns) stacked over [`GROUPING_STATES`] seeded states within `reach` of
/// `home`, in the platform's `N` coordinates, singular ones passed over.
pub(crate) fn stacked_regressor<const N: usize>(
    home: &[f64; N],
    reach: &[f64; N],
    width: usize,
    regressor: impl Fn(&[[f64; N]; 3]) -> Result<Vec<f64>, Error>,
) -> DMatrix<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(0x6e5a);
    let mut rows: Vec<f64> = Vec::with_capacity(N * GROUPING_STATES * width);
    let mut draw = |scale: &[f64; N]| -> [f64; N] {
        core::array::from_fn(|k| scale[k] * rng.gen_range(-1.0..1.0))
    };
    for _ in 0..8 * GROUPING_STATES {
        let offset = draw(reach);
        let pose: [f64; N] = core::array::from_fn(|k| home[k] + offset[k]);
        let motion = [pose, draw(&[1.0; N]), draw(&[5.0; N])];
        if let Ok(y) = regressor(&motion) {
            rows.extend(y);
            if rows.len() == N * GROUPING_STATES * width {
                break;
            }
        }
    }
    DMatrix::from_row_slice(rows.len() / width, width, &rows)
}

/// `y` if every entry is finite.
pub(crate) fn finite_rows<R: AsRef<[f64]>, const N: usize>(
    output: &'static str,
    y: [R; N],
) -> Result<[R; N], Error> {
    match y
        .iter()
        .all(|row| row.as_ref().iter().all(|v| v.is_finite()))
    {
        true => Ok(y),
        false => Err(Error::NonFiniteResult { output }),
    }
}
