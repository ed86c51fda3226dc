//! Kinematic calibration of a legged mechanism (the Gough-Stewart platform, the rotary
//! hexapod, the Delta): its true geometry from measured poses.
//!
//! A built robot is never its drawing: each leg's joint centres, lengths and encoder offset sit
//! off their nominal values by millimetres. Given poses measured by an external instrument
//! (laser tracker, CMM, camera) beside the encoders' readings, [`calibrate`] fits them by
//! weighted least squares on the legs' residuals `r_i = q_i(X; θ) - q̂_i`, with the exact
//! Jacobians of the mechanism's generated kernel `calibration_residuals`. What is fitted per
//! leg is the mechanism's ([`c5_robot::calibration`]): a Gough-Stewart leg's `A_i`, `p_i`,
//! `o_i` (7); a rotary hexapod leg's `A_i`, its motor axis's azimuth and elevation, `p_i`,
//! crank and rod lengths `c_i`, `L_i` and `o_i` (11); a Delta arm's the same but `p_i` (8: a
//! platform that only translates sees `p_i - A_i` alone).
//!
//! The measurement model: the readings carry the encoders' noise, the measured pose the
//! instrument's (per position component and per RPY angle, [`Noise`]); each residual's
//! variance is `σ_q² + Σ_k (∂q_i/∂X_k)² σ_k²`, so a pose's noise counts as much as it moves
//! the leg. Leg `i`'s residuals depend on its own parameters only, so the fit is one
//! independent problem per leg; the parameters are scaled ([`Options::scale`]) so that the
//! observability (the singular values of the whitened, scaled Jacobian) reads in one unit for
//! lengths (m) and angles (rad): a millimetre and a milliradian alike.
//!
//! A combination of a leg's parameters that the data cannot separate (its standard deviation
//! would exceed [`Options::observable`]) is not smeared over its members: one of them is fixed
//! at its nominal value, and the [`Report`] names the combination and the parameter fixed. With
//! [`Options::strict`], such data are refused instead.

mod fit;
mod nominal;
mod observability;
mod plan;

pub(crate) use nominal::residuals_of;
pub use nominal::{Nominal, ResidualKernel, Residuals};
pub use plan::{plan, simulate};

use crate::{Description, Error};
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

/// The fewest measured poses [`calibrate`] accepts for a mechanism fitting `fitted`
/// parameters per leg: a leg's unknowns and one degree of freedom for the noise's estimate.
pub fn min_measurements(fitted: usize) -> usize {
    fitted + 1
}

/// One measured pose and the encoder readings taken with it.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// The platform pose the instrument measured, in the mechanism's coordinates:
    /// `[α β γ xc yc zc]` (rad, m), a Delta's `[xc yc zc]`.
    pub pose: Vec<f64>,
    /// The encoders' readings `q̂_i`, leg order (m, or rad for motors' angles).
    pub q: Vec<f64>,
}

/// The measurements' noise, standard deviations: what weighs each residual.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Each component of the measured platform position (m).
    pub position: f64,
    /// Each measured RPY angle (rad).
    pub angle: f64,
    /// Each encoder reading (m, or rad for motors' angles).
    pub encoder: f64,
}

impl Default for Noise {
    /// A laser tracker's 10 µm and 20 µrad, and encoders of 1 µm (1 µrad for a motor's).
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
    /// The unit in which every parameter is scaled, about the size of the geometric errors
    /// expected: the singular values and the observability bound read in it, in metres for
    /// lengths and radians for angles. Default 1e-3 (1 mm, 1 mrad).
    pub scale: f64,
    /// The largest standard deviation (m) a fitted combination of parameters may have; a
    /// combination the data know worse is fixed at its nominal value. Default 5 mm (five times
    /// the errors one calibrates for: such an estimate would say nothing).
    pub observable: f64,
    /// Refuse data that leave a combination unobservable, instead of fixing it.
    pub strict: bool,
    /// The largest residual (m) of a length actuator the nominal geometry may leave at a
    /// measurement: beyond it the readings do not belong to the pose (columns swapped, wrong
    /// units). Default 20 mm.
    pub gross: f64,
    /// The same for a motor's angle (rad): a millimetre of a crank's geometry turns it by
    /// tens of milliradians. Default 0.35 rad (20°).
    pub gross_angle: f64,
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
            gross_angle: 0.35,
            iterations: 50,
        }
    }
}

/// One fitted parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// `A1.x`, `p3.z`, `L2`, `o6`: the base joint's or motor's centre `A_i` (the file's
    /// `base`), the platform joint centre `p_i` (`platform`), the crank's and the rod's
    /// lengths `c_i` and `L_i`, the encoder's offset `o_i` (`encoder_offset`).
    pub name: String,
    /// The leg, from 1.
    pub leg: usize,
    /// Whether it is an angle (rad); else a length (m).
    pub angle: bool,
    /// The nominal value.
    pub nominal: f64,
    /// The estimate; the nominal value when fixed.
    pub estimate: f64,
    /// The estimate's standard deviation; `None` when fixed.
    pub std_dev: Option<f64>,
}

/// A combination of one leg's parameters that the data cannot separate.
#[derive(Clone, Debug, PartialEq)]
pub struct Unobservable {
    /// The leg, from 1.
    pub leg: usize,
    /// The combination: parameter names with their weights (the largest 1), on the scaled
    /// parameters; moving the parameters along it barely changes any residual.
    pub combination: Vec<(String, f64)>,
    /// How well the data know it: its standard deviation (in the unit of its largest member).
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
            " (σ {:.3e}; {} fixed at nominal)",
            self.std_dev, self.fixed
        )
    }
}

/// The residuals of one leg over the measurements (m, or rad for motors' angles).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    pub rms: f64,
    pub max: f64,
}

/// What [`calibrate`] found.
#[derive(Clone, Debug)]
pub struct Report {
    /// The calibrated description: the nominal one with each leg's fitted parameters.
    pub robot: Description,
    /// The fitted parameters, leg by leg in the mechanism's order ([`Description::fitted`]).
    pub parameters: Vec<Parameter>,
    /// Whether the actuators are motors' angles: the residuals and the encoder's noise are
    /// then in rad, else in m.
    pub angular: bool,
    /// The residuals `q(X) - q̂` of the nominal geometry at each measurement, one per leg.
    pub residuals_before: Vec<Vec<f64>>,
    /// The residuals of the calibrated geometry.
    pub residuals_after: Vec<Vec<f64>>,
    /// Per leg, the singular values of the whitened Jacobian of its parameters scaled by
    /// [`Options::scale`], largest first: `1/σ` is the standard deviation (in scales) of the
    /// best and worst known combinations. All of them, fixed ones included.
    pub singular_values: Vec<Vec<f64>>,
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
    pub fn before(&self) -> Vec<Spread> {
        spread(&self.residuals_before)
    }

    /// Per leg, the residuals of the calibrated geometry.
    pub fn after(&self) -> Vec<Spread> {
        spread(&self.residuals_after)
    }

    /// How many legs.
    pub fn legs(&self) -> usize {
        self.singular_values.len()
    }
}

fn spread(residuals: &[Vec<f64>]) -> Vec<Spread> {
    let legs = residuals.first().map_or(0, Vec::len);
    (0..legs)
        .map(|i| {
            let n = residuals.len().max(1) as f64;
            let squares: f64 = residuals.iter().map(|r| r[i] * r[i]).sum();
            Spread {
                rms: crate::math::sqrt(squares / n),
                max: residuals.iter().map(|r| r[i].abs()).fold(0.0, f64::max),
            }
        })
        .collect()
}

/// Why [`calibrate`] refused; rows count the measurements from 1.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CalibrationError {
    /// Fewer measurements than [`min_measurements`].
    TooFewMeasurements { got: usize, least: usize },
    /// A measurement holds NaN or an infinity.
    NonFinite { row: usize },
    /// A measurement's pose or readings are not as many as the mechanism's coordinates and
    /// actuators.
    WrongWidth {
        row: usize,
        what: &'static str,
        expected: usize,
        got: usize,
    },
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
            CalibrationError::WrongWidth {
                row,
                what,
                expected,
                got,
            } => write!(
                f,
                "measurement {row}: {got} values of the {what}, and the robot has {expected}"
            ),
            CalibrationError::Unreachable { row, why } => {
                write!(
                    f,
                    "measurement {row}: the robot cannot reach its pose: {why}"
                )
            }
            CalibrationError::Mismatch { row, leg, residual } => write!(
                f,
                "measurement {row}: reading {leg} is {:.3}e-3 from what the nominal geometry \
                 predicts at the pose (mm, or mrad for a motor's angle: columns swapped, or not \
                 in metres and radians?)",
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
/// carried by the leg's row `∂q_i/∂X` of the pose Jacobian (angles, then positions; positions
/// alone for a platform that only translates).
pub(crate) fn residual_sigma(pose_row: &[f64], noise: &Noise) -> f64 {
    let turns = pose_row.len().saturating_sub(3);
    let angles: f64 = pose_row[..turns].iter().map(|d| d * d).sum();
    let positions: f64 = pose_row[turns..].iter().map(|d| d * d).sum();
    crate::math::sqrt(
        noise.encoder * noise.encoder
            + angles * noise.angle * noise.angle
            + positions * noise.position * noise.position,
    )
}

/// Fits the geometry of `nominal` (each leg's [`Nominal::fitted`] parameters) to `data` by
/// Levenberg-Marquardt from the nominal values.
///
/// # Errors
/// [`CalibrationError`]: too few measurements, a non-finite value or a row of the wrong
/// width, a pose the nominal robot cannot reach, readings that do not belong to their pose,
/// bad options, or (with [`Options::strict`]) unobservable combinations. Nothing is returned
/// but the error.
pub fn calibrate(
    nominal: &Nominal,
    data: &[Measurement],
    options: &Options,
) -> Result<Report, CalibrationError> {
    check_options(options)?;
    check_data(nominal, data, options)?;
    fit::run(nominal, data, options)
}

fn check_options(options: &Options) -> Result<(), CalibrationError> {
    let noise = &options.noise;
    let positive = |x: f64| x > 0.0 && x.is_finite();
    if !(positive(noise.position) && positive(noise.angle) && positive(noise.encoder)) {
        return Err(CalibrationError::Options {
            rule: "every noise level must be positive and finite",
        });
    }
    let bounds = [
        options.scale,
        options.observable,
        options.gross,
        options.gross_angle,
    ];
    if !bounds.into_iter().all(positive) {
        return Err(CalibrationError::Options {
            rule: "the scale, the observability bound and the gross-error bound must be \
                   positive and finite",
        });
    }
    Ok(())
}

fn check_data(
    nominal: &Nominal,
    data: &[Measurement],
    options: &Options,
) -> Result<(), CalibrationError> {
    let least = min_measurements(nominal.fitted().len());
    if data.len() < least {
        return Err(CalibrationError::TooFewMeasurements {
            got: data.len(),
            least,
        });
    }
    let n = nominal.actuators();
    let gross = if nominal.angular() {
        options.gross_angle
    } else {
        options.gross
    };
    for (k, m) in data.iter().enumerate() {
        let row = k + 1;
        for (what, values) in [("pose", &m.pose), ("readings", &m.q)] {
            if values.len() != n {
                return Err(CalibrationError::WrongWidth {
                    row,
                    what,
                    expected: n,
                    got: values.len(),
                });
            }
        }
        if !(m.pose.iter().chain(&m.q)).all(|x| x.is_finite()) {
            return Err(CalibrationError::NonFinite { row });
        }
        let predicted = nominal
            .reach(&m.pose)
            .map_err(|why| CalibrationError::Unreachable { row, why })?;
        for (leg, (q, reading)) in predicted.iter().zip(&m.q).enumerate() {
            let residual = q - reading;
            if residual.abs() > gross {
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
