//! The C5 robot (the consistent model, the mechanism of eq 16) as a tree: per segment, from
//! the platform, the C5 joint's plates on two slides in the platform plane (body 2, turning
//! with the platform), the rod on the ball at `B_i` (body 1), and the actuator's guide on the
//! rod's slide along `n_i`, welded to the base.

use super::{
    add, dot, scale, sub, Body, BodyTree, Chain, Freedom, Joint, JointKind, Shape, IDENTITY,
};
use crate::{Robot, AXIS};
use alloc::format;
use alloc::string::ToString;
use alloc::vec;
use alloc::vec::Vec;

impl Robot {
    /// `A_i` of segment `i` (0-based), base frame: segments 1, 2 along x at `z = ±L`, 3, 4
    /// along y at `x = ±L`, 5, 6 along z at `y = ±L` (what eq 16 encodes).
    pub fn anchor(&self, i: usize) -> [f64; 3] {
        let l = if i.is_multiple_of(2) {
            self.half_spacing
        } else {
            -self.half_spacing
        };
        match AXIS[i] {
            0 => [0.0, 0.0, l],
            1 => [l, 0.0, 0.0],
            _ => [0.0, l, 0.0],
        }
    }

    /// The platform and its six segments as a tree at the home pose (the origin, level).
    ///
    /// The chapter's paper model is not a mechanism, so the tree is the consistent model's:
    /// body 2 (the plates and the ball's housing) keeps the platform's orientation and slides
    /// in its plane through `C` of normal `m_i`; body 1 (the rod) translates along `n_i` and
    /// turns on the ball at `B_i` relative to body 2. The actuator is the guide's slide along
    /// `-n_i` relative to the rod: a positive force pushes the rod along `+n_i`, as `Γ_i` does.
    pub fn body_tree(&self) -> BodyTree {
        let l = self.half_spacing;
        let mut platform = Body::at("platform".to_string(), IDENTITY, [0.0; 3]);
        platform.mass = self.platform.mass;
        platform.com = self.platform.com;
        platform.inertia = self.platform.inertia;
        platform.shapes.push(Shape::Box {
            centre: [0.0; 3],
            half_sizes: [0.5 * l; 3],
        });
        let legs = (0..6)
            .map(|i| {
                let segment = &self.segments[i];
                let k = AXIS[i];
                let n: [f64; 3] = core::array::from_fn(|j| if j == k { 1.0 } else { 0.0 });
                let a = self.anchor(i);
                // Eq 16 at the level home: m_i = n_i, so Q_i1 = n_i·(C - A_i).
                let q = dot(n, sub([0.0; 3], a));
                let b = add(a, scale(n, q));
                let name = |part: &str| format!("segment{}_{part}", i + 1);

                let mut plates = Body::at(name("joint"), IDENTITY, b);
                plates.joints = [(k + 1) % 3, (k + 2) % 3]
                    .into_iter()
                    .zip(["plate_u", "plate_v"])
                    .map(|(axis, part)| Joint {
                        name: name(part),
                        kind: JointKind::Slide {
                            axis: core::array::from_fn(|j| if j == axis { 1.0 } else { 0.0 }),
                        },
                    })
                    .collect();
                plates.mass = segment.joint.mass;
                plates.com = segment.joint.com;
                plates.inertia = segment.joint.inertia;
                let mut half = [0.2 * l; 3];
                half[k] = 0.03 * l;
                plates.shapes.push(Shape::Box {
                    centre: [0.0; 3],
                    half_sizes: half,
                });

                let mut rod = Body::at(name("rod"), IDENTITY, b);
                rod.joints.push(Joint {
                    name: name("ball"),
                    kind: JointKind::Ball,
                });
                rod.mass = segment.rod.mass;
                // Its centre of mass halfway along its stroke from A_i; the rod never turns,
                // so its inertia is never felt, and is written as the tables give it at Q_i1.
                rod.com = scale(n, -0.5 * q);
                rod.inertia = core::array::from_fn(|r| {
                    core::array::from_fn(|c| {
                        segment.rod.inertia[r][c]
                            + q * q * segment.rod.inertia_per_length_squared[r][c]
                    })
                });
                rod.shapes.push(Shape::Capsule {
                    from: [0.0; 3],
                    to: scale(n, -0.8 * l),
                    radius: 0.04 * l,
                });

                let mut guide = Body::at(name("guide"), IDENTITY, a);
                guide.joints.push(Joint {
                    name: name("stroke"),
                    kind: JointKind::Slide {
                        axis: scale(n, -1.0),
                    },
                });
                guide.shapes.push(Shape::Capsule {
                    from: scale(n, -0.4 * l),
                    to: scale(n, -l),
                    radius: 0.08 * l,
                });
                Chain::serial(
                    format!("segment{}", i + 1),
                    vec![plates, rod, guide],
                    (2, 0),
                )
            })
            .collect::<Vec<_>>();
        BodyTree {
            mechanism: crate::description::C5,
            gravity: self.gravity,
            home: [0.0; 6],
            platform,
            freedom: Freedom::Free,
            legs,
        }
    }
}
