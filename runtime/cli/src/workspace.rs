//! `c5 workspace`: the reachable centres at one orientation (or orientations at one centre)
//! on a grid, within the robot file's `[limits]` and away from singular poses, with two
//! dexterity measures; a CSV of the reachable points, slices plotted, and the volume.

use crate::options::RobotArgs;
use crate::view;
use c5_runtime::workspace::{map, Grid, Map, Sweep};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Maps the workspace: which centres the robot reaches at an orientation (or, with `--at`,
/// which orientations at a centre), within its `[limits]`; writes `workspace.csv` (the
/// reachable points with the inverse condition number of `J⁻¹` and the largest actuator force
/// per newton of load) and slices through the grid's middle coloured by each. A platform that
/// only translates (the Delta) has its centres swept, level.
#[derive(Args)]
pub struct WorkspaceArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// The orientation `α,β,γ` (rad) at which centres are swept.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with = "at"
    )]
    orientation: Option<Vec<f64>>,
    /// Sweep the orientations at this centre `xc,yc,zc` (m) instead.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    at: Option<Vec<f64>>,
    /// Half-width of the swept box: m for centres, rad for orientations [default: 0.3 m, or
    /// 1.2 rad].
    #[arg(long)]
    range: Option<f64>,
    /// Grid points per axis (101 gives 1 030 301 poses).
    #[arg(long, default_value_t = 101)]
    points: usize,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Do not write the 3D page of the reachable points (`workspace.html`).
    #[arg(long)]
    no_view: bool,
}

fn three(v: &Option<Vec<f64>>, flag: &str, default: [f64; 3]) -> crate::Result<[f64; 3]> {
    match v {
        None => Ok(default),
        Some(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok([v[0], v[1], v[2]]),
        Some(_) => Err(format!("{flag} takes three finite numbers").into()),
    }
}

pub fn run(args: &WorkspaceArgs) -> crate::Result<ExitCode> {
    let robot = args.robot.load_mechanism()?;
    let freedom = robot.freedom();
    if !freedom.turns() && (args.at.is_some() || args.orientation.is_some()) {
        return Err(format!(
            "--at and --orientation sweep or set the platform's orientation, and the {}'s \
             platform only translates: its centres are swept, level",
            robot.mechanism()
        )
        .into());
    }
    // About the robot's home: the C5's is the origin, a hexapod's and a Delta's below or
    // above their base.
    let home_pose = robot.home();
    let home: [f64; 3] = home_pose[home_pose.len() - 3..]
        .try_into()
        .expect("a pose ends with its centre");
    let (sweep, range, names, unit, middle) = match &args.at {
        Some(_) => (
            Sweep::Orientations {
                centre: three(&args.at, "--at", home)?,
            },
            args.range.unwrap_or(1.2),
            ["alpha", "beta", "gamma"],
            "rad³",
            [0.0; 3],
        ),
        None => (
            Sweep::Centres {
                orientation: three(&args.orientation, "--orientation", [0.0; 3])?,
            },
            args.range.unwrap_or(0.3),
            ["xc", "yc", "zc"],
            "m³",
            home,
        ),
    };
    if !(range > 0.0 && range.is_finite()) {
        return Err(format!("--range must be positive, got {range}").into());
    }
    let grid = Grid {
        sweep,
        lower: middle.map(|m| m - range),
        upper: middle.map(|m| m + range),
        points: args.points,
    };
    let total = args.points.saturating_pow(3);
    let bar = ProgressBar::new(total as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} poses {per_sec} eta {eta}")
            .expect("a valid template"),
    );
    let started = Instant::now();
    let m = map(robot.as_ref(), &grid, &|done| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    let elapsed = started.elapsed();
    std::fs::create_dir_all(&args.out)?;
    let csv = args.out.join("workspace.csv");
    write_csv(&csv, &m, &names)?;
    let mut written = vec![csv];
    for (measure, title) in [
        (Measure::InverseCondition, "inverse condition number of J⁻¹"),
        (
            Measure::ForceRatio,
            "largest actuator force per newton of load (N/N)",
        ),
    ] {
        let path = args.out.join(format!("workspace_{}.png", measure.file()));
        plot_slices(&path, &m, measure, title, &names)?;
        written.push(path);
    }
    if !args.no_view {
        let path = args.out.join("workspace.html");
        let points: Vec<[f64; 3]> = m
            .reachable
            .iter()
            .map(|c| m.grid.coordinates(c.index))
            .collect();
        let values: Vec<f64> = m.reachable.iter().map(|c| c.inverse_condition).collect();
        // The robot among its reachable centres, at the swept orientation's grid middle.
        // Where the grid's middle is out of reach, the points alone.
        let scene = match &args.at {
            None => robot
                .scene(&m.grid.platform_pose([args.points / 2; 3], freedom))
                .ok(),
            Some(_) => None,
        };
        let axes = names.map(|n| {
            if args.at.is_some() {
                format!("{n} (rad)")
            } else {
                format!("{n} (m)")
            }
        });
        view::write_cloud(
            &points,
            &values,
            "inverse condition number of J⁻¹",
            axes.each_ref().map(String::as_str),
            scene.as_ref(),
            &format!("Workspace ({} robot)", robot.mechanism()),
            &path,
        )?;
        written.push(path);
    }
    let mut report = std::io::stdout().lock();
    if !robot.has_limits() {
        writeln!(
            report,
            "note: the robot sets no [limits]; only singular poses are out of reach"
        )?;
    }
    let volume = m.volume();
    writeln!(
        report,
        "{} of {} poses reachable in {:.2} s ({:.0} ns a pose); volume {volume:.6} {unit}",
        m.reachable.len(),
        m.total,
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * 1e9 / m.total as f64
    )?;
    if let Some(best) = m
        .reachable
        .iter()
        .max_by(|a, b| a.inverse_condition.total_cmp(&b.inverse_condition))
    {
        let worst = m
            .reachable
            .iter()
            .map(|c| c.inverse_condition)
            .fold(f64::INFINITY, f64::min);
        let ratio = m
            .reachable
            .iter()
            .map(|c| c.force_ratio)
            .fold(0.0, f64::max);
        writeln!(
            report,
            "inverse condition number from {worst:.4} to {:.4} (at {:?}); largest force per newton of load {ratio:.3}",
            best.inverse_condition,
            grid.coordinates(best.index)
        )?;
    }
    for p in written {
        writeln!(report, "wrote {}", p.display())?;
    }
    Ok(ExitCode::SUCCESS)
}

#[derive(Clone, Copy)]
enum Measure {
    InverseCondition,
    ForceRatio,
}

impl Measure {
    fn file(self) -> &'static str {
        match self {
            Measure::InverseCondition => "dexterity",
            Measure::ForceRatio => "force_ratio",
        }
    }

    fn of(self, c: &c5_runtime::workspace::Cell) -> f64 {
        match self {
            Measure::InverseCondition => c.inverse_condition,
            Measure::ForceRatio => c.force_ratio,
        }
    }
}

fn write_csv(path: &Path, m: &Map, names: &[&str; 3]) -> crate::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(
        w,
        "{},{},{},inverse_condition,force_ratio",
        names[0], names[1], names[2]
    )?;
    for c in &m.reachable {
        let x = m.grid.coordinates(c.index);
        writeln!(
            w,
            "{},{},{},{},{}",
            x[0], x[1], x[2], c.inverse_condition, c.force_ratio
        )?;
    }
    w.flush()?;
    Ok(())
}

/// Three slices through the grid's middle (normal to each swept axis), cells coloured by
/// `measure` (viridis, its range over the reachable set), unreachable cells left white.
fn plot_slices(
    path: &Path,
    m: &Map,
    measure: Measure,
    title: &str,
    names: &[&str; 3],
) -> crate::Result<()> {
    crate::simulate::register_font();
    let n = m.grid.points;
    let mid = n / 2;
    let mut values = vec![f64::NAN; n * n * n];
    for c in &m.reachable {
        values[(c.index[0] * n + c.index[1]) * n + c.index[2]] = measure.of(c);
    }
    let (lo, hi) = m
        .reachable
        .iter()
        .map(|c| measure.of(c))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    crate::png_figure::write(path, (1500, 560), |root| {
        root.fill(&WHITE)?;
        let (top, panels) = root.split_vertically(60);
        top.titled(
            &format!(
                "{title}: {:.3} to {:.3} (viridis); white: out of reach",
                lo, hi
            ),
            ("sans-serif", 22),
        )?;
        let (h, lower, upper) = (m.grid.step(), m.grid.lower, m.grid.upper);
        for (normal, panel) in panels.split_evenly((1, 3)).iter().enumerate() {
            let (a, b) = match normal {
                0 => (1, 2),
                1 => (0, 2),
                _ => (0, 1),
            };
            let at = lower[normal] + mid as f64 * h[normal];
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{} = {at:.3}", names[normal]), ("sans-serif", 18))
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(lower[a]..upper[a], lower[b]..upper[b])?;
            chart
                .configure_mesh()
                .x_desc(names[a])
                .y_desc(names[b])
                .disable_mesh()
                .label_style(("sans-serif", 13))
                .draw()?;
            let mut cells = Vec::new();
            for i in 0..n {
                for j in 0..n {
                    let mut index = [mid; 3];
                    index[a] = i;
                    index[b] = j;
                    let v = values[(index[0] * n + index[1]) * n + index[2]];
                    if v.is_nan() {
                        continue;
                    }
                    let t = if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
                    let color = ViridisRGB::get_color(t);
                    let (x, y) = (lower[a] + i as f64 * h[a], lower[b] + j as f64 * h[b]);
                    cells.push(Rectangle::new(
                        [
                            (x - h[a] / 2.0, y - h[b] / 2.0),
                            (x + h[a] / 2.0, y + h[b] / 2.0),
                        ],
                        color.filled(),
                    ));
                }
            }
            chart.draw_series(cells)?;
        }
        Ok(())
    })
}
