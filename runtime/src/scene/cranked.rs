//! A leg whose motor turns a crank, as drawn: the motor's R joint at `A_i` on the base, the
//! crank to its elbow `E_i = A_i + c_i (cos θ_i h_i + sin θ_i k_i)`, and from there a rod (the
//! rotary hexapod's) or a parallelogram of two rods `w_i` apart along `r_i` (the Delta's) to the
//! platform's S joints. The angle is the generated inverse kinematics' (`θ_i = q_i - o_i`),
//! the elbow the robot file's crank at that angle.

use super::{plate, platform_axes, Joint, JointKind, Leg, Scene, BASE_AXES};
use crate::{Delta, Error, Pose, RusHexapod};
use alloc::vec::Vec;
use c5_robot::rus::RusLeg;

/// How thick the plates are drawn, in platform radii.
const PLATE_THICKNESS: f64 = 0.04;

/// `leg` with its crank at the actuator value `q` (the encoder's reading) and its rods ending
/// at `ball` (base frame): the midpoint of a parallelogram's two ball centres.
fn crank_leg(leg: &RusLeg, q: f64, ball: [f64; 3]) -> Leg {
    let joint = |kind, at| Joint {
        kind,
        at,
        over_limit: false,
    };
    let elbow = leg.elbow(q - leg.encoder_offset);
    let motor = joint(JointKind::Revolute, leg.base);
    match leg.rod.separation {
        None => Leg {
            path: alloc::vec![leg.base, elbow, ball],
            joints: alloc::vec![
                motor,
                joint(JointKind::Universal, elbow),
                joint(JointKind::Spherical, ball),
            ],
            over_stroke: false,
        },
        Some(w) => {
            let (r, _, _) = leg.axes();
            let side = |p: [f64; 3], s: f64| super::along(p, s * 0.5 * w, r);
            let [e_minus, e_plus, b_minus, b_plus] =
                [(elbow, -1.0), (elbow, 1.0), (ball, -1.0), (ball, 1.0)].map(|(p, s)| side(p, s));
            Leg {
                // Round the parallelogram: crank, half the elbow's bar, a rod, the platform's
                // side, the other rod, the bar's other half.
                path: alloc::vec![leg.base, elbow, e_minus, b_minus, b_plus, e_plus, elbow],
                joints: alloc::vec![
                    motor,
                    joint(JointKind::Universal, e_minus),
                    joint(JointKind::Universal, e_plus),
                    joint(JointKind::Spherical, b_minus),
                    joint(JointKind::Spherical, b_plus),
                ],
                over_stroke: false,
            }
        }
    }
}

/// The scene of cranked `legs` at actuator values `q`, their rods ending at `balls`, the
/// platform's origin at `centre` with `axes`: plates through the motors and through the S
/// joints. Neither robot file sets limits, so nothing is flagged.
fn scene(
    legs: &[RusLeg],
    q: &[f64],
    balls: &[[f64; 3]],
    centre: [f64; 3],
    axes: [[f64; 3]; 3],
) -> Scene {
    let legs: Vec<Leg> = (0..legs.len())
        .map(|i| crank_leg(&legs[i], q[i], balls[i]))
        .collect();
    let spheres: Vec<[f64; 3]> = legs
        .iter()
        .flat_map(|l| l.joints.iter().filter(|j| j.kind == JointKind::Spherical))
        .map(|j| j.at)
        .collect();
    let motors: Vec<[f64; 3]> = legs.iter().map(|l| l.joints[0].at).collect();
    let size = spheres
        .iter()
        .map(|b| {
            let d: [f64; 3] = core::array::from_fn(|k| b[k] - centre[k]);
            crate::math::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        })
        .fold(0.0, f64::max);
    Scene {
        platform: plate(&spheres, axes, PLATE_THICKNESS * size),
        base: plate(&motors, BASE_AXES, PLATE_THICKNESS * size),
        legs,
        centre,
        axes,
        size,
    }
}

/// The rotary hexapod's parts at `pose`: each crank at the angle the generated inverse
/// kinematics gives, its rod to `B_i = C + R p_i`.
///
/// # Errors
/// As [`RusHexapod::inverse_kinematics`]: a non-finite or singular pose, one out of reach.
pub(crate) fn rus_hexapod(robot: &RusHexapod, pose: &Pose) -> Result<Scene, Error> {
    let (q, p) = robot.inverse_kinematics(pose)?;
    let c = pose.center;
    let balls: Vec<[f64; 3]> = p
        .iter()
        .map(|p| core::array::from_fn(|k| c[k] - p[k]))
        .collect();
    Ok(scene(
        &robot.robot().legs,
        &q,
        &balls,
        c,
        platform_axes(pose),
    ))
}

/// The Delta's parts at `position`: each upper arm at the angle the generated inverse
/// kinematics gives, its parallelogram to `C + p_i ± (w_i/2) r_i`; the platform level.
///
/// # Errors
/// As [`Delta::inverse_kinematics`].
pub(crate) fn delta(robot: &Delta, position: &[f64; 3]) -> Result<Scene, Error> {
    let q = robot.inverse_kinematics(position)?;
    let arms = &robot.robot().arms;
    let balls: Vec<[f64; 3]> = arms
        .iter()
        .map(|a| core::array::from_fn(|k| position[k] + a.platform[k]))
        .collect();
    Ok(scene(arms, &q, &balls, *position, BASE_AXES))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
        let d: [f64; 3] = core::array::from_fn(|k| a[k] - b[k]);
        crate::math::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    }

    /// Every drawn body has its length: each crank `c_i` from its motor, each rod `L_i` from its
    /// elbow to its ball, a parallelogram's sides parallel and equal; for every leg of the
    /// example rotary hexapod and Delta at poses about home.
    #[test]
    fn cranks_and_rods_are_drawn_at_their_lengths() {
        let hexapod = RusHexapod::new(c5_robot::RusHexapod::example()).unwrap();
        let delta = Delta::new(c5_robot::Delta::example()).unwrap();
        for k in 0..12 {
            let s = |a: f64| 0.02 * (a * (f64::from(k) + 1.0)).sin();
            let mut x = hexapod.home().to_array();
            for (j, v) in x.iter_mut().enumerate() {
                *v += s(0.7 + 0.61 * j as f64) * if j < 3 { 4.0 } else { 1.0 };
            }
            let drawn = hexapod.scene(&Pose::from_array(x)).unwrap();
            assert_eq!(drawn.legs.len(), 6);
            for (leg, description) in drawn.legs.iter().zip(&hexapod.robot().legs) {
                let [motor, elbow, ball] = [0, 1, 2].map(|j| leg.joints[j].at);
                assert_eq!(leg.path, [motor, elbow, ball]);
                assert!((distance(motor, elbow) - description.crank.length).abs() < 1e-12);
                assert!((distance(elbow, ball) - description.rod.length).abs() < 1e-12);
            }
            let home = delta.home();
            let position = core::array::from_fn(|j| home[j] + 3.0 * s(1.3 + j as f64));
            let drawn = delta.scene(&position).unwrap();
            assert_eq!(drawn.legs.len(), 3);
            for (leg, arm) in drawn.legs.iter().zip(&delta.robot().arms) {
                let [motor, e_minus, e_plus, b_minus, b_plus] =
                    [0, 1, 2, 3, 4].map(|j| leg.joints[j].at);
                let elbow = leg.path[1];
                assert!((distance(motor, elbow) - arm.crank.length).abs() < 1e-12);
                assert!((distance(e_minus, b_minus) - arm.rod.length).abs() < 1e-12);
                assert!((distance(e_plus, b_plus) - arm.rod.length).abs() < 1e-12);
                let w = arm.rod.separation.unwrap();
                assert!((distance(e_minus, e_plus) - w).abs() < 1e-12);
                assert!((distance(b_minus, b_plus) - w).abs() < 1e-12);
            }
        }
    }

    /// The plates close: every triangle's vertices exist, none degenerate; the Delta's base is
    /// the triangle of its three motors.
    #[test]
    fn the_plates_are_well_formed() {
        let delta = Delta::new(c5_robot::Delta::example()).unwrap();
        let drawn = delta.scene(&delta.home()).unwrap();
        assert_eq!(drawn.base.triangles.len(), 4 * 3);
        for solid in [&drawn.platform, &drawn.base] {
            for t in &solid.triangles {
                assert!(t.iter().all(|&v| v < solid.vertices.len()));
                assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
            }
        }
    }
}
