//! MJCF, the format of MuJoCo, which Pinocchio's MJCF reader also loads with its loop closures.
//!
//! The layout both engines load (measured with Pinocchio 4.1 and MuJoCo): one root body, the
//! platform, with a `freejoint` (Pinocchio reads only the first body tree under `worldbody`,
//! and MuJoCo allows a `freejoint` only on a top-level body), or three slides where it only
//! translates; each leg nested under it; each cut loop closed by `equality/weld` (a body on
//! the world) or `equality/connect` (a ball on the platform) at the bodies' poses in the
//! reference configuration, which is the assembled robot at home. Bodies with several joints
//! compose them in order, as Pinocchio's composite joint does.

use super::{header, numbers, Num, Triple};
use crate::tree::{
    quaternion, Body, BodyTree, Chain, Closure, Freedom, JointKind, Mat3, Shape, Vec3, IDENTITY,
};
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
    let _ = write!(
        out,
        "<!-- {} -->\n<mujoco model=\"{}\">\n  <compiler angle=\"radian\" \
         autolimits=\"true\"/>\n  <!-- The loops are closed by soft equality constraints: \
         MuJoCo lets each open in proportion to the force it carries, by solref {} (the \
         stiffest for the timestep) and solimp {} (the hardest MuJoCo takes); RK4 at {} s keeps \
         them closed to the tolerance docs/export.md states. Contacts are off: the legs pass \
         through each other as the kernels' do. -->\n  <option gravity=\"{}\" \
         timestep=\"{}\" integrator=\"RK4\">\n    <flag contact=\"disable\"/>\n  </option>\n  \
         <default>\n    <geom contype=\"0\" conaffinity=\"0\" rgba=\"0.6 0.65 0.7 1\"/>\n  \
         </default>\n  <worldbody>\n    <light pos=\"0 0 3\" dir=\"0 0 -1\"/>\n",
        header(tree, super::Format::Mjcf),
        tree.mechanism,
        numbers(&SOLREF),
        numbers(&SOLIMP),
        Num(TIMESTEP),
        Triple(tree.gravity),
        Num(TIMESTEP)
    );
    let p = &tree.platform;
    let _ = writeln!(
        out,
        "    <body name=\"{}\" pos=\"{}\" quat=\"{}\">",
        p.name,
        Triple(p.origin),
        Quat(quaternion(&p.rotation))
    );
    match tree.freedom {
        Freedom::Free => {
            let _ = writeln!(out, "      <freejoint name=\"{}\"/>", p.name);
        }
        Freedom::Translations => {
            for (axis, name) in IDENTITY.iter().zip(["x", "y", "z"]) {
                let _ = writeln!(
                    out,
                    "      <joint name=\"{}_{name}\" type=\"slide\" axis=\"{}\"/>",
                    p.name,
                    Triple(*axis)
                );
            }
        }
    }
    body_contents(&mut out, p, 6);
    for leg in &tree.legs {
        for child in leg.children(None) {
            nested_body(&mut out, leg, p, child, 6);
        }
    }
    out.push_str("    </body>\n  </worldbody>\n  <equality>\n");
    let soft = alloc::format!(
        "solref=\"{}\" solimp=\"{}\"",
        numbers(&SOLREF),
        numbers(&SOLIMP)
    );
    for leg in &tree.legs {
        for closure in &leg.closures {
            let _ = match *closure {
                Closure::Weld { body } => writeln!(
                    out,
                    "    <!-- {}: a loop is cut here, {} welded to the world where it is at \
                     home -->\n    <weld name=\"{1}_closure\" body1=\"{1}\" {soft}/>",
                    leg.name, leg.bodies[body].name,
                ),
                Closure::Ball { body, anchor } => writeln!(
                    out,
                    "    <!-- {}: a loop is cut here, {} holding the platform by its ball -->\n    \
                     <connect name=\"{1}_closure\" body1=\"{1}\" body2=\"{}\" anchor=\"{}\" \
                     {soft}/>",
                    leg.name,
                    leg.bodies[body].name,
                    p.name,
                    Triple(anchor),
                ),
            };
        }
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

/// `<body>` of `leg.bodies[k]`, placed relative to its parent, with its joints, inertia,
/// shapes and children.
fn nested_body(out: &mut String, leg: &Chain, platform: &Body, k: usize, depth: usize) {
    let body = &leg.bodies[k];
    let (pos, rot) = body.relative_to(leg.parent(k, platform));
    let _ = writeln!(
        out,
        "{}<body name=\"{}\" pos=\"{}\" quat=\"{}\">",
        indent(depth),
        body.name,
        Triple(pos),
        Quat(quaternion(&rot))
    );
    for joint in &body.joints {
        let (kind, axis) = match joint.kind {
            JointKind::Hinge { axis } => ("hinge", Some(axis)),
            JointKind::Slide { axis } => ("slide", Some(axis)),
            JointKind::Ball => ("ball", None),
        };
        let axis = axis.map_or(String::new(), |a| alloc::format!(" axis=\"{}\"", Triple(a)));
        let _ = writeln!(
            out,
            "{}<joint name=\"{}\" type=\"{kind}\"{axis}/>",
            indent(depth + 2),
            joint.name
        );
    }
    body_contents(out, body, depth + 2);
    for child in leg.children(Some(k)) {
        nested_body(out, leg, platform, child, depth + 2);
    }
    let _ = writeln!(out, "{}</body>", indent(depth));
}

/// A body's inertia and shapes.
fn body_contents(out: &mut String, body: &Body, depth: usize) {
    let no_inertia = body.inertia.iter().flatten().all(|&x| x == 0.0);
    let (mass, com, inertia) = if body.mass > 0.0 && !no_inertia {
        (body.mass, body.com, body.inertia)
    } else if body.mass > 0.0 {
        let _ = writeln!(
            out,
            "{}<!-- No inertia in the robot file: a nominal one, never felt (it only \
             translates). -->",
            indent(depth)
        );
        let i = WELDED_INERTIA;
        (
            body.mass,
            body.com,
            [[i, 0.0, 0.0], [0.0, i, 0.0], [0.0, 0.0, i]],
        )
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

/// The joint coordinates at home, in MuJoCo's order (depth first): the platform's placement
/// (a translating platform's slides at zero), then each joint at its reference (a ball's
/// identity quaternion, zero for the others).
fn home_qpos(tree: &BodyTree) -> String {
    fn visit(leg: &Chain, parent: Option<usize>, q: &mut Vec<f64>) {
        for k in leg.children(parent) {
            for joint in &leg.bodies[k].joints {
                match joint.kind {
                    JointKind::Ball => q.extend([1.0, 0.0, 0.0, 0.0]),
                    JointKind::Hinge { .. } | JointKind::Slide { .. } => q.push(0.0),
                }
            }
            visit(leg, Some(k), q);
        }
    }
    let p = &tree.platform;
    let mut q: Vec<f64> = match tree.freedom {
        Freedom::Free => p
            .origin
            .into_iter()
            .chain(quaternion(&p.rotation))
            .collect(),
        Freedom::Translations => alloc::vec![0.0; 3],
    };
    for leg in &tree.legs {
        visit(leg, None, &mut q);
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
