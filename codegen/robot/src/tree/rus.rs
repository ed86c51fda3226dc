//! The rotary hexapod and the Delta as trees: per leg, from the platform, the rod on its ball,
//! the crank on the rod's U joint (at the crank's tip), and the motor's housing on the
//! actuated hinge about `-r_i` at `A_i`, welded to the base. A Delta's second rod hangs from
//! the crank on its own U joint and holds the platform by a ball, closed as a loop of its own.

use super::{
    add, columns, cross, diagonal, norm, scale, sub, transpose_times, unit, Body, BodyTree, Chain,
    Closure, Freedom, Joint, JointKind, Shape, Vec3, IDENTITY,
};
use crate::{Delta, RusHexapod, RusLeg};
use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

impl RusHexapod {
    /// The platform and its six legs as a tree at the home pose ([`RusHexapod::home`]), for a
    /// valid description.
    ///
    /// The rod's frame is `z' = u_i`, `y' ∝ u_i × r_i`, the crank's `x''` along the crank,
    /// `z'' = r_i`: their inertias are the file's diagonals. The actuator is the motor's hinge,
    /// about `-r_i` from the crank to the housing: a positive torque turns the crank positively
    /// about `r_i`, as `Γ_i` does.
    pub fn body_tree(&self) -> BodyTree {
        let home = self.home().unwrap_or([0.0; 6]);
        let (platform, _, _) = self
            .platform
            .root_at(&home, self.legs.iter().map(|l| l.platform));
        let legs = self
            .legs
            .iter()
            .enumerate()
            .map(|(i, leg)| leg_chain(&format!("leg{}", i + 1), leg, self.ball(i, &home), &[0.0]))
            .collect();
        BodyTree {
            mechanism: crate::description::RUS_HEXAPOD,
            gravity: self.gravity,
            home,
            platform,
            freedom: Freedom::Free,
            legs,
        }
    }
}

impl Delta {
    /// The platform (translating) and its three arms as a tree at the home position, for a
    /// valid description: each arm as the rotary hexapod's leg, its parallelogram's first rod
    /// in the chain, the second hanging from the crank and holding the platform by its ball.
    pub fn body_tree(&self) -> BodyTree {
        let c0 = self.home().unwrap_or([0.0; 3]);
        let size = self
            .arms
            .iter()
            .map(|a| norm(a.platform))
            .fold(0.0, f64::max);
        let mut platform = Body::at("platform".to_string(), IDENTITY, c0);
        platform.mass = self.platform.mass;
        platform.com = self.platform.centre_of_mass;
        platform.shapes.push(Shape::Box {
            centre: [0.0; 3],
            half_sizes: [size, size, 0.1 * size],
        });
        let legs = self
            .arms
            .iter()
            .enumerate()
            .map(|(i, arm)| {
                let half = 0.5 * arm.rod.separation.unwrap_or(0.0);
                leg_chain(
                    &format!("arm{}", i + 1),
                    arm,
                    add(c0, arm.platform),
                    &[half, -half],
                )
            })
            .collect();
        BodyTree {
            mechanism: crate::description::DELTA,
            gravity: self.gravity,
            home: [0.0, 0.0, 0.0, c0[0], c0[1], c0[2]],
            platform,
            freedom: Freedom::Translations,
            legs,
        }
    }
}

/// One R-U-S leg reaching `ball` (base frame, at home), a rod at each of `offsets` along
/// `r_i` from the crank's tip and the ball: the first rod in the chain, the others hanging from
/// the crank and closed on the platform by their balls.
fn leg_chain(name: &str, leg: &RusLeg, ball: Vec3, offsets: &[f64]) -> Chain {
    let (r, h, k) = leg.axes();
    let theta = leg.crank_angle(ball).unwrap_or(0.0);
    let (s, c) = crate::math::sin_cos(theta);
    let along = add(scale(h, c), scale(k, s));
    let crank_frame = columns(along, cross(r, along), r);
    let elbow = leg.elbow(theta);
    let u = unit(sub(ball, elbow));
    let y = unit(cross(u, r));
    let rod_frame = columns(cross(y, u), y, u);
    let part = |p: &str| format!("{name}_{p}");
    let suffix = |j: usize| -> String {
        if offsets.len() == 1 {
            String::new()
        } else {
            format!("_{}", ["a", "b"][j.min(1)])
        }
    };
    let length = leg.rod.length;
    let rod = |j: usize, origin: Vec3, joints: Vec<Joint>, tip: Vec3| {
        let mut body = Body::at(part(&format!("rod{}", suffix(j))), rod_frame, origin);
        let start = add(elbow, scale(r, offsets[j]));
        body.joints = joints;
        body.mass = leg.rod.mass;
        body.com = transpose_times(&rod_frame, sub(add(start, scale(u, leg.rod.com)), origin));
        body.inertia = diagonal([leg.rod.inertia[0], leg.rod.inertia[1], leg.rod.inertia[2]]);
        body.shapes.push(Shape::Capsule {
            from: transpose_times(&rod_frame, sub(start, origin)),
            to: tip,
            radius: 0.025 * length,
        });
        body
    };
    let first_ball = add(ball, scale(r, offsets[0]));
    let first_elbow = add(elbow, scale(r, offsets[0]));
    let hinge = |n: &str, axis: Vec3| Joint {
        name: part(n),
        kind: JointKind::Hinge { axis },
    };
    let rod_a = rod(
        0,
        first_ball,
        vec![Joint {
            name: part(&format!("ball{}", suffix(0))),
            kind: JointKind::Ball,
        }],
        [0.0; 3],
    );

    let mut crank = Body::at(part("crank"), crank_frame, first_elbow);
    crank.joints = vec![
        hinge(
            &format!("u2{}", suffix(0)),
            transpose_times(&crank_frame, y),
        ),
        hinge(&format!("u1{}", suffix(0)), [0.0, 0.0, 1.0]),
    ];
    crank.mass = leg.crank.mass;
    crank.com = transpose_times(
        &crank_frame,
        sub(add(leg.base, scale(along, leg.crank.com)), first_elbow),
    );
    crank.inertia = diagonal(leg.crank.inertia);
    crank.shapes.push(Shape::Capsule {
        from: transpose_times(&crank_frame, sub(leg.base, first_elbow)),
        to: scale(transpose_times(&crank_frame, r), -offsets[0]),
        radius: 0.08 * leg.crank.length,
    });

    let mut motor = Body::at(part("motor"), crank_frame, leg.base);
    motor.joints = vec![hinge("angle", [0.0, 0.0, -1.0])];
    motor.shapes.push(Shape::Capsule {
        from: [0.0, 0.0, -0.15 * leg.crank.length],
        to: [0.0, 0.0, 0.15 * leg.crank.length],
        radius: 0.15 * leg.crank.length,
    });

    let mut bodies = vec![rod_a, crank, motor];
    let mut parents = vec![None, Some(0), Some(1)];
    let mut closures = vec![Closure::Weld { body: 2 }];
    for (j, &offset) in offsets.iter().enumerate().skip(1) {
        let start = add(elbow, scale(r, offset));
        let end = add(ball, scale(r, offset));
        let tip = transpose_times(&rod_frame, sub(end, start));
        let joints = vec![
            hinge(&format!("u1{}", suffix(j)), transpose_times(&rod_frame, r)),
            hinge(&format!("u2{}", suffix(j)), [0.0, 1.0, 0.0]),
        ];
        closures.push(Closure::Ball {
            body: bodies.len(),
            anchor: tip,
        });
        bodies.push(rod(j, start, joints, tip));
        parents.push(Some(1));
    }
    Chain {
        name: name.to_string(),
        bodies,
        parents,
        closures,
        actuated: (2, 0),
    }
}
