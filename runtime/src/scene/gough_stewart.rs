//! A Gough-Stewart platform as drawn: each leg from its U joint `A_i` on the base to its S
//! joint `B_i` on the platform, the base and the platform as plates through their joints.

use super::{plate, platform_axes, Joint, JointKind, Leg, Scene, BASE_AXES};
use crate::{Error, GoughStewart, Pose};
use alloc::vec::Vec;

/// The robot's parts at `pose` (`B_i = C - p_i` from the generated inverse kinematics), each
/// leg and joint flagged where the robot file's stroke or joint-cone limit is crossed.
///
/// # Errors
/// A non-finite pose, or a U joint at its singularity.
pub(crate) fn scene(robot: &GoughStewart, pose: &Pose) -> Result<Scene, Error> {
    let (_, p) = robot.inverse_kinematics(pose)?;
    let margins = robot.limit_margins(pose)?;
    let c = pose.center;
    let legs: Vec<Leg> = (0..6)
        .map(|i| {
            let base = Joint {
                kind: JointKind::Universal,
                at: robot.robot().legs[i].base,
                over_limit: margins.u_joint[i].0 < 0.0,
            };
            let platform = Joint {
                kind: JointKind::Spherical,
                at: core::array::from_fn(|k| c[k] - p[i][k]),
                over_limit: margins.s_joint[i].0 < 0.0,
            };
            Leg::straight(base, platform, margins.stroke[i].0 < 0.0)
        })
        .collect();
    let axes = platform_axes(pose);
    let size = platform_radius(robot);
    let points = |k: usize| -> Vec<[f64; 3]> { legs.iter().map(|l| l.joints[k].at).collect() };
    Ok(Scene {
        platform: plate(&points(1), axes, 0.04 * size),
        base: plate(&points(0), BASE_AXES, 0.04 * size),
        legs,
        centre: c,
        axes,
        size,
    })
}

/// The largest distance of an S joint from the platform's origin (m).
fn platform_radius(robot: &GoughStewart) -> f64 {
    robot
        .robot()
        .legs
        .iter()
        .map(|l| crate::math::sqrt(l.platform.iter().map(|x| x * x).sum()))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use c5_robot::gough_stewart::{rotation, GoughStewart as Description};

    /// Each S joint is at `C + R b_i` of the description, and each leg's length plus its
    /// encoder's offset is the actuator position the kernels give.
    #[test]
    fn each_joint_is_where_the_kinematics_puts_it() {
        let description = Description::example();
        let robot = GoughStewart::new(description).unwrap();
        let home = robot.home().to_array();
        for k in 0..40 {
            let s = |a: f64| (a * (f64::from(k) + 1.0)).sin();
            let mut x = home;
            for (j, v) in x.iter_mut().enumerate() {
                *v += [0.2, 0.2, 0.3, 0.05, 0.05, 0.04][j] * s(0.7 + 0.61 * j as f64);
            }
            let pose = Pose::from_array(x);
            let scene = robot.scene(&pose).unwrap();
            let q = robot.inverse_kinematics(&pose).unwrap().0;
            let r = rotation(&x);
            for (i, leg) in scene.legs.iter().enumerate() {
                let b_i = description.legs[i].platform;
                for c in 0..3 {
                    let expected = x[3 + c] + (0..3).map(|j| r[c][j] * b_i[j]).sum::<f64>();
                    assert!((leg.platform_joint().at[c] - expected).abs() < 1e-12);
                }
                let d: [f64; 3] =
                    core::array::from_fn(|c| leg.joints[1].at[c] - leg.joints[0].at[c]);
                let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let offset = description.legs[i].encoder_offset;
                assert!((length + offset - q[i]).abs() < 1e-12, "leg {i}");
                assert_eq!(leg.joints[0].at, description.legs[i].base);
                assert_eq!(leg.path, [leg.joints[0].at, leg.joints[1].at]);
            }
        }
    }

    /// The plates are closed solids: every triangle's vertices exist, none is degenerate.
    #[test]
    fn the_plates_are_well_formed() {
        let robot = GoughStewart::new(Description::example()).unwrap();
        let scene = robot.scene(&robot.home()).unwrap();
        for solid in [&scene.platform, &scene.base] {
            assert_eq!(solid.triangles.len(), 24);
            for t in &solid.triangles {
                assert!(t.iter().all(|&v| v < solid.vertices.len()));
                assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
            }
        }
    }
}
