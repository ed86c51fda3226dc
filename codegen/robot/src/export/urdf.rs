//! URDF, the format ROS loads for display: the tree with its loops cut, one single-axis joint
//! per URDF joint, and each cut written as urdfdom's proposed `<constraint>` element
//! (ros/urdfdom#264), which a reader without it skips.
//!
//! URDF has no ball joint and no body with several joints: a ball becomes three hinges about
//! the child's axes and a body's joints a chain, through links with no mass.

use super::{header, Num, Triple};
use crate::math::{atan2, sqrt};
use crate::tree::{
    columns, cross, norm, scale, sub, unit, Body, BodyTree, JointKind, Mat3, Shape, Vec3, IDENTITY,
};
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write;

/// A wide range for the prismatic joints, whose `<limit>` URDF requires (m); the robot
/// file's limits are the runtime's to check.
const SLIDE_RANGE: f64 = 10.0;

/// The tree as a URDF document.
pub fn urdf(tree: &BodyTree) -> String {
    let mut out = format!(
        "<?xml version=\"1.0\"?>\n<!-- {} -->\n<robot name=\"{}\">\n  \
         <link name=\"world\"/>\n",
        header(tree, super::Format::Urdf),
        tree.mechanism
    );
    let p = &tree.platform;
    link(&mut out, p);
    let _ = writeln!(
        out,
        "  <joint name=\"{}\" type=\"floating\">\n    <parent link=\"world\"/>\n    \
         <child link=\"{}\"/>\n    {}\n  </joint>",
        p.name,
        p.name,
        Origin(p.origin, &p.rotation)
    );
    for leg in &tree.legs {
        let mut parent = p;
        for body in &leg.bodies {
            link(&mut out, body);
            joints(&mut out, parent, body);
            parent = body;
        }
        let _ = writeln!(
            out,
            "  <!-- {}: the loop is cut here; {} is fixed to the world where it is at home. -->\n  \
             <constraint name=\"{}_closure\" type=\"fixed\">\n    <parent link=\"world\"/>\n    \
             <parent_origin {}/>\n    <child link=\"{}\"/>\n    \
             <child_origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n  </constraint>",
            leg.name,
            parent.name,
            leg.name,
            OriginAttributes(parent.origin, &parent.rotation),
            parent.name
        );
    }
    out.push_str("</robot>\n");
    out
}

/// `<link>` with its inertia (none for a body without mass) and shapes.
fn link(out: &mut String, body: &Body) {
    let _ = writeln!(out, "  <link name=\"{}\">", body.name);
    if body.mass > 0.0 {
        let m = &body.inertia;
        let _ = writeln!(
            out,
            "    <inertial>\n      <origin xyz=\"{}\" rpy=\"0 0 0\"/>\n      \
             <mass value=\"{}\"/>\n      <inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" \
             iyz=\"{}\" izz=\"{}\"/>\n    </inertial>",
            Triple(body.com),
            Num(body.mass),
            Num(m[0][0]),
            Num(m[0][1]),
            Num(m[0][2]),
            Num(m[1][1]),
            Num(m[1][2]),
            Num(m[2][2])
        );
    }
    for shape in &body.shapes {
        let (origin, geometry) = match *shape {
            Shape::Capsule { from, to, radius } => {
                let axis = sub(to, from);
                let length = norm(axis);
                let centre = scale(crate::tree::add(from, to), 0.5);
                (
                    Origin(centre, &aligned_with(axis)),
                    format!(
                        "<cylinder radius=\"{}\" length=\"{}\"/>",
                        Num(radius),
                        Num(length)
                    ),
                )
            }
            Shape::Box { centre, half_sizes } => (
                Origin(centre, &IDENTITY),
                format!("<box size=\"{}\"/>", Triple(scale(half_sizes, 2.0))),
            ),
            Shape::Sphere { centre, radius } => (
                Origin(centre, &IDENTITY),
                format!("<sphere radius=\"{}\"/>", Num(radius)),
            ),
        };
        let _ = writeln!(
            out,
            "    <visual>\n      {origin}\n      <geometry>{geometry}</geometry>\n    </visual>"
        );
    }
    out.push_str("  </link>\n");
}

/// The URDF joints from `parent` to `body`: one per axis, through massless links where the
/// body has more than one (a ball is three hinges about the body's axes).
fn joints(out: &mut String, parent: &Body, body: &Body) {
    let mut axes: Vec<(String, &str, Vec3)> = Vec::new();
    for joint in &body.joints {
        match joint.kind {
            JointKind::Hinge { axis } => axes.push((joint.name.clone(), "continuous", axis)),
            JointKind::Slide { axis } => axes.push((joint.name.clone(), "prismatic", axis)),
            JointKind::Ball => {
                for (k, axis) in IDENTITY.iter().enumerate() {
                    axes.push((
                        format!("{}_{}", joint.name, ["x", "y", "z"][k]),
                        "continuous",
                        *axis,
                    ));
                }
            }
        }
    }
    let (origin, rotation) = body.relative_to(parent);
    let mut from = parent.name.clone();
    for (k, (name, kind, axis)) in axes.iter().enumerate() {
        let last = k + 1 == axes.len();
        let to = if last {
            body.name.clone()
        } else {
            let link = format!("{name}_link");
            let _ = writeln!(
                out,
                "  <link name=\"{link}\"/>  <!-- between two axes of one joint: no mass -->"
            );
            link
        };
        let placement = if k == 0 {
            Origin(origin, &rotation)
        } else {
            Origin([0.0; 3], &IDENTITY)
        };
        let limit = if *kind == "prismatic" {
            format!(
                "\n    <limit lower=\"{}\" upper=\"{SLIDE_RANGE}\" effort=\"1e9\" velocity=\"1e9\"/>",
                -SLIDE_RANGE
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "  <joint name=\"{name}\" type=\"{kind}\">\n    <parent link=\"{from}\"/>\n    \
             <child link=\"{to}\"/>\n    {placement}\n    <axis xyz=\"{}\"/>{limit}\n  </joint>",
            Triple(*axis)
        );
        from = to;
    }
}

/// A rotation taking `z` to the direction of `axis`.
fn aligned_with(axis: Vec3) -> Mat3 {
    let z = unit(axis);
    let helper = if z[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let x = unit(cross(helper, z));
    columns(x, cross(z, x), z)
}

/// `<origin xyz rpy>` of a placement.
struct Origin<'a>(Vec3, &'a Mat3);

impl core::fmt::Display for Origin<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "<origin {}/>", OriginAttributes(self.0, self.1))
    }
}

/// The attributes `xyz="…" rpy="…"`, URDF's fixed-axis roll, pitch and yaw
/// (`R = Rz(yaw) Ry(pitch) Rx(roll)`).
struct OriginAttributes<'a>(Vec3, &'a Mat3);

impl core::fmt::Display for OriginAttributes<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let r = self.1;
        let roll = atan2(r[2][1], r[2][2]);
        let pitch = atan2(-r[2][0], sqrt(r[0][0] * r[0][0] + r[1][0] * r[1][0]));
        let yaw = atan2(r[1][0], r[0][0]);
        write!(
            f,
            "xyz=\"{}\" rpy=\"{}\"",
            Triple(self.0),
            Triple([roll, pitch, yaw])
        )
    }
}
