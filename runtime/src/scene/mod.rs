//! Where a mechanism's parts are at a pose, for drawing it (`c5 view`): its legs, their joints
//! and the platform, as points and triangles in the base frame, as many legs as it has
//! actuators.
//!
//! The mechanisms say where their parts are; a viewer decides how they look. Every point comes
//! from the same kinematics the kernels compute (the C5's `Q_i1` of eq 16, a hexapod's leg
//! vectors, a crank's angle), so a drawn ball sits where the model puts it, and a leg or joint
//! past one of the robot file's `[limits]` is flagged here, from the same margins
//! `check_limits` reads. A leg type draws its legs once (`scene/cranked.rs` for a motor turning a
//! crank, the rotary hexapod's legs and the Delta's arms).

mod c5;
pub(crate) mod cranked;
pub(crate) mod gough_stewart;

use crate::Pose;
use alloc::vec::Vec;

/// The kind of a drawn joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// An actuated prismatic joint: where the actuator's body is fixed to the base.
    Prismatic,
    /// A motor's revolute joint on the base, turning a crank.
    Revolute,
    /// A universal (Hooke's) joint.
    Universal,
    /// A ball-and-socket joint.
    Spherical,
    /// The C5 joint: a ball riding on crossed plates of the platform.
    BallOnPlates,
}

impl JointKind {
    /// The name a legend shows.
    pub const fn name(self) -> &'static str {
        match self {
            JointKind::Prismatic => "P (actuator)",
            JointKind::Revolute => "R (motor)",
            JointKind::Universal => "U joint",
            JointKind::Spherical => "S joint",
            JointKind::BallOnPlates => "C5 joint (ball on plates)",
        }
    }
}

/// A joint: its kind, its centre (m, base frame) and whether the pose is past one of its
/// limits (a U or S joint's cone, a C5 ball's tilt or plate travel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint {
    pub kind: JointKind,
    pub at: [f64; 3],
    pub over_limit: bool,
}

/// A leg: its bodies drawn as one line, its joints (base side first), and whether its
/// actuator is past its stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct Leg {
    /// The line through the leg's bodies, from the base: a hexapod's leg from its base joint to
    /// its platform joint, a crank to its elbow and its rod on, a Delta's arm round its
    /// parallelogram.
    pub path: Vec<[f64; 3]>,
    pub joints: Vec<Joint>,
    pub over_stroke: bool,
}

impl Leg {
    /// A leg drawn straight from its base joint to its platform joint.
    pub(crate) fn straight(base: Joint, platform: Joint, over_stroke: bool) -> Self {
        Leg {
            path: alloc::vec![base.at, platform.at],
            joints: alloc::vec![base, platform],
            over_stroke,
        }
    }

    /// Its joint nearest the platform.
    pub fn platform_joint(&self) -> &Joint {
        self.joints.last().expect("a leg has joints")
    }
}

/// A solid as triangles: vertices (m, base frame) and the vertex indices of each triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solid {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[usize; 3]>,
}

impl Solid {
    /// Adds the quadrilateral `a b c d` (in order round its edge) as two triangles.
    pub(crate) fn quad(&mut self, corners: [[f64; 3]; 4]) {
        let n = self.vertices.len();
        self.vertices.extend(corners);
        self.triangles.push([n, n + 1, n + 2]);
        self.triangles.push([n, n + 2, n + 3]);
    }

    /// Adds a box of half-extents `half` along the unit axes `axes`, centred at `centre`.
    pub(crate) fn cuboid(&mut self, centre: [f64; 3], axes: [[f64; 3]; 3], half: [f64; 3]) {
        let corner = |s: [f64; 3]| -> [f64; 3] {
            core::array::from_fn(|k| {
                centre[k] + (0..3).map(|j| s[j] * half[j] * axes[j][k]).sum::<f64>()
            })
        };
        let n = self.vertices.len();
        for s in 0..8 {
            let sign = |bit: usize| if s >> bit & 1 == 1 { 1.0 } else { -1.0 };
            self.vertices.push(corner([sign(0), sign(1), sign(2)]));
        }
        const FACES: [[usize; 4]; 6] = [
            [0, 1, 3, 2],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 3, 7, 5],
        ];
        for [a, b, c, d] in FACES {
            self.triangles.push([n + a, n + b, n + c]);
            self.triangles.push([n + a, n + c, n + d]);
        }
    }
}

/// A mechanism at a pose, ready to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The legs in actuator order.
    pub legs: Vec<Leg>,
    /// The platform as a solid in its pose.
    pub platform: Solid,
    /// What does not move: the base plate, the actuators' rails.
    pub base: Solid,
    /// The platform frame: its origin `C` and its axes (the columns of `R`).
    pub centre: [f64; 3],
    pub axes: [[f64; 3]; 3],
    /// A length that sizes markers and the frame's axes (m).
    pub size: f64,
}

/// `R = Rx(α) Ry(β) Rz(γ)`'s columns: the platform's axes in the base frame.
pub(crate) fn platform_axes(pose: &Pose) -> [[f64; 3]; 3] {
    let r = c5_robot::gough_stewart::rotation(&pose.to_array());
    core::array::from_fn(|j| core::array::from_fn(|k| r[k][j]))
}

/// `c + s v`.
pub(crate) fn along(c: [f64; 3], s: f64, v: [f64; 3]) -> [f64; 3] {
    core::array::from_fn(|k| c[k] + s * v[k])
}

/// A plate of thickness `thickness` along `axes[2]` whose rim runs through `points`, taken in
/// order of their angle about the plate's centre.
pub(crate) fn plate(points: &[[f64; 3]], axes: [[f64; 3]; 3], thickness: f64) -> Solid {
    let n = points.len();
    let centre: [f64; 3] =
        core::array::from_fn(|k| points.iter().map(|p| p[k]).sum::<f64>() / n as f64);
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut rim: Vec<([f64; 3], f64)> = points
        .iter()
        .map(|&p| {
            let d: [f64; 3] = core::array::from_fn(|k| p[k] - centre[k]);
            (p, crate::math::atan2(dot(d, axes[1]), dot(d, axes[0])))
        })
        .collect();
    rim.sort_by(|a, b| a.1.total_cmp(&b.1));
    let offset =
        |p: [f64; 3], s: f64| -> [f64; 3] { core::array::from_fn(|k| p[k] + s * axes[2][k]) };
    let mut solid = Solid::default();
    let h = 0.5 * thickness;
    for s in [-h, h] {
        let hub = solid.vertices.len();
        solid.vertices.push(offset(centre, s));
        for &(p, _) in &rim {
            solid.vertices.push(offset(p, s));
        }
        for k in 0..n {
            solid
                .triangles
                .push([hub, hub + 1 + k, hub + 1 + (k + 1) % n]);
        }
    }
    for k in 0..n {
        let (p, q) = (rim[k].0, rim[(k + 1) % n].0);
        solid.quad([offset(p, -h), offset(q, -h), offset(q, h), offset(p, h)]);
    }
    solid
}

/// The base frame's axes, for a plate lying in the base.
pub(crate) const BASE_AXES: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
