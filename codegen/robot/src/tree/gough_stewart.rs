//! The Gough-Stewart platform as a tree: per leg, from the platform, the rod on its S joint
//! (a ball at `B_i`), the cylinder on the actuator's prismatic joint, and the U joint's yoke on
//! its two hinges at `A_i`, welded to the base.

use super::{
    columns, cross, diagonal, norm, scale, sub, times, transpose_times, unit, Body, BodyTree,
    Chain, Freedom, Joint, JointKind, Shape,
};
use crate::GoughStewart;
use alloc::format;
use alloc::vec;
use alloc::vec::Vec;

impl GoughStewart {
    /// The platform and its six legs as a tree at the home pose ([`GoughStewart::home`]).
    ///
    /// Each leg's bodies are placed in its leg frame (`z' = u_i`, `y' ∝ u_i × a_i`), so the
    /// rod's and the cylinder's inertias are the description's `diag(It, It, Ia)`. The
    /// actuator is the cylinder's slide along `-z'` relative to the rod: a positive force
    /// extends the leg, as `Γ_i` does.
    pub fn body_tree(&self) -> BodyTree {
        let home = self.home();
        let (platform, r0, c0) = self
            .platform
            .root_at(&home, self.legs.iter().map(|l| l.platform));
        let legs = self
            .legs
            .iter()
            .enumerate()
            .map(|(i, leg)| {
                let b = super::add(c0, times(&r0, leg.platform));
                let d = sub(b, leg.base);
                let length = norm(d);
                let u = scale(d, 1.0 / length);
                let a = unit(leg.u_axis);
                let y = unit(cross(u, a));
                let frame = columns(cross(y, u), y, u);
                let radius = 0.04 * length;
                let name = |part: &str| format!("leg{}_{part}", i + 1);

                let mut rod = Body::at(name("rod"), frame, b);
                rod.joints.push(Joint {
                    name: name("ball"),
                    kind: JointKind::Ball,
                });
                rod.mass = leg.rod.mass;
                rod.com = [0.0, 0.0, -leg.rod.com];
                rod.inertia = diagonal(leg.rod.inertia);
                rod.shapes.push(Shape::Capsule {
                    from: [0.0; 3],
                    to: [0.0, 0.0, -0.55 * length],
                    radius: 0.6 * radius,
                });

                let mut cylinder = Body::at(name("cylinder"), frame, leg.base);
                cylinder.joints.push(Joint {
                    name: name("stroke"),
                    kind: JointKind::Slide {
                        axis: [0.0, 0.0, -1.0],
                    },
                });
                cylinder.mass = leg.cylinder.mass;
                cylinder.com = [0.0, 0.0, leg.cylinder.com];
                cylinder.inertia = diagonal(leg.cylinder.inertia);
                cylinder.shapes.push(Shape::Capsule {
                    from: [0.0; 3],
                    to: [0.0, 0.0, 0.55 * length],
                    radius,
                });

                // The U joint: first about y' (fixed in the cylinder), then about a_i (fixed in
                // the base), read from the cylinder towards the base.
                let mut yoke = Body::at(name("base"), frame, leg.base);
                yoke.joints = vec![
                    Joint {
                        name: name("u2"),
                        kind: JointKind::Hinge {
                            axis: [0.0, 1.0, 0.0],
                        },
                    },
                    Joint {
                        name: name("u1"),
                        kind: JointKind::Hinge {
                            axis: transpose_times(&frame, a),
                        },
                    },
                ];
                yoke.shapes.push(Shape::Sphere {
                    centre: [0.0; 3],
                    radius: 1.5 * radius,
                });
                Chain::serial(format!("leg{}", i + 1), vec![rod, cylinder, yoke], (1, 0))
            })
            .collect::<Vec<_>>();
        BodyTree {
            mechanism: crate::description::GOUGH_STEWART,
            gravity: self.gravity,
            home,
            platform,
            freedom: Freedom::Free,
            legs,
        }
    }
}
