//! The legged mechanisms' regressors and base parameters (the Gough-Stewart platform, the
//! rotary hexapod), written once and instantiated for each over its generated kernels.
//!
//! Their base regressors' columns are those the generator found for the checked-in example of
//! each; which standard parameters fold into each, and with what coefficients, depends on the
//! geometry (a rod's mass joins the platform's at its ball joint `p_i`), so `base_parameters`
//! finds them for the robot at hand from its own regressor.

use crate::{Acceleration, Error, Pose, State, Twist};
use alloc::vec::Vec;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How many seeded states the groupings are found from (six equations each).
const GROUPING_STATES: usize = 40;

/// The identification methods of a legged mechanism: `$robot` with its generated kernels
/// `$kernels` (`regressor`, `base_regressor`, their parameter names and groupings), its
/// singularity check `$check`, and `$reach`, how far from home (rad, m) the seeded states of
/// the groupings are drawn.
macro_rules! legged_identification {
    ($robot:ty, $kernels:ident, $check:path, $reach:expr) => {
        impl $robot {
            /// The geometry and gravity, what the regressors read of the parameter vector.
            fn identification_geometry(
                &self,
            ) -> [f64; c5_generated::f64::$kernels::GEOMETRY_PARAMETERS] {
                core::array::from_fn(|k| self.parameters()[k])
            }

            /// `Y` at `state` (row `i` for actuator `i+1`, columns in the order of
            /// `BaseParameters::standard_names`): `Γ = Y π` with friction.
            ///
            /// # Errors
            /// Non-finite inputs, a singular pose or a non-finite result.
            pub fn regressor(
                &self,
                state: &crate::State,
            ) -> Result<
                [[f64; c5_generated::f64::$kernels::STANDARD_PARAMETERS.len()]; 6],
                crate::Error,
            > {
                let [x, v, a] = crate::C5::checked_motion(state)?;
                let (y, guard) = c5_generated::f64::$kernels::regressor(
                    &x,
                    &v,
                    &a,
                    &self.identification_geometry(),
                );
                $check(&guard)?;
                crate::identify::legged::finite_rows("regressor", y)
            }

            /// `Y_b` at `state` into `out`, row-major (`6 × n_b`): `Γ = Y_b β` with friction.
            ///
            /// # Errors
            /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `6 n_b`
            /// long.
            pub fn base_regressor_into(
                &self,
                state: &crate::State,
                out: &mut [f64],
            ) -> Result<(), crate::Error> {
                const WIDTH: usize = c5_generated::f64::$kernels::BASE_PARAMETERS.len();
                if out.len() != 6 * WIDTH {
                    return Err(crate::Error::WrongLength {
                        input: "out",
                        expected: 6 * WIDTH,
                        got: out.len(),
                    });
                }
                let [x, v, a] = crate::C5::checked_motion(state)?;
                let (y, guard) = c5_generated::f64::$kernels::base_regressor(
                    &x,
                    &v,
                    &a,
                    &self.identification_geometry(),
                );
                $check(&guard)?;
                out.copy_from_slice(
                    crate::identify::legged::finite_rows("base regressor", y)?.as_flattened(),
                );
                Ok(())
            }

            /// `Y_b` at `state` (`6 × n_b`).
            ///
            /// # Errors
            /// Non-finite inputs, a singular pose or a non-finite result.
            pub fn base_regressor(
                &self,
                state: &crate::State,
            ) -> Result<nalgebra::DMatrix<f64>, crate::Error> {
                const WIDTH: usize = c5_generated::f64::$kernels::BASE_PARAMETERS.len();
                let mut rows = alloc::vec![0.0; 6 * WIDTH];
                self.base_regressor_into(state, &mut rows)?;
                Ok(nalgebra::DMatrix::from_row_slice(6, WIDTH, &rows))
            }

            /// The standard parameters `π` of this robot with the actuators' `friction`.
            pub fn standard_parameters(
                &self,
                friction: &[crate::identify::Friction; 6],
            ) -> alloc::vec::Vec<f64> {
                self.robot().standard_parameters(friction)
            }

            /// This robot's base parameters: the generated base regressor's columns, each
            /// with the standard parameters this geometry folds into it (found from the
            /// regressor on seeded states about home; a few hundred microseconds).
            ///
            /// # Errors
            /// [`Error::Unsupported`](crate::Error::Unsupported) if this geometry has base
            /// parameters the generated regressor lacks.
            pub fn base_parameters(&self) -> Result<crate::identify::BaseParameters, crate::Error> {
                use c5_generated::f64::$kernels as kernels;
                let standard = kernels::STANDARD_PARAMETERS
                    .iter()
                    .map(|s| alloc::string::ToString::to_string(s))
                    .collect();
                let leads: alloc::vec::Vec<usize> =
                    kernels::BASE_OF_STANDARD.iter().map(|t| t[0].0).collect();
                let y = crate::identify::legged::stacked_regressor(
                    &self.home(),
                    &$reach,
                    kernels::STANDARD_PARAMETERS.len(),
                    |state| self.regressor(state).map(|y| y.concat()),
                );
                crate::identify::BaseParameters::from_regressor(
                    <$robot as crate::ParallelRobot>::mechanism(self),
                    standard,
                    &leads,
                    &y,
                )
            }
        }
    };
}

legged_identification!(
    crate::GoughStewart,
    gough_stewart,
    crate::gough_stewart::check_terms,
    [0.2, 0.2, 0.2, 0.03, 0.03, 0.03]
);
legged_identification!(
    crate::RusHexapod,
    rus_hexapod,
    crate::rus_hexapod::check_terms,
    [0.1, 0.1, 0.1, 0.02, 0.02, 0.02]
);

/// `Y` (`width` columns) stacked over [`GROUPING_STATES`] seeded states within `reach` of
/// `home`, singular ones passed over.
pub(crate) fn stacked_regressor(
    home: &Pose,
    reach: &[f64; 6],
    width: usize,
    regressor: impl Fn(&State) -> Result<Vec<f64>, Error>,
) -> DMatrix<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(0x6e5a);
    let home = home.to_array();
    let mut rows: Vec<f64> = Vec::with_capacity(6 * GROUPING_STATES * width);
    let mut draw = |scale: &[f64; 6]| -> [f64; 6] {
        core::array::from_fn(|k| scale[k] * rng.gen_range(-1.0..1.0))
    };
    for _ in 0..8 * GROUPING_STATES {
        let offset = draw(reach);
        let pose: [f64; 6] = core::array::from_fn(|k| home[k] + offset[k]);
        let state = State {
            pose: Pose::from_array(pose),
            twist: Twist::from_array(draw(&[1.0; 6])),
            accel: Acceleration::from_array(draw(&[5.0; 6])),
        };
        if let Ok(y) = regressor(&state) {
            rows.extend(y);
            if rows.len() == 6 * GROUPING_STATES * width {
                break;
            }
        }
    }
    DMatrix::from_row_slice(rows.len() / width, width, &rows)
}

/// `y` if every entry is finite.
pub(crate) fn finite_rows<const W: usize>(
    output: &'static str,
    y: [[f64; W]; 6],
) -> Result<[[f64; W]; 6], Error> {
    match y.iter().flatten().all(|v| v.is_finite()) {
        true => Ok(y),
        false => Err(Error::NonFiniteResult { output }),
    }
}
