//! The robot to calibrate: a legged mechanism, its fitted parameters
//! ([`c5_robot::calibration`]) and its generated residual kernel behind one signature.

use super::CalibrationError;
use crate::platform::{self, Mechanism};
use crate::{Description, Error, Model};
use alloc::boxed::Box;
use alloc::vec::Vec;
use c5_generated::legged::Calibrated;
use c5_robot::calibration::Fitted;

/// The residuals of one measurement and their Jacobians, row-major.
#[derive(Clone, Debug, Default)]
pub struct Residuals {
    /// `q(X; θ) - q̂`, one per actuator.
    pub residual: Vec<f64>,
    /// `∂q_i/∂θ_i`: actuators × fitted parameters per leg.
    pub geometry: Vec<f64>,
    /// `∂q/∂X`: actuators × the pose's coordinates.
    pub pose: Vec<f64>,
}

/// A mechanism's generated `calibration_residuals` on slices: the kernel parameters (whose
/// geometry it reads), the pose and the readings, their lengths checked by the caller.
pub type ResidualKernel = fn(&[f64], &[f64], &[f64]) -> Residuals;

/// The kernel set `K`'s `calibration_residuals` on slices, a [`ResidualKernel`]. A slice of
/// another length than the mechanism's (a bug of the caller's) gives NaN, not a panic.
pub(crate) fn residuals_of<K: Calibrated<N>, const N: usize>(
    parameters: &[f64],
    pose: &[f64],
    q: &[f64],
) -> Residuals {
    let padded = |v: &[f64]| -> [f64; N] {
        core::array::from_fn(|k| match v.len() == N {
            true => v[k],
            false => f64::NAN,
        })
    };
    let (x, q) = (padded(pose), padded(q));
    let width = K::FittedRow::default().as_ref().len();
    let Some(p) = K::parameters(parameters) else {
        return Residuals {
            residual: alloc::vec![f64::NAN; N],
            geometry: alloc::vec![f64::NAN; N * width],
            pose: alloc::vec![f64::NAN; N * N],
        };
    };
    let (residual, geometry, pose) = K::calibration_residuals(&x, &q, &p);
    Residuals {
        residual: residual.to_vec(),
        geometry: geometry
            .iter()
            .flat_map(|row| row.as_ref().iter().copied())
            .collect(),
        pose: pose.as_flattened().to_vec(),
    }
}

/// The robot whose geometry [`super::calibrate`] fits, with what it needs of its mechanism.
pub struct Nominal {
    mechanism: Box<dyn Mechanism>,
    fitted: &'static [Fitted],
    kernel: ResidualKernel,
}

impl core::fmt::Debug for Nominal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Nominal")
            .field("mechanism", &self.mechanism)
            .finish_non_exhaustive()
    }
}

impl Nominal {
    /// The robot of `description`, checked as every command checks it.
    ///
    /// # Errors
    /// [`CalibrationError::Robot`] for a description that breaks a rule of its mechanism, or
    /// of a mechanism without legs' geometry to fit (the C5).
    pub fn new(description: Description) -> Result<Self, CalibrationError> {
        let fitted = description.fitted().unwrap_or(&[]);
        let mechanism =
            platform::load(description, Model::Consistent).map_err(CalibrationError::Robot)?;
        let kernel = mechanism.calibration().ok_or_else(|| {
            CalibrationError::Robot(Error::Unsupported {
                what: "kinematic calibration",
                mechanism: mechanism.mechanism(),
                why: "calibration fits the joint centres, lengths and encoder offsets of a \
                      mechanism's legs, and this mechanism has no calibration kernel generated",
            })
        })?;
        Ok(Nominal {
            mechanism,
            fitted,
            kernel,
        })
    }

    /// The robot as a mechanism.
    pub fn mechanism(&self) -> &dyn Mechanism {
        self.mechanism.as_ref()
    }

    /// Its description.
    pub fn description(&self) -> Description {
        self.mechanism.description()
    }

    /// The parameters fitted per leg.
    pub fn fitted(&self) -> &'static [Fitted] {
        self.fitted
    }

    /// How many actuators (legs), and how many coordinates a pose has.
    pub fn actuators(&self) -> usize {
        self.mechanism.freedom().dimension()
    }

    /// Whether the actuators are motors' angles (rad); else lengths (m). The encoder's offset
    /// has the actuator's unit.
    pub fn angular(&self) -> bool {
        self.fitted.iter().any(|f| f.symbol == "o" && f.angle)
    }

    /// The residuals at `pose` and readings `q` of the geometry in `parameters` (the kernel
    /// parameters of a description of this mechanism).
    pub(super) fn residuals(&self, parameters: &[f64], pose: &[f64], q: &[f64]) -> Residuals {
        (self.kernel)(parameters, pose, q)
    }

    /// Refuses a pose the robot cannot reach: beyond its limits, singular, or out of its legs'
    /// reach; else its actuators' values there.
    pub(super) fn reach(&self, pose: &[f64]) -> Result<Vec<f64>, Error> {
        self.mechanism.check_limits(pose)?;
        let n = self.actuators();
        let mut jinv = alloc::vec![0.0; n * n];
        self.mechanism.inverse_jacobian(pose, &mut jinv)?;
        let mut q = alloc::vec![0.0; n];
        self.mechanism.actuator_positions(pose, &mut q)?;
        Ok(q)
    }
}
