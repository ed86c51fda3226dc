//! The options several commands share, declared once: the robot and its model.

use c5_runtime::trajectory::LinearMove;
use c5_runtime::{Description, Model, Pose};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use std::path::PathBuf;

/// The robot description and the model of the legs' mechanism.
#[derive(Args, Clone, Debug)]
pub struct RobotArgs {
    /// A robot description (TOML) instead of the chapter's robot: its `mechanism` line says
    /// which ("c5", the default, "gough-stewart", "rus-hexapod", "delta"; docs/mechanisms.md).
    #[arg(long)]
    pub robot: Option<PathBuf>,
    /// The model of the legs' mechanism the results follow.
    #[arg(long, default_value = "consistent", value_parser = model_parser())]
    pub model: Model,
}

impl RobotArgs {
    /// The robot of `--robot` (or the chapter's), of any mechanism and freedom; a C5 with the
    /// model of `--model`.
    pub fn load_mechanism(&self) -> crate::Result<Box<dyn c5_runtime::Mechanism>> {
        load_mechanism(self.robot.as_ref(), self.model)
    }
}

/// Parses a model's name, listing the names in `--help`.
pub fn model_parser() -> impl TypedValueParser<Value = Model> {
    PossibleValuesParser::new(Model::ALL.map(Model::name))
        .map(|name| name.parse::<Model>().expect("one of the possible values"))
}

/// The robot of `path` (or the chapter's), of any mechanism and freedom; a C5 with `model`.
pub fn load_mechanism(
    path: Option<&PathBuf>,
    model: Model,
) -> crate::Result<Box<dyn c5_runtime::Mechanism>> {
    Ok(c5_runtime::platform::load(read_description(path)?, model)?)
}

/// The description of the robot file `path`, the chapter's C5 for `None`.
fn read_description(path: Option<&PathBuf>) -> crate::Result<Description> {
    Ok(match path {
        Some(p) => Description::from_toml_file(p)?,
        None => Description::default(),
    })
}

/// The chapter's default trajectory on `robot`: Section 9's move of the platform's centre from
/// its home, at Section 9's orientation where the platform turns. Where the robot cannot take
/// all of that orientation along the move (the rotary hexapod loses its hold on the platform
/// at 20° of yaw), the three angles are scaled down by tenths until every state of the move
/// is served; the scale is returned with the move where it is below 1.
///
/// # Errors
/// A state of the move the robot refuses even level.
pub fn section9_for(robot: &dyn c5_runtime::Mechanism) -> crate::Result<(LinearMove, Option<f64>)> {
    let rest = vec![0.0; robot.freedom().dimension()];
    let home = robot.state_of([&robot.home(), &rest, &rest])?.pose;
    let full = section9_from(home);
    let scales = if robot.freedom().turns() {
        (0..=10).rev().map(|k| k as f64 / 10.0).collect()
    } else {
        vec![0.0]
    };
    let mut refused = None;
    for scale in scales {
        let mut motion = full;
        motion.start.alpha *= scale;
        motion.start.beta *= scale;
        motion.start.gamma *= scale;
        match served(robot, &motion) {
            Ok(()) if scale < 1.0 && robot.freedom().turns() => return Ok((motion, Some(scale))),
            Ok(()) => return Ok((motion, None)),
            Err(e) => refused = Some(e),
        }
    }
    Err(format!(
        "Section 9's move from this robot's home is out of its reach: {}",
        refused.map_or_else(String::new, |e| e.to_string())
    )
    .into())
}

/// What the reports add after the default move's name when [`section9_for`] scaled its
/// orientation by `scale`.
pub fn scaled_note(scale: Option<f64>) -> String {
    scale.map_or_else(String::new, |s| {
        format!(
            ", its orientation scaled to {:.0} % (this robot cannot take all of it)",
            100.0 * s
        )
    })
}

/// Whether `robot` serves every state of `motion`, sampled every millisecond.
fn served(robot: &dyn c5_runtime::Mechanism, motion: &LinearMove) -> crate::Result<()> {
    let samples = (motion.duration * 1000.0).round().max(1.0) as usize;
    for k in 0..=samples {
        let state = motion.state(motion.duration * k as f64 / samples as f64);
        let [pose, twist, accel] = robot.coordinates_of(&state)?;
        robot.evaluate(&pose, &twist, &accel)?;
    }
    Ok(())
}

/// Section 9's move (the chapter's default trajectory), from `home`: the C5's home is the
/// origin, a hexapod's above its base.
pub fn section9_from(home: Pose) -> LinearMove {
    let mut motion = LinearMove::section9();
    for k in 0..3 {
        motion.start.center[k] += home.center[k];
        motion.end[k] += home.center[k];
    }
    motion
}

/// The sample times of a default trajectory of `duration` at `rate`, or why not.
pub fn sample_times(duration: f64, rate: f64, what: &str) -> crate::Result<Vec<f64>> {
    c5_runtime::trajectory::sample_times(duration, rate, crate::MAX_SAMPLES).map_err(|n| {
        if n == usize::MAX {
            format!("--rate must be a positive number, got {rate}").into()
        } else {
            format!(
                "--rate {rate} would take {n} {what} of the {duration} s move (at most {})",
                crate::MAX_SAMPLES
            )
            .into()
        }
    })
}

/// What the robot's sensors and motors add: quantized encoders and noisy forces.
#[derive(Args, Clone, Debug)]
pub struct SensorArgs {
    /// Encoder resolution (m per count): the actuator positions are read as whole counts
    /// [default: exact].
    #[arg(long)]
    pub encoder_resolution: Option<f64>,
    /// Gaussian noise on the forces (N, standard deviation) [default: none].
    #[arg(long)]
    pub force_noise: Option<f64>,
    /// Seed of the force noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

impl SensorArgs {
    /// Whether any sensor option is given.
    pub fn any(&self) -> bool {
        self.encoder_resolution.is_some() || self.force_noise.is_some()
    }

    /// The encoders, exact without `--encoder-resolution`.
    pub fn encoders(&self) -> crate::Result<c5_runtime::sensors::Encoders> {
        match self.encoder_resolution {
            None => Ok(c5_runtime::sensors::Encoders::default()),
            Some(m) => c5_runtime::sensors::Encoders::new(m).map_err(|_| {
                format!("--encoder-resolution must be a positive number, got {m}").into()
            }),
        }
    }

    /// The force noise: a seeded source of `N(0, σ²)` samples (zero without `--force-noise`).
    pub fn noise(&self) -> crate::Result<ForceNoise> {
        let sigma = self.force_noise.unwrap_or(0.0);
        if !(sigma.is_finite() && sigma >= 0.0) {
            return Err(format!("--force-noise must be a non-negative number, got {sigma}").into());
        }
        Ok(ForceNoise {
            normal: rand_distr::Normal::new(0.0, sigma).expect("a valid deviation"),
            rng: <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(self.seed),
        })
    }
}

/// Seeded Gaussian noise on the forces.
pub struct ForceNoise {
    normal: rand_distr::Normal<f64>,
    rng: rand_chacha::ChaCha8Rng,
}

impl ForceNoise {
    /// One force measured.
    pub fn noisy(&mut self, g: f64) -> f64 {
        use rand_distr::Distribution;
        g + self.normal.sample(&mut self.rng)
    }
}
