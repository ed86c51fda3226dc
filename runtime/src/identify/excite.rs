//! Exciting trajectories: a finite Fourier series in every pose coordinate, chosen to keep the
//! condition number of the stacked base regressor low, inside a box of the workspace, within
//! the robot's limits (strokes, plates, tilt, joint cones, speeds, forces) and away from its
//! singular poses (eq 16's for the C5), about the robot's home pose, for any mechanism.

use super::Identifier;
use crate::platform::Mechanism;
use crate::trajectory::Fourier;
use crate::{Error, State};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Where an exciting trajectory may go, and how fast.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Envelope {
    /// Largest `|α|`, `|β|`, `|γ|` from home (rad).
    pub angle: f64,
    /// Largest `|xc|`, `|yc|`, `|zc|` from home (m).
    pub center: f64,
    /// Largest `|ω|` component (rad/s) and `|v_C|` component (m/s).
    pub omega: f64,
    pub velocity: f64,
    /// Largest `|ω̇|` component (rad/s²) and `|a_C|` component (m/s²).
    pub omega_dot: f64,
    pub acceleration: f64,
    /// Smallest [`Mechanism::singularity_clearance`] as a fraction of the home pose's
    /// (for the C5, whose home clearance is 1, its smallest `|r11|`, `|r22|`, `|r33|` of eq
    /// 16): the distance kept from singular poses.
    pub divisor: f64,
}

impl Default for Envelope {
    /// The ranges of Section 9 (orientation up to 20°, centre within 5 cm) with the rates of a
    /// brisk test motion.
    fn default() -> Self {
        Envelope {
            angle: 20f64.to_radians(),
            center: 0.05,
            omega: 1.0,
            velocity: 0.2,
            omega_dot: 4.0,
            acceleration: 2.0,
            divisor: 0.5,
        }
    }
}

/// How the search runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Search {
    /// The period of the series (s).
    pub period: f64,
    /// Harmonics per coordinate.
    pub harmonics: usize,
    /// Samples per period the condition number is computed on.
    pub samples: usize,
    /// Candidate trajectories tried (half at random, half refining the best).
    pub candidates: usize,
    pub seed: u64,
}

impl Default for Search {
    fn default() -> Self {
        Search {
            period: 10.0,
            harmonics: 10,
            samples: 500,
            candidates: 400,
            seed: 1,
        }
    }
}

/// An exciting trajectory and its condition number.
#[derive(Clone, Debug, PartialEq)]
pub struct Excitation {
    pub trajectory: Fourier,
    /// Of the observation matrix over `Search::samples` samples of one period.
    pub condition_number: f64,
}

/// The sample times of one period.
fn times(search: &Search) -> impl Iterator<Item = f64> + '_ {
    (0..search.samples).map(move |k| search.period * k as f64 / search.samples as f64)
}

/// The condition number of the base regressor stacked over `states` (infinite if a state is
/// singular or a base parameter is not excited).
///
/// # Errors
/// A state the robot refuses (non-finite or singular).
pub fn condition_number(
    robot: &dyn Mechanism,
    states: impl IntoIterator<Item = State>,
) -> Result<f64, Error> {
    stacked_condition(Identifier::new(robot)?, states)
}

/// The condition number of the states added to an empty `identifier`.
fn stacked_condition(
    mut identifier: Identifier,
    states: impl IntoIterator<Item = State>,
) -> Result<f64, Error> {
    let rest = vec![0.0; identifier.actuators()];
    for state in states {
        identifier.add(&state, &rest)?;
    }
    Ok(identifier.condition_number())
}

/// The largest ratio of a peak of `trajectory` (pose, rates, accelerations) to its limit.
fn peak_ratio(trajectory: &Fourier, envelope: &Envelope, search: &Search) -> f64 {
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // A turning platform's pose starts with its three angles; every pose ends with the centre.
    let angles = if trajectory.freedom().turns() { 3 } else { 0 };
    times(search)
        .map(|t| {
            let [x, _, _] = trajectory.pose_derivatives(t);
            let d: Vec<f64> = x
                .iter()
                .zip(trajectory.offset())
                .map(|(x, o)| x - o)
                .collect();
            let s = trajectory.state(t);
            [
                largest(&d[..angles]) / envelope.angle,
                largest(&d[angles..]) / envelope.center,
                largest(&s.twist.omega) / envelope.omega,
                largest(&s.twist.velocity) / envelope.velocity,
                largest(&s.accel.omega_dot) / envelope.omega_dot,
                largest(&s.accel.linear) / envelope.acceleration,
            ]
            .into_iter()
            .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// `trajectory` scaled down (about its offset) to fit `envelope`'s box and rates; `None` if it
/// then comes closer to a singular pose than `clearance`.
fn fit(
    robot: &dyn Mechanism,
    clearance: f64,
    mut trajectory: Fourier,
    envelope: &Envelope,
    search: &Search,
) -> Option<Fourier> {
    // The rates are nearly linear in the amplitude (the RPY maps and `Ė θ̇` bend them a
    // little), so a few shrinks settle it.
    for _ in 0..8 {
        let ratio = peak_ratio(&trajectory, envelope, search);
        if ratio <= 1.0 {
            let clear = times(search).all(|t| {
                let state = trajectory.state(t);
                robot.coordinates_of(&state).is_ok_and(|[x, ..]| {
                    robot
                        .singularity_clearance(&x)
                        .is_ok_and(|c| c >= clearance)
                })
            });
            return clear.then_some(trajectory);
        }
        let shrink = 0.999 / ratio;
        for h in trajectory
            .sine
            .iter_mut()
            .chain(trajectory.cosine.iter_mut())
        {
            h.iter_mut().for_each(|v| *v *= shrink);
        }
    }
    None
}

/// Whether `state` keeps every limit of the robot: its pose, the actuators' speeds and the
/// forces the motion needs.
fn within_limits(robot: &dyn Mechanism, state: &State) -> bool {
    let Ok([x, v, a]) = robot.coordinates_of(state) else {
        return false;
    };
    let (mut qd, mut gamma) = (vec![0.0; x.len()], vec![0.0; x.len()]);
    robot.check_limits(&x).is_ok()
        && robot.joint_velocities(&x, &v, &mut qd).is_ok()
        && robot.check_speeds(&qd).is_ok()
        && robot.inverse_dynamics(&x, &v, &a, &mut gamma).is_ok()
        && robot.check_forces(&gamma).is_ok()
}

/// The condition number of a candidate; infinite for one that leaves the robot's limits.
fn score(robot: &dyn Mechanism, empty: &Identifier, trajectory: &Fourier, search: &Search) -> f64 {
    if robot.has_limits() && !times(search).all(|t| within_limits(robot, &trajectory.state(t))) {
        return f64::INFINITY;
    }
    stacked_condition(empty.clone(), times(search).map(|t| trajectory.state(t)))
        .unwrap_or(f64::INFINITY)
}

/// The largest amplitude of each of the series' coordinates, the platform's: the envelope's
/// angle for a turning platform's angles, its centre for the centre's coordinates.
fn bounds(robot: &dyn Mechanism, envelope: &Envelope) -> Vec<f64> {
    let freedom = robot.freedom();
    let angles = if freedom.turns() { 3 } else { 0 };
    (0..freedom.dimension())
        .map(|k| {
            if k < angles {
                envelope.angle
            } else {
                envelope.center
            }
        })
        .collect()
}

/// A random series about `home`, harmonic `l` with amplitude falling as `1/l` (smooth motion).
fn random(
    robot: &dyn Mechanism,
    rng: &mut ChaCha8Rng,
    home: &[f64],
    bounds: &[f64],
    search: &Search,
) -> Result<Fourier, Error> {
    let mut harmonic = |l: usize| -> Vec<f64> {
        bounds
            .iter()
            .map(|bound| bound * rng.gen_range(-1.0..1.0) / (l + 1) as f64)
            .collect()
    };
    let sine = (0..search.harmonics).map(&mut harmonic).collect();
    let cosine = (0..search.harmonics).map(&mut harmonic).collect();
    Fourier::new(robot.freedom(), home.to_vec(), search.period, sine, cosine)
}

/// Searches for a series of low condition number within `envelope`: random candidates, then
/// random perturbations of the best with a shrinking step.
///
/// # Errors
/// [`DesignError::EmptySearch`] if `search` asks for no candidates, harmonics or samples, or a
/// period that is not positive; [`DesignError::NothingFits`] if no candidate keeps clear of
/// the singular poses; [`DesignError::Robot`] if the robot has no base regressor.
pub fn design(
    robot: &dyn Mechanism,
    envelope: &Envelope,
    search: &Search,
) -> Result<Excitation, DesignError> {
    if search.candidates == 0
        || search.harmonics == 0
        || search.samples == 0
        || !(search.period > 0.0 && search.period.is_finite())
    {
        return Err(DesignError::EmptySearch);
    }
    let empty = Identifier::new(robot).map_err(DesignError::Robot)?;
    let home = robot.home();
    let clearance = envelope.divisor
        * robot
            .singularity_clearance(&home)
            .map_err(DesignError::Robot)?;
    let bounds = bounds(robot, envelope);
    let mut rng = ChaCha8Rng::seed_from_u64(search.seed);
    let mut best: Option<(Fourier, f64)> = None;
    let mut step = 0.5;
    for k in 0..search.candidates {
        let candidate = match &best {
            Some((b, _)) if k >= search.candidates / 2 => {
                let mut c = b.clone();
                for h in c.sine.iter_mut().chain(c.cosine.iter_mut()) {
                    for (v, bound) in h.iter_mut().zip(&bounds) {
                        *v += step * bound * rng.gen_range(-1.0..1.0) / search.harmonics as f64;
                    }
                }
                step = (step * 0.995).max(0.02);
                c
            }
            _ => random(robot, &mut rng, &home, &bounds, search).map_err(DesignError::Robot)?,
        };
        let Some(candidate) = fit(robot, clearance, candidate, envelope, search) else {
            continue;
        };
        let cond = score(robot, &empty, &candidate, search);
        if cond.is_finite() && best.as_ref().is_none_or(|(_, b)| cond < *b) {
            best = Some((candidate, cond));
        }
    }
    best.map(|(trajectory, condition_number)| Excitation {
        trajectory,
        condition_number,
    })
    .ok_or(DesignError::NothingFits)
}

/// Why no exciting trajectory was found.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignError {
    /// No candidates, harmonics or samples, or a period that is not positive and finite.
    EmptySearch,
    /// Every candidate came closer to a singular pose than the envelope allows, or left the
    /// robot's limits.
    NothingFits,
    /// The robot has no base regressor to excite.
    Robot(Error),
}

impl core::fmt::Display for DesignError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DesignError::EmptySearch => f.write_str(
                "an excitation search needs candidates, harmonics, samples and a positive period",
            ),
            DesignError::NothingFits => f.write_str(
                "no candidate trajectory keeps clear of the singular poses and within the \
                 robot's limits (and its base regressor of full rank): shrink the envelope's box \
                 or widen the limits",
            ),
            DesignError::Robot(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for DesignError {}
