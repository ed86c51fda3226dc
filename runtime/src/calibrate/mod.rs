//! Kinematic calibration of a Gough-Stewart platform: its true geometry from measured poses.
//!
//! A built hexapod is never its drawing: each leg's base joint centre `A_i`, platform joint
//! centre `p_i` and encoder offset `o_i` (42 parameters) sit off their nominal values by
//! millimetres. Given poses measured by an external instrument (laser tracker, CMM, camera)
//! beside the encoders' readings, [`calibrate`] fits them by weighted least squares on the
//! legs' residuals `r_i = ρ_i(X; θ) - q_i`, `ρ_i = |C + R p_i - A_i| + o_i`, with the exact
//! Jacobians of the generated kernel `calibration_residuals`.
//!
//! The measurement model: the readings carry the encoders' noise, the measured pose the
//! instrument's (per position component and per RPY angle, [`Noise`]); each residual's
//! variance is `σ_q² + Σ_k (∂ρ_i/∂X_k)² σ_k²`, so a pose's noise counts as much as it moves
//! the leg. Leg `i`'s residuals depend on its own seven parameters only, so the fit is six
//! independent problems of seven unknowns; the parameters are scaled ([`Options::scale`]) so
//! that the observability (the singular values of the whitened, scaled Jacobian) reads in
//! one unit for positions and offsets.
//!
//! A combination of a leg's parameters that the data cannot separate (its standard deviation
//! would exceed [`Options::observable`]) is not smeared over its members: one of them is fixed
//! at its nominal value, and the [`Report`] names the combination and the parameter fixed. With
//! [`Options::strict`], such data are refused instead.

mod fit;
mod observability;
mod plan;

pub use plan::{plan, simulate};

use crate::gough_stewart::{Description, GoughStewart};
use crate::{Error, Pose};
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

/// The geometric parameters fitted per leg: `A_i` (base frame), `p_i` (platform frame), `o_i`.
pub const PER_LEG: usize = 7;

/// The fewest measured poses [`calibrate`] accepts: a leg's seven unknowns and one degree of
/// freedom for the noise's estimate.
pub const MIN_MEASUREMENTS: usize = PER_LEG + 1;

/// One measured pose and the six encoder readings taken with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    /// The platform pose the instrument measured, `[α β γ xc yc zc]` (rad, m).
    pub pose: Pose,
    /// The encoders' readings `q_i` (m), leg order.
    pub q: [f64; 6],
}

/// The measurements' noise, standard deviations: what weighs each residual.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Each component of the measured platform position (m).
    pub position: f64,
    /// Each measured RPY angle (rad).
    pub angle: f64,
    /// Each encoder reading (m).
    pub encoder: f64,
}

impl Default for Noise {
    /// A laser tracker's 10 µm and 20 µrad, and 1 µm encoders.
    fn default() -> Self {
        Noise {
            position: 10e-6,
            angle: 20e-6,
            encoder: 1e-6,
        }
    }
}

/// How [`calibrate`] fits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// The measurements' noise.
    pub noise: Noise,
    /// The unit in which every parameter (positions and offsets, all in m) is scaled, about
    /// the size of the geometric errors expected: the singular values and the observability
    /// bound read in it. Default 1 mm.
    pub scale: f64,
    /// The largest standard deviation (m) a fitted combination of parameters may have; a
    /// combination the data know worse is fixed at its nominal value. Default 5 mm (five times
    /// the errors one calibrates for: such an estimate would say nothing).
    pub observable: f64,
    /// Refuse data that leave a combination unobservable, instead of fixing it.
    pub strict: bool,
    /// The largest residual (m) the nominal geometry may leave at a measurement: beyond it the
    /// readings do not belong to the pose (columns swapped, wrong units). Default 20 mm.
    pub gross: f64,
    /// The most Levenberg-Marquardt iterations.
    pub iterations: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            noise: Noise::default(),
            scale: 1e-3,
            observable: 5e-3,
            strict: false,
            gross: 20e-3,
            iterations: 50,
        }
    }
}

/// One fitted parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// `A1.x`, `p3.z`, `o6`: the base joint centre `A_i` (the file's `base`), the platform
    /// joint centre `p_i` (`platform`), the encoder's offset `o_i` (`encoder_offset`).
    pub name: String,
    /// The leg, 1..6.
    pub leg: usize,
    /// The nominal value (m).
    pub nominal: f64,
    /// The estimate (m); the nominal value when fixed.
    pub estimate: f64,
    /// The estimate's standard deviation (m); `None` when fixed.
    pub std_dev: Option<f64>,
}

/// A combination of one leg's parameters that the data cannot separate.
#[derive(Clone, Debug, PartialEq)]
pub struct Unobservable {
    /// The leg, 1..6.
    pub leg: usize,
    /// The combination: parameter names with their weights (the largest 1), on the scaled
    /// parameters; moving the parameters along it barely changes any residual.
    pub combination: Vec<(String, f64)>,
    /// How well the data know it: its standard deviation (m).
    pub std_dev: f64,
    /// The parameter fixed at its nominal value in its stead.
    pub fixed: String,
}

impl fmt::Display for Unobservable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "leg {}: ", self.leg)?;
        for (k, (name, weight)) in self.combination.iter().enumerate() {
            let sign = if *weight < 0.0 { "-" } else { "+" };
            match k {
                0 if *weight < 0.0 => write!(f, "-")?,
                0 => {}
                _ => write!(f, " {sign} ")?,
            }
            write!(f, "{:.3} {name}", weight.abs())?;
        }
        write!(
            f,
            " (σ {:.3e} m; {} fixed at nominal)",
            self.std_dev, self.fixed
        )
    }
}

/// The residuals of one leg over the measurements (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    pub rms: f64,
    pub max: f64,
}

/// What [`calibrate`] found.
#[derive(Clone, Debug)]
pub struct Report {
    /// The calibrated description: the nominal one with the fitted `base`, `platform` and
    /// `encoder_offset` of each leg.
    pub robot: Description,
    /// The 42 parameters, leg by leg in the order `A_x A_y A_z p_x p_y p_z o`.
    pub parameters: Vec<Parameter>,
    /// The residuals `ρ_i(X) - q_i` of the nominal geometry at each measurement (m).
    pub residuals_before: Vec<[f64; 6]>,
    /// The residuals of the calibrated geometry (m).
    pub residuals_after: Vec<[f64; 6]>,
    /// Per leg, the singular values of the whitened Jacobian of its parameters scaled by
    /// [`Options::scale`], largest first: `1/σ` is the standard deviation (in scales) of the
    /// best and worst known combinations. All seven, fixed ones included.
    pub singular_values: [[f64; PER_LEG]; 6],
    /// The combinations fixed at their nominal values.
    pub unobservable: Vec<Unobservable>,
    /// The a posteriori variance factor: the weighted residuals' sum of squares per degree of
    /// freedom, about 1 when the stated noise is right. The standard deviations include it.
    pub variance_factor: f64,
    /// The iterations taken.
    pub iterations: usize,
}

impl Report {
    /// Per leg, the residuals of the nominal geometry.
    pub fn before(&self) -> [Spread; 6] {
        spread(&self.residuals_before)
    }

    /// Per leg, the residuals of the calibrated geometry.
    pub fn after(&self) -> [Spread; 6] {
        spread(&self.residuals_after)
    }
}

fn spread(residuals: &[[f64; 6]]) -> [Spread; 6] {
    core::array::from_fn(|i| {
        let n = residuals.len().max(1) as f64;
        let squares: f64 = residuals.iter().map(|r| r[i] * r[i]).sum();
        Spread {
            rms: crate::math::sqrt(squares / n),
            max: residuals.iter().map(|r| r[i].abs()).fold(0.0, f64::max),
        }
    })
}

/// Why [`calibrate`] refused; rows count the measurements from 1.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CalibrationError {
    /// Fewer measurements than [`MIN_MEASUREMENTS`].
    TooFewMeasurements { got: usize, least: usize },
    /// A measurement holds NaN or an infinity.
    NonFinite { row: usize },
    /// A measured pose the nominal robot cannot reach (beyond its limits, or singular).
    Unreachable { row: usize, why: Error },
    /// The readings of a measurement are further than [`Options::gross`] from what the
    /// nominal geometry predicts at its pose: they do not belong to it.
    Mismatch {
        row: usize,
        leg: usize,
        residual: f64,
    },
    /// With [`Options::strict`]: combinations the data cannot separate.
    Unobservable { combinations: Vec<Unobservable> },
    /// An option out of its range.
    Options { rule: &'static str },
    /// The nominal description, or the calibrated one, breaks a rule.
    Robot(Error),
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CalibrationError::TooFewMeasurements { got, least } => write!(
                f,
                "{got} measurements: calibration needs at least {least} (sixty spread over the \
                 workspace is usual; `c5 calibrate --plan` picks them)"
            ),
            CalibrationError::NonFinite { row } => {
                write!(
                    f,
                    "measurement {row} holds a value that is not a finite number"
                )
            }
            CalibrationError::Unreachable { row, why } => {
                write!(
                    f,
                    "measurement {row}: the robot cannot reach its pose: {why}"
                )
            }
            CalibrationError::Mismatch { row, leg, residual } => write!(
                f,
                "measurement {row}: reading {leg} is {:.3} mm from what the nominal geometry \
                 predicts at the pose (columns swapped, or not in metres and radians?)",
                residual * 1e3
            ),
            CalibrationError::Unobservable { combinations } => {
                write!(f, "the measurements cannot separate")?;
                for c in combinations {
                    write!(f, "\n  {c}")?;
                }
                write!(
                    f,
                    "\n(measure more orientations and positions, or accept these parameters at \
                     their nominal values)"
                )
            }
            CalibrationError::Options { rule } => write!(f, "calibration options: {rule}"),
            CalibrationError::Robot(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for CalibrationError {}

/// The standard deviation of a leg's residual: the encoder's noise and the measured pose's,
/// carried by the leg's row `∂ρ_i/∂X` of the pose Jacobian (angles, then positions).
pub(crate) fn residual_sigma(pose_row: &[f64; 6], noise: &Noise) -> f64 {
    let angles: f64 = pose_row[..3].iter().map(|d| d * d).sum();
    let positions: f64 = pose_row[3..].iter().map(|d| d * d).sum();
    crate::math::sqrt(
        noise.encoder * noise.encoder
            + angles * noise.angle * noise.angle
            + positions * noise.position * noise.position,
    )
}

/// The name of parameter `k` (`0..7`) of leg `leg` (`0..6`).
pub fn parameter_name(leg: usize, k: usize) -> String {
    let i = leg + 1;
    match k {
        0..=2 => alloc::format!("A{i}.{}", ["x", "y", "z"][k]),
        3..=5 => alloc::format!("p{i}.{}", ["x", "y", "z"][k - 3]),
        _ => alloc::format!("o{i}"),
    }
}

/// Leg `leg`'s parameters `[A p o]` in `robot`.
fn leg_parameters(robot: &Description, leg: usize) -> [f64; PER_LEG] {
    let l = &robot.legs[leg];
    let [ax, ay, az] = l.base;
    let [px, py, pz] = l.platform;
    [ax, ay, az, px, py, pz, l.encoder_offset]
}

/// `robot` with leg `leg`'s parameters `[A p o]` set to `theta`.
fn with_leg_parameters(robot: &mut Description, leg: usize, theta: &[f64; PER_LEG]) {
    let l = &mut robot.legs[leg];
    l.base = [theta[0], theta[1], theta[2]];
    l.platform = [theta[3], theta[4], theta[5]];
    l.encoder_offset = theta[6];
}

/// Fits the geometry of `nominal` (each leg's `A_i`, `p_i`, `o_i`) to `data` by
/// Levenberg-Marquardt from the nominal values.
///
/// # Errors
/// [`CalibrationError`]: too few measurements, a non-finite value, a pose the nominal robot
/// cannot reach, readings that do not belong to their pose, bad options, or (with
/// [`Options::strict`]) unobservable combinations. Nothing is returned but the error.
pub fn calibrate(
    nominal: &GoughStewart,
    data: &[Measurement],
    options: &Options,
) -> Result<Report, CalibrationError> {
    check_options(options)?;
    check_data(nominal, data, options)?;
    fit::run(nominal.robot(), data, options)
}

fn check_options(options: &Options) -> Result<(), CalibrationError> {
    let noise = &options.noise;
    let positive = |x: f64| x > 0.0 && x.is_finite();
    if !(positive(noise.position) && positive(noise.angle) && positive(noise.encoder)) {
        return Err(CalibrationError::Options {
            rule: "every noise level must be positive and finite",
        });
    }
    if !(positive(options.scale) && positive(options.observable) && positive(options.gross)) {
        return Err(CalibrationError::Options {
            rule: "the scale, the observability bound and the gross-error bound must be \
                   positive and finite",
        });
    }
    Ok(())
}

fn check_data(
    nominal: &GoughStewart,
    data: &[Measurement],
    options: &Options,
) -> Result<(), CalibrationError> {
    if data.len() < MIN_MEASUREMENTS {
        return Err(CalibrationError::TooFewMeasurements {
            got: data.len(),
            least: MIN_MEASUREMENTS,
        });
    }
    for (k, m) in data.iter().enumerate() {
        let row = k + 1;
        if !(m.pose.to_array().iter().chain(&m.q)).all(|x| x.is_finite()) {
            return Err(CalibrationError::NonFinite { row });
        }
        nominal
            .check_limits(&m.pose)
            .and_then(|()| nominal.singularity_terms(&m.pose).map(|_| ()))
            .map_err(|why| CalibrationError::Unreachable { row, why })?;
        let (rho, _) = nominal
            .inverse_kinematics(&m.pose)
            .map_err(|why| CalibrationError::Unreachable { row, why })?;
        for (leg, (rho, q)) in rho.iter().zip(&m.q).enumerate() {
            let residual = rho - q;
            if residual.abs() > options.gross {
                return Err(CalibrationError::Mismatch {
                    row,
                    leg: leg + 1,
                    residual,
                });
            }
        }
    }
    Ok(())
}
