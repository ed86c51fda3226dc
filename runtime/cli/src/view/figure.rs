//! The robot along a trajectory as a plotly figure: a trace per leg, the joints, the platform,
//! its frame, then what does not move (the base, the path of `C`, the colour bar); one
//! animation frame per drawn instant.

use super::colors::{self, force_colour, WARNING};
use c5_runtime::scene::{Joint, Scene, Solid};
use plotly::common::{
    ColorBar, ColorScale, ColorScalePalette, Line, Marker, MarkerSymbol, Mode, ThicknessMode, Title,
};
use plotly::layout::{
    AspectMode, AspectRatio, Axis, Camera, Eye, Frame, LayoutScene, Legend, Margin,
};
use plotly::{Layout, Mesh3D, Plot, Scatter3D, Trace, Traces};
use serde::Serialize;

/// One drawn instant: its time, the robot's parts, the forces and what crosses a limit.
#[derive(Clone, Debug)]
pub struct Shot {
    pub t: f64,
    pub scene: Scene,
    /// The actuator forces (N).
    pub gamma: [f64; 6],
    /// Legs whose force or speed is past the robot file's `[limits]`.
    pub over_force: [bool; 6],
    pub over_speed: [bool; 6],
}

impl Shot {
    /// What leg `i` crosses, in words, empty within its limits.
    pub fn warnings(&self, i: usize) -> Vec<&'static str> {
        let leg = &self.scene.legs[i];
        [
            (leg.over_stroke, "stroke"),
            (self.over_force[i], "force"),
            (self.over_speed[i], "speed"),
            (leg.base.over_limit, "base joint"),
            (leg.platform.over_limit, "platform joint"),
        ]
        .into_iter()
        .filter_map(|(over, what)| over.then_some(what))
        .collect()
    }

    /// Leg `i`'s colour: its force on the scale `±scale`, or the warning colour.
    pub fn leg_colour(&self, i: usize, scale: f64) -> String {
        let leg = &self.scene.legs[i];
        if leg.over_stroke || self.over_force[i] || self.over_speed[i] {
            WARNING.to_string()
        } else {
            force_colour(self.gamma[i], scale)
        }
    }
}

/// What the page shows beside the figure for one frame.
#[derive(Serialize)]
pub struct Readout {
    pub t: f64,
    pub gamma: [f64; 6],
    pub colours: [String; 6],
    pub warnings: Vec<String>,
}

/// How many traces each frame redraws: six legs, two joint sets, the platform, three axes.
pub const MOVING_TRACES: usize = 12;

/// The page draws to a tenth of a micrometre, which keeps its numbers short (a third of the
/// digits of a full `f64`) and is far below a pixel: this many steps per metre (dividing by
/// it, not multiplying by its inverse, rounds to the shortest decimal).
const STEPS_PER_METRE: f64 = 1e7;

fn xyz(points: &[[f64; 3]]) -> [Vec<f64>; 3] {
    core::array::from_fn(|k| {
        points
            .iter()
            .map(|p| (p[k] * STEPS_PER_METRE).round() / STEPS_PER_METRE)
            .collect()
    })
}

fn line(
    points: &[[f64; 3]],
    colour: &str,
    width: f64,
    name: &str,
) -> Box<Scatter3D<f64, f64, f64>> {
    let [x, y, z] = xyz(points);
    Scatter3D::new(x, y, z)
        .mode(Mode::Lines)
        .line(Line::new().color(colour.to_string()).width(width))
        .name(name)
        .hover_info(plotly::common::HoverInfo::Name)
}

fn joints(joints: &[Joint; 6], symbol: MarkerSymbol, size: usize) -> Box<Scatter3D<f64, f64, f64>> {
    let [x, y, z] = xyz(&joints.map(|j| j.at));
    let colours: Vec<String> = joints
        .iter()
        .map(|j| if j.over_limit { WARNING } else { colors::JOINT }.to_string())
        .collect();
    Scatter3D::new(x, y, z)
        .mode(Mode::Markers)
        .marker(Marker::new().symbol(symbol).size(size).color_array(colours))
        .name(joints[0].kind.name())
}

/// A solid's trace; `with_triangles` false for an animation frame, where the triangles of the
/// first frame stay and only the vertices move.
fn solid(
    solid: &Solid,
    colour: &str,
    name: &str,
    with_triangles: bool,
) -> Box<Mesh3D<f64, f64, f64>> {
    let [x, y, z] = xyz(&solid.vertices);
    let [i, j, k]: [Option<Vec<usize>>; 3] = core::array::from_fn(|c| {
        with_triangles.then(|| solid.triangles.iter().map(|t| t[c]).collect())
    });
    Mesh3D::new(x, y, z, i, j, k)
        .color(colour.to_string())
        .flat_shading(true)
        .name(name)
        .show_legend(true)
}

/// The traces that move, in the order of [`MOVING_TRACES`]; `first` for the figure's own
/// traces, which carry what frames leave out.
fn moving(shot: &Shot, scale: f64, first: bool) -> Vec<Box<dyn Trace>> {
    let s = &shot.scene;
    let mut traces: Vec<Box<dyn Trace>> = Vec::with_capacity(MOVING_TRACES);
    for (i, leg) in s.legs.iter().enumerate() {
        let trace = line(
            &[leg.base.at, leg.platform.at],
            &shot.leg_colour(i, scale),
            10.0,
            &format!("leg {}", i + 1),
        )
        .show_legend(false);
        traces.push(trace);
    }
    traces.push(joints(&s.legs.map(|l| l.base), MarkerSymbol::Square, 5));
    traces.push(joints(&s.legs.map(|l| l.platform), MarkerSymbol::Circle, 6));
    traces.push(solid(&s.platform, colors::PLATFORM, "platform", first));
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        let tip: [f64; 3] = core::array::from_fn(|c| s.centre[c] + 1.3 * s.size * s.axes[k][c]);
        let trace = line(
            &[s.centre, tip],
            colors::AXES[k],
            8.0,
            &format!("platform {name}"),
        )
        .show_legend(false);
        traces.push(trace);
    }
    traces
}

/// The figure of `shots`, forces coloured on `±scale` (N).
pub fn figure(shots: &[Shot], scale: f64) -> Plot {
    let mut plot = Plot::new();
    let first = &shots[0];
    plot.add_traces(moving(first, scale, true));
    plot.add_trace(solid(&first.scene.base, colors::BASE, "base", true));
    let path: Vec<[f64; 3]> = shots.iter().map(|s| s.scene.centre).collect();
    plot.add_trace(line(&path, "#9a9a9a", 2.0, "path of C").opacity(0.6));
    plot.add_trace(colour_bar(first.scene.centre, scale));
    // A legend entry only: its point is not a number, so nothing is drawn.
    plot.add_trace(line(&[[f64::NAN; 3]], WARNING, 10.0, "past a limit"));
    for (k, shot) in shots.iter().enumerate() {
        let mut data = Traces::new();
        for t in moving(shot, scale, false) {
            data.push(t);
        }
        plot.add_frame(
            Frame::new()
                .name(k.to_string())
                .data(data)
                .traces((0..MOVING_TRACES).collect()),
        );
    }
    plot.set_layout(layout(extent(shots), METRES));
    plot
}

/// An invisible point that carries the force scale's colour bar.
fn colour_bar(at: [f64; 3], scale: f64) -> Box<Scatter3D<f64, f64, f64>> {
    Scatter3D::new(vec![at[0]], vec![at[1]], vec![at[2]])
        .mode(Mode::Markers)
        .marker(
            Marker::new()
                .size(1)
                .opacity(0.0)
                .color_array(vec![0.0])
                .cmin(-scale)
                .cmax(scale)
                .color_scale(colors::force_scale())
                .show_scale(true)
                .color_bar(
                    ColorBar::new()
                        .title(Title::with_text("Γ (N)"))
                        .len_mode(ThicknessMode::Pixels)
                        .len(260),
                ),
        )
        .name("actuator force")
        .show_legend(false)
        .hover_info(plotly::common::HoverInfo::Skip)
}

/// Every point the figure of `shots` draws.
fn extent(shots: &[Shot]) -> impl Iterator<Item = [f64; 3]> + '_ {
    shots.iter().flat_map(|shot| {
        let s = &shot.scene;
        s.legs
            .iter()
            .flat_map(|l| [l.base.at, l.platform.at])
            .chain(s.platform.vertices.iter().copied())
            .chain(s.base.vertices.iter().copied())
    })
}

/// Fixed axes that hold every point, at one scale on all three, titled `names`.
fn layout(points: impl Iterator<Item = [f64; 3]>, names: [&str; 3]) -> Layout {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let pad = 0.05 * (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let span: [f64; 3] = core::array::from_fn(|k| hi[k] - lo[k] + 2.0 * pad);
    let longest = span.iter().copied().fold(0.0, f64::max);
    let axis = |k: usize| {
        Axis::new()
            .range(vec![lo[k] - pad, hi[k] + pad])
            .title(Title::with_text(names[k]))
    };
    let ratio = AspectRatio::new()
        .x(span[0] / longest)
        .y(span[1] / longest)
        .z(span[2] / longest);
    Layout::new()
        .scene(
            LayoutScene::new()
                .x_axis(axis(0))
                .y_axis(axis(1))
                .z_axis(axis(2))
                .aspect_mode(AspectMode::Manual)
                .aspect_ratio(ratio)
                .camera(Camera::new().eye(Eye::new().x(1.5).y(-1.5).z(0.9))),
        )
        .legend(Legend::new().x(0.0).y(1.0))
        .margin(Margin::new().left(0).right(0).top(0).bottom(0))
        .show_legend(true)
}

/// The axes' titles of a robot's figure.
const METRES: [&str; 3] = ["x (m)", "y (m)", "z (m)"];

/// A point cloud coloured by `values` (viridis, its colour bar titled `measure`), with the
/// robot drawn at one pose among the points where `robot` is given.
pub fn cloud(
    points: &[[f64; 3]],
    values: &[f64],
    measure: &str,
    names: [&str; 3],
    robot: Option<&Scene>,
) -> Plot {
    let mut plot = Plot::new();
    let [x, y, z] = xyz(points);
    plot.add_trace(
        Scatter3D::new(x, y, z)
            .mode(Mode::Markers)
            .marker(
                Marker::new()
                    .size(2)
                    .color_array(values.to_vec())
                    .color_scale(ColorScale::Palette(ColorScalePalette::Viridis))
                    .show_scale(true)
                    .color_bar(ColorBar::new().title(Title::with_text(measure))),
            )
            .opacity(0.4)
            .name("reachable"),
    );
    let mut extent: Vec<[f64; 3]> = points.to_vec();
    if let Some(scene) = robot {
        let shot = Shot {
            t: 0.0,
            scene: scene.clone(),
            gamma: [0.0; 6],
            over_force: [false; 6],
            over_speed: [false; 6],
        };
        plot.add_traces(moving(&shot, 1.0, true));
        plot.add_trace(solid(&scene.base, colors::BASE, "base", true));
        extent.extend(self::extent(core::slice::from_ref(&shot)));
    }
    plot.set_layout(layout(extent.into_iter(), names));
    plot
}
