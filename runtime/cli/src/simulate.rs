//! Section 9: the inverse dynamics along a trajectory, in both models, as a CSV and four
//! plots.

use c5_runtime::{Error, Evaluation, Model, State, C5};

use plotters::prelude::*;
use std::path::Path;
use std::time::Instant;

/// One sample of the study.
#[derive(Clone, Debug)]
pub struct Sample {
    pub t: f64,
    pub state: State,
    /// Everything the chosen model gives.
    pub eval: Evaluation,
    /// The other model's actuator forces.
    pub other_gamma: [f64; 6],
}

/// The study's samples and how long the kernels took.
#[derive(Clone, Debug)]
pub struct Study {
    /// The model of [`Sample::eval`]; the other gave [`Sample::other_gamma`].
    pub model: Model,
    pub other: Model,
    pub samples: Vec<Sample>,
    /// Mean wall time of [`C5::evaluate`] per sample (s).
    pub time_per_sample: f64,
}

/// Evaluates every state of a trajectory with `robot`'s model, and the forces of the other.
///
/// # Errors
/// The first sample whose state is refused (non-finite or singular), with its time.
pub fn run(robot: &C5, states: &[(f64, State)]) -> Result<Study, (f64, Error)> {
    let other = robot.to_model(match robot.model() {
        Model::Consistent => Model::Paper,
        Model::Paper => Model::Consistent,
    });
    let only: Vec<State> = states.iter().map(|&(_, s)| s).collect();
    let time_of = |k: usize| states[k].0;
    let start = Instant::now();
    let evals = robot
        .evaluate_many(&only)
        .map_err(|(k, e)| (time_of(k), e))?;
    let time_per_sample = start.elapsed().as_secs_f64() / evals.len().max(1) as f64;
    let others = other
        .inverse_dynamics_many(&only)
        .map_err(|(k, e)| (time_of(k), e))?;
    let samples = states
        .iter()
        .zip(evals.into_iter().zip(others))
        .map(|(&(t, state), (eval, other_gamma))| Sample {
            t,
            state,
            eval,
            other_gamma,
        })
        .collect();
    Ok(Study {
        model: robot.model(),
        other: other.model(),
        samples,
        time_per_sample,
    })
}

/// Header of the CSV: time, pose, twist, acceleration, `Q_a`, `Q̇_a`, `Q̈_a`, `Γ` of the chosen
/// model, and `Γ` of the other one (`gamma_paper1..6` or `gamma_consistent1..6`).
pub fn csv_header(other: Model) -> Vec<String> {
    let mut h = vec!["t".to_string()];
    h.extend(["alpha", "beta", "gamma", "xc", "yc", "zc"].map(String::from));
    h.extend(["wx", "wy", "wz", "vx", "vy", "vz"].map(String::from));
    h.extend(["wdx", "wdy", "wdz", "ax", "ay", "az"].map(String::from));
    for name in ["q", "qd", "qdd", "gamma"] {
        h.extend((1..=6).map(|i| format!("{name}{i}")));
    }
    h.extend((1..=6).map(|i| format!("gamma_{other}{i}")));
    h
}

/// Writes the samples as CSV.
///
/// # Errors
/// I/O errors.
pub fn write_csv(path: &Path, study: &Study) -> Result<(), Box<dyn std::error::Error>> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record(csv_header(study.other))?;
    for s in &study.samples {
        let mut row = vec![s.t];
        row.extend(s.state.pose.to_array());
        row.extend(s.state.twist.to_array());
        row.extend(s.state.accel.to_array());
        for v in [s.eval.q, s.eval.qd, s.eval.qdd, s.eval.gamma, s.other_gamma] {
            row.extend(v);
        }
        w.write_record(row.iter().map(|v| format!("{v:.12e}")))?;
    }
    w.flush()?;
    Ok(())
}

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The font ships with the crate, so the plots need no system fonts.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../assets/DejaVuSans.ttf"),
        );
    });
}

/// Plots several series against time.
pub fn plot(
    path: &Path,
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[(String, Vec<f64>)],
) -> Result<(), Box<dyn std::error::Error>> {
    register_font();
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, v)| v.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let pad = ((hi - lo) * 0.08).max(1e-9);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 24))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(t[0]..t[t.len() - 1], (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .x_desc("time t (s)")
        .y_desc(y_label)
        .label_style(("sans-serif", 15))
        .draw()?;
    for (k, (name, v)) in series.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        chart
            .draw_series(LineSeries::new(
                t.iter().copied().zip(v.iter().copied()),
                color.stroke_width(2),
            ))?
            .label(name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()?;
    root.present()?;
    Ok(())
}

/// The four figures of Section 9 (figs 7-10) as PNG files in `dir`.
///
/// # Errors
/// I/O or drawing errors.
pub fn write_plots(dir: &Path, study: &Study) -> Result<Vec<String>, Box<dyn std::error::Error>> {
    let t: Vec<f64> = study.samples.iter().map(|s| s.t).collect();
    let xyz = |f: &dyn Fn(&Sample) -> [f64; 3]| -> Vec<(String, Vec<f64>)> {
        ["x", "y", "z"]
            .iter()
            .enumerate()
            .map(|(k, a)| {
                (
                    a.to_string(),
                    study.samples.iter().map(|s| f(s)[k]).collect(),
                )
            })
            .collect()
    };
    let files = [
        (
            "fig7_trajectory.png",
            "Platform trajectory (fig. 7)",
            "centre position (m)",
            xyz(&|s| s.state.pose.center),
        ),
        (
            "fig8_velocity.png",
            "Platform linear velocity (fig. 8)",
            "velocity (m/s)",
            xyz(&|s| s.state.twist.velocity),
        ),
        (
            "fig9_acceleration.png",
            "Platform linear acceleration (fig. 9)",
            "acceleration (m/s²)",
            xyz(&|s| s.state.accel.linear),
        ),
    ];
    let mut written = Vec::new();
    for (name, title, y, series) in files {
        plot(&dir.join(name), title, y, &t, &series)?;
        written.push(name.to_string());
    }
    let name = "fig10_forces.png";
    plot_forces(&dir.join(name), study, &t)?;
    written.push(name.to_string());
    Ok(written)
}

/// Figure 10: one panel per actuator, so no series hides another; in each, the consistent
/// model solid and the paper model dashed, in the actuator's colour.
fn plot_forces(path: &Path, study: &Study, t: &[f64]) -> Result<(), Box<dyn std::error::Error>> {
    register_font();
    let root = BitMapBackend::new(path, (1200, 720)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        "Actuator forces Γ (fig. 10): consistent model solid, paper model dashed",
        ("sans-serif", 22),
    )?;
    let gamma = |s: &Sample, model: Model, i: usize| {
        if model == study.model {
            s.eval.gamma[i]
        } else {
            s.other_gamma[i]
        }
    };
    for (i, panel) in root.split_evenly((2, 3)).iter().enumerate() {
        let series: Vec<(Model, Vec<f64>)> = [Model::Consistent, Model::Paper]
            .into_iter()
            .map(|m| (m, study.samples.iter().map(|s| gamma(s, m, i)).collect()))
            .collect();
        let (lo, hi) = series
            .iter()
            .flat_map(|(_, v)| v.iter().copied())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let pad = ((hi - lo) * 0.1).max(0.5);
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("Γ{}", i + 1), ("sans-serif", 18))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(56)
            .build_cartesian_2d(t[0]..t[t.len() - 1], (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .y_desc("force (N)")
            .label_style(("sans-serif", 13))
            .draw()?;
        let color = Palette99::pick(i).to_rgba();
        for (model, values) in &series {
            let points = t.iter().copied().zip(values.iter().copied());
            let style = color.stroke_width(2);
            let label = model.to_string();
            match model {
                Model::Consistent => chart
                    .draw_series(LineSeries::new(points, style))?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style)),
                Model::Paper => chart
                    .draw_series(DashedLineSeries::new(points, 6, 5, style))?
                    .label(label)
                    .legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (7, 0)], style)
                            + PathElement::new(vec![(12, 0), (19, 0)], style)
                    }),
            };
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()?;
    }
    root.present()?;
    Ok(())
}
