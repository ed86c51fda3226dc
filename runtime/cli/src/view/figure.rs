//! The robot along a trajectory as a plotly.js figure: a trace per leg, a trace per kind of
//! joint, the platform, its frame, then what does not move (the base, the path of `C`, the
//! colour bar); one animation frame per drawn instant.

use super::colors::{self, force_colour, WARNING};
use super::plotly::{self, title, Figure};
use c5_runtime::scene::{Joint, JointKind, Scene, Solid};
use serde::Serialize;
use serde_json::{json, Value};

/// One drawn instant: its time, the robot's parts, the forces and what crosses a limit.
#[derive(Clone, Debug)]
pub struct Shot {
    pub t: f64,
    pub scene: Scene,
    /// The actuator forces (N or N·m), one per leg.
    pub gamma: Vec<f64>,
    /// Legs whose force or speed is past the robot file's `[limits]`.
    pub over_force: Vec<bool>,
    pub over_speed: Vec<bool>,
}

impl Shot {
    /// What leg `i` crosses, in words, empty within its limits.
    pub fn warnings(&self, i: usize) -> Vec<&'static str> {
        let leg = &self.scene.legs[i];
        let last = leg.joints.len() - 1;
        let joints = leg.joints.iter().enumerate().map(|(k, j)| {
            let side = match k {
                0 => "base joint",
                k if k == last => "platform joint",
                _ => "elbow joint",
            };
            (j.over_limit, side)
        });
        [
            (leg.over_stroke, "stroke"),
            (self.over_force[i], "force"),
            (self.over_speed[i], "speed"),
        ]
        .into_iter()
        .chain(joints)
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
    pub gamma: Vec<f64>,
    pub colours: Vec<String>,
    pub warnings: Vec<String>,
}

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

fn line(points: &[[f64; 3]], colour: &str, width: f64, name: &str) -> Value {
    let mut trace = plotly::scatter3d(name, "lines", xyz(points));
    trace["line"] = json!({"color": colour, "width": width});
    trace["hoverinfo"] = json!("name");
    trace
}

/// A trace that leaves the legend alone.
fn unlisted(mut trace: Value) -> Value {
    trace["showlegend"] = json!(false);
    trace
}

/// The marker a kind of joint is drawn with: its symbol and size. Base-side joints are squares,
/// the elbows' U joints diamonds, the platform's joints circles.
fn marker(kind: JointKind) -> (&'static str, usize) {
    match kind {
        JointKind::Prismatic | JointKind::Revolute => ("square", 5),
        JointKind::Universal => ("diamond", 5),
        JointKind::Spherical | JointKind::BallOnPlates => ("circle", 6),
    }
}

/// The joints of one kind, over every leg.
fn joints(joints: &[&Joint]) -> Value {
    let colours: Vec<&str> = joints
        .iter()
        .map(|j| if j.over_limit { WARNING } else { colors::JOINT })
        .collect();
    let points: Vec<[f64; 3]> = joints.iter().map(|j| j.at).collect();
    let kind = joints[0].kind;
    let (symbol, size) = marker(kind);
    let mut trace = plotly::scatter3d(kind.name(), "markers", xyz(&points));
    trace["marker"] = json!({"symbol": symbol, "size": size, "color": colours});
    trace
}

/// The scene's joints grouped by kind, the kinds in the order the first leg meets them (a
/// base joint first): the same groups in every frame of one robot.
fn joint_groups(scene: &Scene) -> Vec<Vec<&Joint>> {
    let mut groups: Vec<Vec<&Joint>> = Vec::new();
    for joint in scene.legs.iter().flat_map(|l| &l.joints) {
        match groups.iter_mut().find(|g| g[0].kind == joint.kind) {
            Some(group) => group.push(joint),
            None => groups.push(vec![joint]),
        }
    }
    groups
}

/// A solid's trace; `with_triangles` false for an animation frame, where the triangles of the
/// first frame stay and only the vertices move.
fn solid(solid: &Solid, colour: &str, name: &str, with_triangles: bool) -> Value {
    let triangles = with_triangles.then_some(solid.triangles.as_slice());
    let mut mesh = plotly::mesh3d(name, xyz(&solid.vertices), triangles);
    mesh["color"] = json!(colour);
    mesh["flatshading"] = json!(true);
    mesh["showlegend"] = json!(true);
    mesh
}

/// The traces that move: a leg each, a kind of joint each, the platform and its three axes;
/// `first` for the figure's own traces, which carry what frames leave out.
fn moving(shot: &Shot, scale: f64, first: bool) -> Vec<Value> {
    let s = &shot.scene;
    let mut traces = Vec::new();
    for (i, leg) in s.legs.iter().enumerate() {
        traces.push(unlisted(line(
            &leg.path,
            &shot.leg_colour(i, scale),
            10.0,
            &format!("leg {}", i + 1),
        )));
    }
    traces.extend(joint_groups(s).iter().map(|group| joints(group)));
    traces.push(solid(&s.platform, colors::PLATFORM, "platform", first));
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        let tip: [f64; 3] = core::array::from_fn(|c| s.centre[c] + 1.3 * s.size * s.axes[k][c]);
        traces.push(unlisted(line(
            &[s.centre, tip],
            colors::AXES[k],
            8.0,
            &format!("platform {name}"),
        )));
    }
    traces
}

/// The figure of `shots`, forces coloured on `±scale` (in `unit`).
pub fn figure(shots: &[Shot], scale: f64, unit: &str) -> Figure {
    let first = &shots[0];
    let mut data = moving(first, scale, true);
    data.push(solid(&first.scene.base, colors::BASE, "base", true));
    let path: Vec<[f64; 3]> = shots.iter().map(|s| s.scene.centre).collect();
    let mut path = line(&path, "#9a9a9a", 2.0, "path of C");
    path["opacity"] = json!(0.6);
    data.push(path);
    data.push(colour_bar(first.scene.centre, scale, unit));
    // A legend entry only: its point is not a number (`null`), so nothing is drawn.
    data.push(line(&[[f64::NAN; 3]], WARNING, 10.0, "past a limit"));
    let frames = shots
        .iter()
        .enumerate()
        .map(|(k, shot)| {
            let traces = moving(shot, scale, false);
            let count = traces.len();
            plotly::frame(&k.to_string(), traces, 0..count)
        })
        .collect();
    Figure {
        data,
        layout: layout(extent(shots), METRES),
        frames,
    }
}

/// An invisible point that carries the force scale's colour bar.
fn colour_bar(at: [f64; 3], scale: f64, unit: &str) -> Value {
    let mut trace = plotly::scatter3d("actuator force", "markers", at.map(|c| vec![c]));
    trace["marker"] = json!({
        "size": 1,
        "opacity": 0.0,
        "color": [0.0],
        "cmin": -scale,
        "cmax": scale,
        "colorscale": colors::force_scale(),
        "showscale": true,
        "colorbar": {"title": title(&format!("Γ ({unit})")), "lenmode": "pixels", "len": 260},
    });
    trace["hoverinfo"] = json!("skip");
    unlisted(trace)
}

/// Every point the figure of `shots` draws.
fn extent(shots: &[Shot]) -> impl Iterator<Item = [f64; 3]> + '_ {
    shots.iter().flat_map(|shot| {
        let s = &shot.scene;
        s.legs
            .iter()
            .flat_map(|l| l.path.iter().copied().chain(l.joints.iter().map(|j| j.at)))
            .chain(s.platform.vertices.iter().copied())
            .chain(s.base.vertices.iter().copied())
    })
}

/// Fixed axes that hold every point, at one scale on all three, titled `names`.
fn layout(points: impl Iterator<Item = [f64; 3]>, names: [&str; 3]) -> Value {
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
    let axis = |k: usize| json!({"range": [lo[k] - pad, hi[k] + pad], "title": title(names[k])});
    json!({
        "scene": {
            "xaxis": axis(0),
            "yaxis": axis(1),
            "zaxis": axis(2),
            "aspectmode": "manual",
            "aspectratio": {
                "x": span[0] / longest,
                "y": span[1] / longest,
                "z": span[2] / longest,
            },
            "camera": {"eye": {"x": 1.5, "y": -1.5, "z": 0.9}},
        },
        "legend": {"x": 0.0, "y": 1.0},
        "margin": {"l": 0, "r": 0, "t": 0, "b": 0},
        "showlegend": true,
    })
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
) -> Figure {
    let mut reachable = plotly::scatter3d("reachable", "markers", xyz(points));
    reachable["marker"] = json!({
        "size": 2,
        "color": values,
        "colorscale": "Viridis",
        "showscale": true,
        "colorbar": {"title": title(measure)},
    });
    reachable["opacity"] = json!(0.4);
    let mut data = vec![reachable];
    let mut extent: Vec<[f64; 3]> = points.to_vec();
    if let Some(scene) = robot {
        let legs = scene.legs.len();
        let shot = Shot {
            t: 0.0,
            scene: scene.clone(),
            gamma: vec![0.0; legs],
            over_force: vec![false; legs],
            over_speed: vec![false; legs],
        };
        data.extend(moving(&shot, 1.0, true));
        data.push(solid(&scene.base, colors::BASE, "base", true));
        extent.extend(self::extent(core::slice::from_ref(&shot)));
    }
    Figure {
        data,
        layout: layout(extent.into_iter(), names),
        frames: Vec::new(),
    }
}
