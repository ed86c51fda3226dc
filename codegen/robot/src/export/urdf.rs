//! URDF, the format ROS loads for display: the tree with its loops cut, one single-axis joint
//! per URDF joint, and each cut written as urdfdom's proposed `<constraint>` element
//! (ros/urdfdom#264), which a reader without it skips.
//!
//! URDF has no ball joint and no body with several joints: a ball becomes three hinges about
//! the child's axes and a body's joints a chain, through links with no mass.

use super::{header, Num, Triple};
use crate::math::{atan2, sqrt};
use crate::tree::{
    columns, cross, norm, scale, sub, unit, Body, BodyTree, Closure, Freedom, Joint, JointKind,
    Mat3, Shape, Vec3, IDENTITY,
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
    let world = Body::at("world".into(), IDENTITY, [0.0; 3]);
    match tree.freedom {
        Freedom::Free => {
            let _ = writeln!(
                out,
                "  <joint name=\"{}\" type=\"floating\">\n    <parent link=\"world\"/>\n    \
                 <child link=\"{}\"/>\n    {}\n  </joint>",
                p.name,
                p.name,
                Origin(p.origin, &p.rotation)
            );
        }
        Freedom::Translations => {
            let mut sliding = p.clone();
            sliding.joints = IDENTITY
                .iter()
                .zip(["x", "y", "z"])
                .map(|(axis, name)| Joint {
                    name: format!("{}_{name}", p.name),
                    kind: JointKind::Slide { axis: *axis },
                })
                .collect();
            joints(&mut out, &world, &sliding);
        }
    }
    for leg in &tree.legs {
        for (k, body) in leg.bodies.iter().enumerate() {
            link(&mut out, body);
            joints(&mut out, leg.parent(k, p), body);
        }
        for closure in &leg.closures {
            let (kind, parent, body, at_parent, at_child) = match *closure {
                Closure::Weld { body } => {
                    let b = &leg.bodies[body];
                    (
                        "fixed",
                        &world,
                        b,
                        OriginAttributes(b.origin, &b.rotation),
                        [0.0; 3],
                    )
                }
                Closure::Ball { body, anchor } => {
                    let b = &leg.bodies[body];
                    let point = crate::tree::add(b.origin, crate::tree::times(&b.rotation, anchor));
                    let (in_platform, _) = Body::at(String::new(), IDENTITY, point).relative_to(p);
                    (
                        "spherical",
                        p,
                        b,
                        OriginAttributes(in_platform, &IDENTITY),
                        anchor,
                    )
                }
            };
            let _ = writeln!(
                out,
                "  <!-- {}: a loop is cut here; {} is held to {} ({kind}). -->\n  \
                 <constraint name=\"{}_closure\" type=\"{kind}\">\n    <parent link=\"{}\"/>\n    \
                 <parent_origin {at_parent}/>\n    <child link=\"{}\"/>\n    \
                 <child_origin xyz=\"{}\" rpy=\"0 0 0\"/>\n  </constraint>",
                leg.name,
                body.name,
                parent.name,
                body.name,
                parent.name,
                body.name,
                Triple(at_child)
            );
        }
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
/// (`R = Rz(yaw) Ry(pitch) Rx(roll)`). The roll is solved last from what the pitch and yaw
/// leave, so the three give `R` back to rounding at every pitch, ±90° included (where the yaw
/// is any, and taken as 0).
struct OriginAttributes<'a>(Vec3, &'a Mat3);

impl core::fmt::Display for OriginAttributes<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let r = self.1;
        let level = sqrt(r[0][0] * r[0][0] + r[1][0] * r[1][0]);
        let pitch = atan2(-r[2][0], level);
        let yaw = if level > 0.0 {
            atan2(r[1][0], r[0][0])
        } else {
            0.0
        };
        // Rx(roll) = Ry(pitch)ᵀ Rz(yaw)ᵀ R: its rows 2 and 3 give the roll.
        let (sy, cy) = crate::math::sin_cos(yaw);
        let (sp, cp) = crate::math::sin_cos(pitch);
        let unyawed = |j: usize| {
            [
                cy * r[0][j] + sy * r[1][j],
                -sy * r[0][j] + cy * r[1][j],
                r[2][j],
            ]
        };
        let (c1, c2) = (unyawed(1), unyawed(2));
        // Row 3 of Ry(pitch)ᵀ times the unyawed columns 2 and 3.
        let sin_roll = sp * c1[0] + cp * c1[2];
        let cos_roll = sp * c2[0] + cp * c2[2];
        let roll = atan2(sin_roll, cos_roll);
        write!(
            f,
            "xyz=\"{}\" rpy=\"{}\"",
            Triple(self.0),
            Triple([roll, pitch, yaw])
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tree::IDENTITY;

    fn from_rpy([roll, pitch, yaw]: [f64; 3]) -> Mat3 {
        let (sr, cr) = (roll.sin(), roll.cos());
        let (sp, cp) = (pitch.sin(), pitch.cos());
        let (sy, cy) = (yaw.sin(), yaw.cos());
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    }

    #[test]
    fn roll_pitch_yaw_give_the_rotation_back_at_every_pitch_the_vertical_included() {
        let quarter = core::f64::consts::FRAC_PI_2;
        let cases = [
            IDENTITY,
            from_rpy([0.3, -0.2, 1.1]),
            from_rpy([2.9, 1.4, -3.0]),
            // Pitch ±90° exactly, and within rounding of it: the yaw is any.
            columns([0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
            columns([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            from_rpy([0.7, quarter - 1e-13, -0.4]),
            from_rpy([-1.2, -quarter + 1e-9, 2.2]),
        ];
        for r in cases {
            let text = alloc::format!("{}", OriginAttributes([0.0; 3], &r));
            let rpy: Vec<f64> = text
                .split("rpy=\"")
                .nth(1)
                .unwrap()
                .trim_end_matches('"')
                .split(' ')
                .map(|x| x.parse().unwrap())
                .collect();
            let back = from_rpy([rpy[0], rpy[1], rpy[2]]);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((back[i][j] - r[i][j]).abs() < 1e-15, "{text} [{i}][{j}]");
                }
            }
        }
    }
}
