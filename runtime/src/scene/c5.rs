//! The C5 joint parallel robot as drawn: each rod slides along its fixed axis `n_i` from an
//! actuator on the base and carries its ball to `B_i = A_i + Q_i1 n_i`; the ball rides on a
//! plate of the platform centred at the platform's copy of `A_i`, in the plane of normal
//! `m_i = R e_k` through `C` (eq 16: `m_i·(B_i - C) = 0`).

use super::{along, platform_axes, Joint, JointKind, Leg, Scene, Solid};
use crate::{Error, Pose, C5};
use c5_robot::AXIS;

/// How far behind `A_i` an actuator's body sits, in half-spacings: the rods push along `+n_i`
/// (README, Conventions), so the actuators are on the `-n_i` side.
const ACTUATOR_SETBACK: f64 = 2.5;
/// A plate's half-width where the robot file sets no plate travel, in half-spacings.
const PLATE_HALF_WIDTH: f64 = 0.5;

/// `A_i`, segment `i` (0-based), for half-spacing `l` (README, Conventions: segments 1, 2
/// along x at `z = ±L`, 3, 4 along y at `x = ±L`, 5, 6 along z at `y = ±L`).
pub(crate) fn anchor(l: f64, i: usize) -> [f64; 3] {
    let s = if i.is_multiple_of(2) { l } else { -l };
    match AXIS[i] {
        0 => [0.0, 0.0, s],
        1 => [s, 0.0, 0.0],
        _ => [0.0, s, 0.0],
    }
}

/// `n_i = e_k`.
pub(crate) fn axis(i: usize) -> [f64; 3] {
    core::array::from_fn(|k| if k == AXIS[i] { 1.0 } else { 0.0 })
}

impl C5 {
    /// The robot's parts at `pose` (eq 16's `Q_i1` from the generated kernel), each leg and
    /// ball flagged where the robot file's stroke, plate-travel or tilt limit is crossed.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn scene(&self, pose: &Pose) -> Result<Scene, Error> {
        let l = self.robot().half_spacing;
        let (q, _) = self.inverse_kinematics(pose)?;
        let margins = self.limit_margins(pose)?;
        let legs = (0..6)
            .map(|i| {
                let (a, n) = (anchor(l, i), axis(i));
                let base = Joint {
                    kind: JointKind::Prismatic,
                    at: along(a, -ACTUATOR_SETBACK * l, n),
                    over_limit: false,
                };
                let ball = Joint {
                    kind: JointKind::BallOnPlates,
                    at: along(a, q[i], n),
                    over_limit: margins.tilt[i] < 0.0 || margins.plate[i].iter().any(|&m| m < 0.0),
                };
                Leg::straight(base, ball, margins.stroke[i] < 0.0)
            })
            .collect();
        let axes = platform_axes(pose);
        let travel = self
            .robot()
            .limits
            .plate_travel
            .unwrap_or([PLATE_HALF_WIDTH * l; 2]);
        Ok(Scene {
            legs,
            platform: platform(l, pose.center, axes, travel),
            base: actuators(l),
            centre: pose.center,
            axes,
            size: l,
        })
    }
}

/// A hub at `C`, a strut to each plate, and the six plates, each centred at `C + R A_i` in
/// the plane of normal `R e_k` with half-widths `travel` along its in-plane axes.
fn platform(l: f64, centre: [f64; 3], axes: [[f64; 3]; 3], travel: [f64; 2]) -> Solid {
    let mut solid = Solid::default();
    let thin = 0.03 * l;
    solid.cuboid(centre, axes, [0.15 * l; 3]);
    for (i, &normal) in AXIS.iter().enumerate() {
        let a = anchor(l, i);
        let plate_centre: [f64; 3] =
            core::array::from_fn(|k| centre[k] + (0..3).map(|j| axes[j][k] * a[j]).sum::<f64>());
        let mid: [f64; 3] = core::array::from_fn(|k| 0.5 * (centre[k] + plate_centre[k]));
        let strut_axis = (0..3).find(|&j| a[j] != 0.0).unwrap_or(0);
        let mut half = [thin; 3];
        half[strut_axis] = 0.5 * l;
        solid.cuboid(mid, axes, half);
        let mut half = [0.0; 3];
        let mut in_plane = travel.iter();
        for (j, h) in half.iter_mut().enumerate() {
            *h = if j == normal {
                0.5 * thin
            } else {
                *in_plane.next().unwrap_or(&thin)
            };
        }
        solid.cuboid(plate_centre, axes, half);
    }
    solid
}

/// Each actuator's body on the base, a box on the rod's axis behind `A_i`.
fn actuators(l: f64) -> Solid {
    let mut solid = Solid::default();
    let base_axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for i in 0..6 {
        let (a, n) = (anchor(l, i), axis(i));
        let mut half = [0.08 * l; 3];
        half[AXIS[i]] = 0.3 * l;
        solid.cuboid(along(a, -(ACTUATOR_SETBACK + 0.3) * l, n), base_axes, half);
    }
    solid
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Robot;

    fn poses() -> impl Iterator<Item = Pose> {
        (0..40).map(|k| {
            let s = |a: f64| (a * (k as f64 + 1.0)).sin();
            Pose::from_array([
                0.4 * s(0.7),
                0.35 * s(1.3),
                0.5 * s(2.1),
                0.05 * s(0.9),
                0.05 * s(1.7),
                0.05 * s(2.9),
            ])
        })
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// Each ball lies in its plates' plane through `C` (eq 16, with `R` taken afresh from the
    /// pose), on its actuator's axis, and at `C - P_i2` of the generated kernel.
    #[test]
    fn each_ball_is_where_eq_16_puts_it() {
        let robot = C5::new(Robot::default()).unwrap();
        let l = robot.robot().half_spacing;
        for pose in poses() {
            let scene = robot.scene(&pose).unwrap();
            let (_, p) = robot.inverse_kinematics(&pose).unwrap();
            for (i, leg) in scene.legs.iter().enumerate() {
                let b = leg.platform_joint().at;
                let from_c: [f64; 3] = core::array::from_fn(|k| b[k] - pose.center[k]);
                assert!(
                    dot(scene.axes[AXIS[i]], from_c).abs() < 1e-12,
                    "{i}: off its plates"
                );
                let a = anchor(l, i);
                for k in (0..3).filter(|&k| k != AXIS[i]) {
                    assert!((b[k] - a[k]).abs() < 1e-15, "{i}: off its axis");
                }
                for k in 0..3 {
                    assert!((b[k] - (pose.center[k] - p[i][k])).abs() < 1e-12);
                }
                assert_eq!(leg.platform_joint().kind, JointKind::BallOnPlates);
                let behind = dot(axis(i), leg.joints[0].at) - dot(axis(i), a);
                assert!((behind + ACTUATOR_SETBACK * l).abs() < 1e-15);
            }
        }
    }

    /// A stroke limit crossed flags that leg, and only where its margin is negative.
    #[test]
    fn legs_past_their_stroke_are_flagged() {
        let mut description = Robot::default();
        description.limits.stroke = Some([[-0.01, 0.01]; 6]);
        let robot = C5::new(description).unwrap();
        let mut flagged = 0;
        for pose in poses() {
            let scene = robot.scene(&pose).unwrap();
            let margins = robot.limit_margins(&pose).unwrap();
            for i in 0..6 {
                assert_eq!(scene.legs[i].over_stroke, margins.stroke[i] < 0.0);
                flagged += usize::from(scene.legs[i].over_stroke);
            }
        }
        assert!(flagged > 0 && flagged < 240, "{flagged}");
    }
}
