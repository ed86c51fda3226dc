//! The robot to calibrate: a legged mechanism, its fitted parameters
//! ([`c5_robot::calibration`]) and its generated residual kernel behind one signature.

use super::CalibrationError;
use crate::platform::{self, Mechanism};
use crate::{Description, Error, Model};
use alloc::boxed::Box;
use alloc::vec::Vec;
use c5_generated::f64::{delta, gough_stewart, rus_hexapod};
use c5_robot::calibration::Fitted;

/// The residuals of one measurement and their Jacobians, row-major.
#[derive(Clone, Debug, Default)]
pub(super) struct Residuals {
    /// `q(X; θ) - q̂`, one per actuator.
    pub residual: Vec<f64>,
    /// `∂q_i/∂θ_i`: actuators × fitted parameters per leg.
    pub geometry: Vec<f64>,
    /// `∂q/∂X`: actuators × the pose's coordinates.
    pub pose: Vec<f64>,
}

/// A mechanism's generated `calibration_residuals` on slices: the geometry (the kernel
/// parameters' leading entries), the pose and the readings, all of checked lengths.
type Kernel = fn(&[f64], &[f64], &[f64]) -> Residuals;

fn flat<const R: usize, const C: usize>(m: [[f64; C]; R]) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

/// A generated `calibration_residuals` of `N` actuators, `F` fitted parameters per leg, `D`
/// pose coordinates and `G` geometry entries.
type Generated<const N: usize, const F: usize, const D: usize, const G: usize> =
    fn(&[f64; D], &[f64; N], &[f64; G]) -> ([f64; N], [[f64; F]; N], [[f64; D]; N]);

/// Calls a [`Generated`] kernel on slices.
fn call<const N: usize, const F: usize, const D: usize, const G: usize>(
    kernel: Generated<N, F, D, G>,
    geometry: &[f64],
    pose: &[f64],
    q: &[f64],
) -> Residuals {
    let (mut g, mut x, mut r) = ([0.0; G], [0.0; D], [0.0; N]);
    g.copy_from_slice(&geometry[..G]);
    x.copy_from_slice(pose);
    r.copy_from_slice(q);
    let (residual, geometry, pose) = kernel(&x, &r, &g);
    Residuals {
        residual: residual.to_vec(),
        geometry: flat(geometry),
        pose: flat(pose),
    }
}

/// The robot whose geometry [`super::calibrate`] fits, with what it needs of its mechanism.
pub struct Nominal {
    mechanism: Box<dyn Mechanism>,
    fitted: &'static [Fitted],
    kernel: Kernel,
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
        let kernel: Kernel = match description {
            Description::GoughStewart(_) => {
                |g, x, q| call(gough_stewart::calibration_residuals, g, x, q)
            }
            Description::RusHexapod(_) => {
                |g, x, q| call(rus_hexapod::calibration_residuals, g, x, q)
            }
            Description::Delta(_) => |g, x, q| call(delta::calibration_residuals, g, x, q),
            Description::C5(_) => {
                return Err(CalibrationError::Robot(Error::Unsupported {
                    what: "kinematic calibration",
                    mechanism: description.mechanism(),
                    why: "calibration fits the joint centres, lengths and encoder offsets of a \
                          mechanism's legs; the C5's legs are fixed to its platform",
                }))
            }
        };
        let fitted = description.fitted().unwrap_or(&[]);
        let mechanism =
            platform::load(description, Model::Consistent).map_err(CalibrationError::Robot)?;
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
        if let Some(spatial) = self.mechanism.spatial() {
            spatial.check_limits(&crate::Pose::from_array(platform::array("pose", pose)?))?;
        }
        let n = self.actuators();
        let mut jinv = alloc::vec![0.0; n * n];
        self.mechanism.inverse_jacobian(pose, &mut jinv)?;
        let mut q = alloc::vec![0.0; n];
        self.mechanism.actuator_positions(pose, &mut q)?;
        Ok(q)
    }
}
