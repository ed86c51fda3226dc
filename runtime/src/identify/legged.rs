//! The legged mechanisms' regressors and base parameters (the Gough-Stewart platform, the
//! rotary hexapod, the Delta), written once and instantiated for each over its generated
//! kernels and in its platform's coordinates.
//!
//! Their base regressors' columns are those the generator found for the checked-in example of
//! each; which standard parameters fold into each, and with what coefficients, depends on the
//! geometry (a rod's mass joins the platform's at its ball joint `p_i`), so `base_parameters`
//! finds them for the robot at hand from its own regressor.

use crate::{Error, State};
use alloc::vec::Vec;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How many seeded states the groupings are found from (six equations each).
const GROUPING_STATES: usize = 40;

/// The identification methods of a legged mechanism: `$robot` with its generated kernels
/// `$kernels` (`regressor`, `base_regressor`, their parameter names and groupings) on `$n`
/// actuators, its state type `$state` with `$motion` giving its
/// coordinates checked finite, `$home`, the coordinates it rests at, and `$reach`, how far from
/// there (rad, m) the seeded states of the groupings are drawn.
macro_rules! legged_identification {
    (
        $robot:ty, $kernels:ident, $n:literal,
        $state:ty, $motion:path, $home:expr, $reach:expr
    ) => {
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
                state: &$state,
            ) -> Result<
                [[f64; c5_generated::f64::$kernels::STANDARD_PARAMETERS.len()]; $n],
                crate::Error,
            > {
                self.regressor_at(&$motion(state)?)
            }

            /// `Y` at the platform's coordinates `[pose, twist, acceleration]`, checked finite.
            fn regressor_at(
                &self,
                [x, v, a]: &[[f64; $n]; 3],
            ) -> Result<
                [[f64; c5_generated::f64::$kernels::STANDARD_PARAMETERS.len()]; $n],
                crate::Error,
            > {
                let (y, guard) = c5_generated::f64::$kernels::regressor(
                    x,
                    v,
                    a,
                    &self.identification_geometry(),
                );
                crate::singularity::check(&guard, &c5_generated::f64::$kernels::SINGULARITY_TERMS)?;
                crate::identify::legged::finite_rows("regressor", y)
            }

            /// `Y_b` at `state` into `out`, row-major (`n × n_b` for `n` actuators):
            /// `Γ = Y_b β` with friction.
            ///
            /// # Errors
            /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `n n_b`
            /// long.
            pub fn base_regressor_into(
                &self,
                state: &$state,
                out: &mut [f64],
            ) -> Result<(), crate::Error> {
                const WIDTH: usize = c5_generated::f64::$kernels::BASE_PARAMETERS.len();
                if out.len() != $n * WIDTH {
                    return Err(crate::Error::WrongLength {
                        input: "out",
                        expected: $n * WIDTH,
                        got: out.len(),
                    });
                }
                let [x, v, a] = $motion(state)?;
                let (y, guard) = c5_generated::f64::$kernels::base_regressor(
                    &x,
                    &v,
                    &a,
                    &self.identification_geometry(),
                );
                crate::singularity::check(&guard, &c5_generated::f64::$kernels::SINGULARITY_TERMS)?;
                out.copy_from_slice(
                    crate::identify::legged::finite_rows("base regressor", y)?.as_flattened(),
                );
                Ok(())
            }

            /// `Y_b` at `state` (`n × n_b`).
            ///
            /// # Errors
            /// Non-finite inputs, a singular pose or a non-finite result.
            pub fn base_regressor(
                &self,
                state: &$state,
            ) -> Result<nalgebra::DMatrix<f64>, crate::Error> {
                const WIDTH: usize = c5_generated::f64::$kernels::BASE_PARAMETERS.len();
                let mut rows = alloc::vec![0.0; $n * WIDTH];
                self.base_regressor_into(state, &mut rows)?;
                Ok(nalgebra::DMatrix::from_row_slice($n, WIDTH, &rows))
            }

            /// The standard parameters `π` of this robot with the actuators' `friction`.
            pub fn standard_parameters(
                &self,
                friction: &[crate::identify::Friction; $n],
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
                    &$home(self),
                    &$reach,
                    kernels::STANDARD_PARAMETERS.len(),
                    |motion| self.regressor_at(motion).map(|y| y.concat()),
                );
                crate::identify::BaseParameters::from_regressor(
                    crate::platform::Mechanism::mechanism(self),
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
    6,
    State,
    crate::C5::checked_motion,
    |robot: &crate::GoughStewart| robot.home().to_array(),
    [0.2, 0.2, 0.2, 0.03, 0.03, 0.03]
);
legged_identification!(
    crate::RusHexapod,
    rus_hexapod,
    6,
    State,
    crate::C5::checked_motion,
    |robot: &crate::RusHexapod| robot.home().to_array(),
    [0.1, 0.1, 0.1, 0.02, 0.02, 0.02]
);
legged_identification!(
    crate::Delta,
    delta,
    3,
    crate::delta::Translation,
    crate::delta::checked_motion,
    crate::Delta::home,
    [0.05, 0.05, 0.05]
);

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
pub(crate) fn finite_rows<const W: usize, const N: usize>(
    output: &'static str,
    y: [[f64; W]; N],
) -> Result<[[f64; W]; N], Error> {
    match y.iter().flatten().all(|v| v.is_finite()) {
        true => Ok(y),
        false => Err(Error::NonFiniteResult { output }),
    }
}
