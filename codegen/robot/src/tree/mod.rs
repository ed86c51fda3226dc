//! The robot as a tree of rigid bodies with its loops cut: what the export formats write.
//!
//! A parallel robot is a closed chain; the formats other tools read want a tree. The tree here
//! is the one both Pinocchio's and MuJoCo's MJCF readers accept: the platform is the single
//! root, each leg hangs from it, body after body towards the base, and the leg's part fixed to
//! the base (a guide, a U joint's yoke, a motor's housing) is closed on the world by a weld; a
//! body whose other end holds the platform by a ball (the second rod of a Delta's
//! parallelogram) is closed on it by that ball. Every body is placed at the robot's home pose,
//! so the tree's zero joint coordinates are the assembled robot at home and the loops are
//! closed there by construction.
//!
//! A mechanism builds its tree from its description ([`crate::Description::body_tree`]); the
//! writers ([`crate::export`]) know nothing of mechanisms.

mod c5;
mod gough_stewart;
mod rus;

use alloc::string::String;
use alloc::vec::Vec;

/// A 3-vector.
pub type Vec3 = [f64; 3];
/// A 3×3 matrix, by rows.
pub type Mat3 = [[f64; 3]; 3];

/// The robot as a tree with its loops cut at the base.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyTree {
    /// The mechanism's name as a robot file spells it.
    pub mechanism: &'static str,
    /// Gravity in the base frame (m/s²).
    pub gravity: Vec3,
    /// The home pose `[α β γ xc yc zc]` the bodies are placed at.
    pub home: [f64; 6],
    /// The platform, the tree's root.
    pub platform: Body,
    /// How the platform may move.
    pub freedom: Freedom,
    /// The legs in actuator order, each hanging from the platform.
    pub legs: Vec<Chain>,
}

/// How the platform moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Freedom {
    /// Free in space: six coordinates.
    Free,
    /// Translations only, its frame parallel to the base's (the Delta).
    Translations,
}

impl Freedom {
    /// The pose's coordinates, as robot files, JSON lines and CSV columns name them: as many
    /// as the platform has freedoms, and as the mechanism has actuators.
    pub const fn pose_names(self) -> &'static [&'static str] {
        match self {
            Freedom::Free => &["alpha", "beta", "gamma", "xc", "yc", "zc"],
            Freedom::Translations => &["xc", "yc", "zc"],
        }
    }

    /// The twist's coordinates: `(ω; v_C)`, or `v_C` alone.
    pub const fn twist_names(self) -> &'static [&'static str] {
        match self {
            Freedom::Free => &["wx", "wy", "wz", "vx", "vy", "vz"],
            Freedom::Translations => &["vx", "vy", "vz"],
        }
    }

    /// The classical acceleration's coordinates: `(ω̇; a_C)`, or `a_C` alone.
    pub const fn acceleration_names(self) -> &'static [&'static str] {
        match self {
            Freedom::Free => &["wdx", "wdy", "wdz", "ax", "ay", "az"],
            Freedom::Translations => &["ax", "ay", "az"],
        }
    }

    /// The twist's parts as JSON lines and Python name them, three numbers each: `omega` and
    /// `velocity`, or `velocity` alone.
    pub const fn twist_parts(self) -> &'static [&'static str] {
        match self {
            Freedom::Free => &["omega", "velocity"],
            Freedom::Translations => &["velocity"],
        }
    }

    /// The acceleration's parts as JSON lines and Python name them: `omega_dot` and
    /// `acceleration`, or `acceleration` alone.
    pub const fn acceleration_parts(self) -> &'static [&'static str] {
        match self {
            Freedom::Free => &["omega_dot", "acceleration"],
            Freedom::Translations => &["acceleration"],
        }
    }

    /// Whether the platform turns: its pose has the RPY angles `α β γ` first, its twist `ω`.
    pub const fn turns(self) -> bool {
        matches!(self, Freedom::Free)
    }

    /// How many coordinates the pose, twist and acceleration have, and so how many actuators
    /// drive the platform.
    pub const fn dimension(self) -> usize {
        self.pose_names().len()
    }
}

/// One leg: its bodies from the platform outwards, and where its loops close.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// The actuator's name (`leg1`, `segment1`).
    pub name: String,
    /// The bodies, each after its parent.
    pub bodies: Vec<Body>,
    /// Each body's parent: `None` the platform, `Some(k)` `bodies[k]`, `k` before it.
    pub parents: Vec<Option<usize>>,
    /// Where the loops through this leg are cut.
    pub closures: Vec<Closure>,
    /// Which joint the motor drives: `(body, joint)` indices into [`Chain::bodies`]. Its
    /// positive direction is the actuator's: a positive `Γ_i` drives it positive.
    pub actuated: (usize, usize),
}

/// A cut loop, closed again by a constraint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Closure {
    /// `bodies[body]` is welded to the world where it is at home.
    Weld { body: usize },
    /// `bodies[body]`'s point `anchor` (its frame) is held by a ball at the platform's point
    /// that is there at home.
    Ball { body: usize, anchor: Vec3 },
}

impl Chain {
    /// A chain of `bodies`, each the child of the one before (the first, of the platform),
    /// the last welded to the world.
    pub(crate) fn serial(name: String, bodies: Vec<Body>, actuated: (usize, usize)) -> Self {
        let n = bodies.len();
        Chain {
            name,
            bodies,
            parents: (0..n).map(|k| k.checked_sub(1)).collect(),
            closures: alloc::vec![Closure::Weld { body: n - 1 }],
            actuated,
        }
    }

    /// The children of `parent` (`None`: the platform), in order.
    pub fn children(&self, parent: Option<usize>) -> impl Iterator<Item = usize> + '_ {
        (0..self.bodies.len()).filter(move |&k| self.parents[k] == parent)
    }

    /// The parent body of `bodies[k]` (the platform for `None`).
    pub fn parent<'a>(&'a self, k: usize, platform: &'a Body) -> &'a Body {
        self.parents[k].map_or(platform, |p| &self.bodies[p])
    }
}

/// A rigid body, placed at the home pose.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: String,
    /// Its frame at home: the columns of `rotation` are its axes in the base frame.
    pub rotation: Mat3,
    /// Its frame's origin at home, base frame (m).
    pub origin: Vec3,
    /// The joints from its parent to it, in the order they act, all at the body's origin: the
    /// first one's axis is fixed in the parent, the last one's in this body.
    pub joints: Vec<Joint>,
    /// Its mass (kg); zero only for the parts the robot's description gives no mass to,
    /// which are fixed to the base.
    pub mass: f64,
    /// Its centre of mass, body frame (m).
    pub com: Vec3,
    /// Its inertia about the centre of mass, body frame (kg·m²).
    pub inertia: Mat3,
    /// Shapes for a viewer, body frame: no mass, no contact.
    pub shapes: Vec<Shape>,
}

/// A joint between a body and its parent.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
}

/// The joint's kind; axes are unit vectors in the child body's frame at zero displacement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// A revolute joint about `axis`, through the body's origin.
    Hinge { axis: Vec3 },
    /// A prismatic joint along `axis`.
    Slide { axis: Vec3 },
    /// A spherical joint at the body's origin.
    Ball,
}

/// A shape to draw, body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A capsule from one point to another.
    Capsule { from: Vec3, to: Vec3, radius: f64 },
    /// A box centred at `centre`, along the body's axes.
    Box { centre: Vec3, half_sizes: Vec3 },
    /// A sphere.
    Sphere { centre: Vec3, radius: f64 },
}

impl BodyTree {
    /// Whether the motors turn (a hinge: angles in rad, torques in N·m) rather than slide (m,
    /// N), from the joint the first leg's motor drives.
    pub fn actuators_turn(&self) -> bool {
        let leg = &self.legs[0];
        let (body, joint) = leg.actuated;
        matches!(leg.bodies[body].joints[joint].kind, JointKind::Hinge { .. })
    }

    /// The unit of the actuators' forces `Γ_i`: `N·m` where the motors turn, else `N`.
    pub fn actuator_unit(&self) -> &'static str {
        if self.actuators_turn() {
            "N·m"
        } else {
            "N"
        }
    }

    /// The total mass of the moving bodies (kg).
    pub fn mass(&self) -> f64 {
        self.platform.mass
            + self
                .legs
                .iter()
                .flat_map(|l| &l.bodies)
                .map(|b| b.mass)
                .sum::<f64>()
    }
}

impl Body {
    /// Its placement in `parent`'s frame at home: the origin and the rotation (exactly the
    /// identity where the two frames are turned alike).
    pub fn relative_to(&self, parent: &Body) -> (Vec3, Mat3) {
        let origin = transpose_times(&parent.rotation, sub(self.origin, parent.origin));
        let rotation = if self.rotation == parent.rotation {
            IDENTITY
        } else {
            transpose_product(&parent.rotation, &self.rotation)
        };
        (origin, rotation)
    }

    /// A body at `origin`, turned by `rotation`, with no joint, mass or shape yet.
    pub(crate) fn at(name: String, rotation: Mat3, origin: Vec3) -> Self {
        Body {
            name,
            rotation,
            origin,
            joints: Vec::new(),
            mass: 0.0,
            com: [0.0; 3],
            inertia: [[0.0; 3]; 3],
            shapes: Vec::new(),
        }
    }
}

impl crate::Platform {
    /// The platform as the tree's root at the pose `home`, drawn as a plate across its joints
    /// `joints` (platform frame): the body, its rotation and its origin.
    pub(crate) fn root_at(
        &self,
        home: &[f64; 6],
        joints: impl Iterator<Item = Vec3>,
    ) -> (Body, Mat3, Vec3) {
        let rotation = crate::gough_stewart::rotation(home);
        let origin = [home[3], home[4], home[5]];
        let size = joints.map(norm).fold(0.0, f64::max);
        (self.root_body(rotation, origin, size), rotation, origin)
    }

    /// The platform as the tree's root at `rotation` and `origin`, drawn as a plate `size`
    /// across its joints (the largest `|p_i|`).
    fn root_body(&self, rotation: Mat3, origin: Vec3, size: f64) -> Body {
        let mut platform = Body::at("platform".into(), rotation, origin);
        platform.mass = self.mass;
        platform.com = self.centre_of_mass;
        platform.inertia = self.inertia_matrix();
        platform.shapes.push(Shape::Box {
            centre: [0.0; 3],
            half_sizes: [size, size, 0.04 * size],
        });
        platform
    }
}

pub(crate) fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub(crate) fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: Vec3) -> f64 {
    crate::math::sqrt(dot(a, a))
}

pub(crate) fn unit(a: Vec3) -> Vec3 {
    scale(a, 1.0 / norm(a))
}

/// `Mᵀ v`.
pub(crate) fn transpose_times(m: &Mat3, v: Vec3) -> Vec3 {
    core::array::from_fn(|j| m[0][j] * v[0] + m[1][j] * v[1] + m[2][j] * v[2])
}

/// `M v`.
pub(crate) fn times(m: &Mat3, v: Vec3) -> Vec3 {
    core::array::from_fn(|i| dot(m[i], v))
}

/// `Aᵀ B`.
pub(crate) fn transpose_product(a: &Mat3, b: &Mat3) -> Mat3 {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[k][i] * b[k][j]).sum()))
}

/// The matrix whose columns are `x`, `y`, `z`.
pub(crate) fn columns(x: Vec3, y: Vec3, z: Vec3) -> Mat3 {
    core::array::from_fn(|i| [x[i], y[i], z[i]])
}

pub(crate) fn diagonal(d: Vec3) -> Mat3 {
    [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]
}

pub(crate) const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// The unit quaternion `[w x y z]` of a rotation matrix, `w ≥ 0` (Shepperd's method: the
/// largest of the four squares first, so no division loses digits).
pub fn quaternion(r: &Mat3) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let q = if trace >= r[0][0].max(r[1][1]).max(r[2][2]) {
        let w = 0.5 * crate::math::sqrt(1.0 + trace);
        let k = 0.25 / w;
        [
            w,
            (r[2][1] - r[1][2]) * k,
            (r[0][2] - r[2][0]) * k,
            (r[1][0] - r[0][1]) * k,
        ]
    } else if r[0][0] >= r[1][1] && r[0][0] >= r[2][2] {
        let x = 0.5 * crate::math::sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
        let k = 0.25 / x;
        [
            (r[2][1] - r[1][2]) * k,
            x,
            (r[0][1] + r[1][0]) * k,
            (r[0][2] + r[2][0]) * k,
        ]
    } else if r[1][1] >= r[2][2] {
        let y = 0.5 * crate::math::sqrt(1.0 - r[0][0] + r[1][1] - r[2][2]);
        let k = 0.25 / y;
        [
            (r[0][2] - r[2][0]) * k,
            (r[0][1] + r[1][0]) * k,
            y,
            (r[1][2] + r[2][1]) * k,
        ]
    } else {
        let z = 0.5 * crate::math::sqrt(1.0 - r[0][0] - r[1][1] + r[2][2]);
        let k = 0.25 / z;
        [
            (r[1][0] - r[0][1]) * k,
            (r[0][2] + r[2][0]) * k,
            (r[1][2] + r[2][1]) * k,
            z,
        ]
    };
    if q[0] < 0.0 {
        q.map(|c| -c)
    } else {
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gough_stewart::rotation;

    /// The rotation of a unit quaternion `[w x y z]`.
    fn matrix(q: [f64; 4]) -> Mat3 {
        let [w, x, y, z] = q;
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }

    /// Forces where a leg slides, torques where a motor turns.
    #[test]
    fn the_actuators_unit_follows_the_joint_the_motor_drives() {
        assert_eq!(crate::Robot::default().body_tree().actuator_unit(), "N");
        let hexapod = crate::GoughStewart::example().body_tree();
        assert_eq!(hexapod.actuator_unit(), "N");
        assert_eq!(
            crate::RusHexapod::example().body_tree().actuator_unit(),
            "N·m"
        );
        assert_eq!(crate::Delta::example().body_tree().actuator_unit(), "N·m");
    }

    #[test]
    fn the_quaternion_gives_its_rotation_back_in_every_branch() {
        // Near the identity, and near half turns about each axis (each of Shepperd's branches).
        for pose in [
            [0.1, -0.2, 0.3],
            [3.1, 0.05, -0.02],
            [0.02, 3.1, 0.05],
            [3.1, 3.1, 0.0],
            [0.0, 0.0, 3.1],
        ] {
            let r = rotation(&[pose[0], pose[1], pose[2], 0.0, 0.0, 0.0]);
            let back = matrix(quaternion(&r));
            for i in 0..3 {
                for j in 0..3 {
                    assert!((back[i][j] - r[i][j]).abs() < 1e-15, "{pose:?} [{i}][{j}]");
                }
            }
        }
    }
}
