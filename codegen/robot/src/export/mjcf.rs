//! MJCF, the format of MuJoCo, which Pinocchio's MJCF reader also loads with its loop closures.
//!
//! The layout both engines load (measured with Pinocchio 4.1 and MuJoCo): one root body, the
//! platform, with a `freejoint` (Pinocchio reads only the first body tree under `worldbody`,
//! and MuJoCo allows a `freejoint` only on a top-level body); each leg nested under it; each
//! leg's last body closed on the world by `equality/weld` at its pose in the reference
//! configuration, which is the assembled robot at home. Bodies with several joints compose them
//! in order, as Pinocchio's composite joint does.

use super::{header, numbers, Num, Triple};
use crate::tree::{quaternion, Body, BodyTree, JointKind, Mat3, Shape, Vec3};
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::Write;

/// The integration step MuJoCo takes (s): the welds' time constant below is twice it, the
/// stiffest MuJoCo accepts.
pub const TIMESTEP: f64 = 1e-4;
/// The welds' `solref`: time constant (s) and damping ratio of the soft loop closures.
pub const SOLREF: [f64; 2] = [2e-4, 1.0];
/// The welds' `solimp`: impedance 0.9999, the hardest MuJoCo takes, at every violation (from
/// 0.99, the loops opened a hundred times wider: docs/export.md).
pub const SOLIMP: [f64; 5] = [0.9999, 0.9999, 0.001, 0.5, 2.0];

/// The mass (kg) and principal inertia (kg·m²) given to a body the description gives no mass
/// to (the parts welded to the base: their motion is zero, so any real inertia gives the same
/// dynamics, and MuJoCo refuses a massless body that has joints).
const WELDED_MASS: f64 = 1.0;
const WELDED_INERTIA: f64 = 1e-3;

/// The tree as an MJCF document.
pub fn mjcf(tree: &BodyTree) -> String {
    let mut out = String::new();
    let mut w = |s: core::fmt::Arguments| out.write_fmt(s).expect("writing to a String");
    w(format_args!(
        "<!-- {} -->\n",
        header(tree, super::Format::Mjcf)
    ));
    w(format_args!("<mujoco model=\"{}\">\n", tree.mechanism));
    w(format_args!(
        "  <compiler angle=\"radian\" autolimits=\"true\"/>\n\
         \x20 <!-- The loops are closed by soft welds: MuJoCo lets each open in proportion to \
         the force it carries, by solref {} {} (the stiffest for the timestep) and solimp \
         {} {} {} {} {}; RK4 at {} s keeps them closed to the tolerance docs/export.md \
         states. Contacts are off: the legs pass through each other as the kernels' do. -->\n",
        SOLREF[0], SOLREF[1], SOLIMP[0], SOLIMP[1], SOLIMP[2], SOLIMP[3], SOLIMP[4], TIMESTEP
    ));
    w(format_args!(
        "  <option gravity=\"{}\" timestep=\"{}\" integrator=\"RK4\">\n\
         \x20   <flag contact=\"disable\"/>\n  </option>\n",
        Triple(tree.gravity),
        Num(TIMESTEP)
    ));
    w(format_args!(
        "  <default>\n    <geom contype=\"0\" conaffinity=\"0\" rgba=\"0.6 0.65 0.7 1\"/>\n  \
         </default>\n  <worldbody>\n    <light pos=\"0 0 3\" dir=\"0 0 -1\"/>\n"
    ));
    let p = &tree.platform;
    w(format_args!(
        "    <body name=\"{}\" pos=\"{}\" quat=\"{}\">\n      <freejoint name=\"{}\"/>\n",
        p.name,
        Triple(p.origin),
        Quat(quaternion(&p.rotation)),
        p.name
    ));
    body_contents(&mut out, p, 6);
    for leg in &tree.legs {
        let mut parent = p;
        for (depth, body) in leg.bodies.iter().enumerate() {
            nested_body(&mut out, parent, body, 6 + 2 * depth);
            parent = body;
        }
        for depth in (0..leg.bodies.len()).rev() {
            out.push_str(&indent(6 + 2 * depth));
            out.push_str("</body>\n");
        }
    }
    out.push_str("    </body>\n  </worldbody>\n  <equality>\n");
    for leg in &tree.legs {
        let last = leg.bodies.last().expect("a leg has bodies");
        let _ = writeln!(
            out,
            "    <!-- {}: the loop is cut here, {} welded to the world where it is at home -->\n\
             \x20   <weld name=\"{}_closure\" body1=\"{}\" solref=\"{} {}\" solimp=\"{}\"/>",
            leg.name,
            last.name,
            leg.name,
            last.name,
            SOLREF[0],
            SOLREF[1],
            numbers(&SOLIMP)
        );
    }
    out.push_str("  </equality>\n  <actuator>\n");
    for leg in &tree.legs {
        let (b, j) = leg.actuated;
        let _ = writeln!(
            out,
            "    <motor name=\"{}\" joint=\"{}\" gear=\"1\"/>",
            leg.name, leg.bodies[b].joints[j].name
        );
    }
    let _ = write!(
        out,
        "  </actuator>\n  <keyframe>\n    <!-- At home, every joint at its reference: the loops \
         closed exactly. -->\n    <key name=\"home\" qpos=\"{}\"/>\n  </keyframe>\n</mujoco>\n",
        home_qpos(tree)
    );
    out
}

/// `<body>` of `body`, placed relative to `parent`, with its joints, inertia and shapes, left
/// open for its children.
fn nested_body(out: &mut String, parent: &Body, body: &Body, depth: usize) {
    let (pos, rot) = body.relative_to(parent);
    let _ = writeln!(
        out,
        "{}<body name=\"{}\" pos=\"{}\" quat=\"{}\">",
        indent(depth),
        body.name,
        Triple(pos),
        Quat(quaternion(&rot))
    );
    for joint in &body.joints {
        let _ = match joint.kind {
            JointKind::Hinge { axis } => writeln!(
                out,
                "{}<joint name=\"{}\" type=\"hinge\" axis=\"{}\"/>",
                indent(depth + 2),
                joint.name,
                Triple(axis)
            ),
            JointKind::Slide { axis } => writeln!(
                out,
                "{}<joint name=\"{}\" type=\"slide\" axis=\"{}\"/>",
                indent(depth + 2),
                joint.name,
                Triple(axis)
            ),
            JointKind::Ball => writeln!(
                out,
                "{}<joint name=\"{}\" type=\"ball\"/>",
                indent(depth + 2),
                joint.name
            ),
        };
    }
    body_contents(out, body, depth + 2);
}

/// A body's inertia and shapes.
fn body_contents(out: &mut String, body: &Body, depth: usize) {
    let (mass, com, inertia) = if body.mass > 0.0 {
        (body.mass, body.com, body.inertia)
    } else {
        let i = WELDED_INERTIA;
        (
            WELDED_MASS,
            [0.0; 3],
            [[i, 0.0, 0.0], [0.0, i, 0.0], [0.0, 0.0, i]],
        )
    };
    if body.mass <= 0.0 {
        let _ = writeln!(
            out,
            "{}<!-- No mass in the robot file: a nominal one, never felt (it is welded). -->",
            indent(depth)
        );
    }
    let _ = writeln!(
        out,
        "{}<inertial pos=\"{}\" mass=\"{}\" fullinertia=\"{}\"/>",
        indent(depth),
        Triple(com),
        Num(mass),
        FullInertia(inertia)
    );
    for shape in &body.shapes {
        let _ = match *shape {
            Shape::Capsule { from, to, radius } => writeln!(
                out,
                "{}<geom type=\"capsule\" fromto=\"{} {}\" size=\"{}\"/>",
                indent(depth),
                Triple(from),
                Triple(to),
                Num(radius)
            ),
            Shape::Box { centre, half_sizes } => writeln!(
                out,
                "{}<geom type=\"box\" pos=\"{}\" size=\"{}\"/>",
                indent(depth),
                Triple(centre),
                Triple(half_sizes)
            ),
            Shape::Sphere { centre, radius } => writeln!(
                out,
                "{}<geom type=\"sphere\" pos=\"{}\" size=\"{}\"/>",
                indent(depth),
                Triple(centre),
                Num(radius)
            ),
        };
    }
}

/// The joint coordinates at home, in MuJoCo's order (depth first): the platform's placement,
/// then each joint at its reference (a ball's identity quaternion, zero for the others).
fn home_qpos(tree: &BodyTree) -> String {
    let p = &tree.platform;
    let mut q: Vec<f64> = p.origin.to_vec();
    q.extend(quaternion(&p.rotation));
    for joint in tree
        .legs
        .iter()
        .flat_map(|l| &l.bodies)
        .flat_map(|b| &b.joints)
    {
        match joint.kind {
            JointKind::Ball => q.extend([1.0, 0.0, 0.0, 0.0]),
            JointKind::Hinge { .. } | JointKind::Slide { .. } => q.push(0.0),
        }
    }
    numbers(&q)
}

fn indent(depth: usize) -> String {
    " ".repeat(depth)
}

/// A quaternion `w x y z`.
struct Quat([f64; 4]);

impl core::fmt::Display for Quat {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&numbers(&self.0))
    }
}

/// MJCF's `fullinertia`: `ixx iyy izz ixy ixz iyz`.
struct FullInertia(Mat3);

impl core::fmt::Display for FullInertia {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let m = &self.0;
        let v: Vec3 = [m[0][0], m[1][1], m[2][2]];
        write!(f, "{} {}", Triple(v), Triple([m[0][1], m[0][2], m[1][2]]))
    }
}
