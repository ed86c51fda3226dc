//! The robot's limits: the margins against their definitions written with the matrix-form
//! reference (the ball `B_i = A_i + Q_i1 n_i`, its offset `Rᵀ (B_i - C) - A_i` on the plate, the
//! tilt `arccos(n_i · R e_k)`), and each limit just inside (accepted) and just outside
//! (refused, naming the limit and the actuator), at every actuator.

use crate::support;

use c5_runtime::reference::{self as r, consistent as rc};
use c5_runtime::ParallelRobot;
use c5_runtime::{Error, Limit, Limits, Pose, Robot, C5};
use nalgebra::Vector3;
use support::*;

/// The quantities the limits bound, from the reference: `Q_i1`, the plate offsets along the
/// plate's two axes, the tilts (rad).
fn reference(robot: &Robot, pose: &Pose) -> ([f64; 6], [[f64; 2]; 6], [f64; 6]) {
    let l = robot.half_spacing;
    let q = rc::lengths(l, pose);
    let rot = r::rotation(pose);
    let c = Vector3::from(pose.center);
    let mut plate = [[0.0; 2]; 6];
    let mut tilt = [0.0; 6];
    for i in 0..6 {
        let b = r::anchor(l, i) + q[i] * r::axis(i);
        let offset = rot.transpose() * (b - c) - r::anchor(l, i);
        let axis = [0, 0, 1, 1, 2, 2][i];
        let others: Vec<usize> = (0..3).filter(|&a| a != axis).collect();
        plate[i] = [offset[others[0]], offset[others[1]]];
        tilt[i] = r::axis(i).dot(&rot.column(axis)).clamp(-1.0, 1.0).acos();
    }
    (q, plate, tilt)
}

fn with_limits(limits: Limits) -> C5 {
    C5::new(Robot {
        limits,
        ..Robot::default()
    })
    .unwrap()
}

#[test]
fn margins_are_their_definitions() {
    let mut rng = rng(201);
    let limits = Limits {
        stroke: Some([
            [-0.11, 0.09],
            [-0.1, 0.1],
            [-0.12, 0.08],
            [-0.1, 0.1],
            [-0.1, 0.13],
            [-0.1, 0.1],
        ]),
        plate_travel: Some([0.05, 0.07]),
        tilt: Some(0.6),
        ..Limits::default()
    };
    for n in 0..2_000 {
        let robot = if n % 2 == 0 {
            Robot {
                limits,
                ..random_robot(&mut rng)
            }
        } else {
            Robot {
                limits,
                ..Robot::default()
            }
        };
        let c5 = C5::new(robot).unwrap();
        let pose = random_state(&mut rng).pose;
        let m = c5.limit_margins(&pose).unwrap();
        let (q, plate, tilt) = reference(&robot, &pose);
        let stroke = limits.stroke.unwrap();
        let travel = limits.plate_travel.unwrap();
        for i in 0..6 {
            let want = (q[i] - stroke[i][0]).min(stroke[i][1] - q[i]);
            assert!((m.stroke[i] - want).abs() < 1e-12, "stroke {i}");
            for a in 0..2 {
                assert!(
                    (m.values.plate[i][a] - plate[i][a]).abs() < 1e-12,
                    "plate {i} {a}"
                );
                assert!((m.plate[i][a] - (travel[a] - plate[i][a].abs())).abs() < 1e-12);
            }
            assert!((m.values.tilt[i] - tilt[i]).abs() < 1e-12, "tilt {i}");
            assert!((m.tilt[i] - (0.6 - tilt[i])).abs() < 1e-12);
        }
    }
}

#[test]
fn without_limits_every_margin_is_infinite_and_every_pose_passes() {
    let c5 = C5::new(Robot::default()).unwrap();
    let far = Pose::from_array([1.2, -1.1, 1.3, 0.5, -0.4, 0.3]);
    let m = c5.limit_margins(&far).unwrap();
    assert!(m.smallest().is_none());
    assert!(m.stroke.iter().all(|x| *x == f64::INFINITY));
    c5.check_limits(&far).unwrap();
    c5.check_speeds(&[100.0; 6]).unwrap();
    c5.check_forces(&[1e6; 6]).unwrap();
}

/// For each kind of pose limit, over random poses: with the limit set just above the largest
/// value the pose reaches, the pose passes; just below, it is refused naming the limit and the
/// actuator that reaches it; every actuator is that one for some pose.
#[test]
fn each_limit_just_inside_passes_and_just_outside_fails_at_each_actuator() {
    let mut rng = rng(202);
    let eps = 1e-9;
    let mut named = std::collections::HashSet::new();
    for _ in 0..3_000 {
        let pose = random_state(&mut rng).pose;
        let (q, plate, tilt) = reference(&Robot::default(), &pose);
        // Stroke: the largest |Q_i1| reaches a symmetric stroke.
        let reached = q.map(f64::abs);
        let reach = max(&reached);
        let stroke = |s: f64| Limits {
            stroke: Some([[-s, s]; 6]),
            ..Limits::default()
        };
        check(
            &pose,
            stroke(reach + eps),
            stroke(reach - eps),
            Limit::Stroke,
            &reached,
            &mut named,
        );
        // Plate travel, the same along both axes.
        let reached = plate.map(|p| p[0].abs().max(p[1].abs()));
        let reach = max(&reached);
        let travel = |t: f64| Limits {
            plate_travel: Some([t, t]),
            ..Limits::default()
        };
        check(
            &pose,
            travel(reach + eps),
            travel(reach - eps),
            Limit::PlateTravel,
            &reached,
            &mut named,
        );
        // Tilt: the pair of an axis tilts alike, so the first of the pair is named.
        let reach = max(&tilt);
        let tilted = |t: f64| Limits {
            tilt: Some(t),
            ..Limits::default()
        };
        check(
            &pose,
            tilted(reach + eps),
            tilted(reach - eps),
            Limit::Tilt,
            &tilt,
            &mut named,
        );
    }
    for limit in [Limit::Stroke, Limit::PlateTravel] {
        for actuator in 1..=6 {
            assert!(
                named.contains(&(limit, actuator)),
                "{limit} never named actuator {actuator}"
            );
        }
    }
    for actuator in [1, 3, 5] {
        assert!(
            named.contains(&(Limit::Tilt, actuator)),
            "tilt never named actuator {actuator}"
        );
    }
}

fn max(values: &[f64; 6]) -> f64 {
    values.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v))
}

fn check(
    pose: &Pose,
    inside: Limits,
    outside: Limits,
    limit: Limit,
    reached: &[f64; 6],
    named: &mut std::collections::HashSet<(Limit, usize)>,
) {
    with_limits(inside).check_limits(pose).unwrap();
    match with_limits(outside).check_limits(pose) {
        Err(Error::Limit {
            limit: l,
            actuator,
            margin,
            ..
        }) => {
            assert_eq!(l, limit);
            assert!(margin < 0.0 && margin > -1e-8, "{limit}: margin {margin:e}");
            // The actuator named is one that reaches the limit (a pair's tilt is shared).
            assert!(
                reached[actuator - 1] >= max(reached) - 1e-12,
                "{limit}: {actuator}"
            );
            named.insert((l, actuator));
            let e = Error::Limit {
                limit: l,
                actuator,
                value: 0.0,
                margin,
            };
            assert!(e
                .to_string()
                .starts_with(&format!("{limit} limit exceeded at actuator {actuator}")));
        }
        other => panic!("{limit} just outside: {other:?}"),
    }
}

#[test]
fn speeds_and_forces_are_checked_by_actuator() {
    let c5 = with_limits(Limits {
        speed: Some(0.5),
        force: Some(200.0),
        ..Limits::default()
    });
    c5.check_speeds(&[0.5, -0.5, 0.1, 0.0, 0.2, 0.3]).unwrap();
    let e = c5
        .check_speeds(&[0.1, 0.2, -0.51, 0.0, 0.2, 0.3])
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::Limit {
                limit: Limit::Speed,
                actuator: 3,
                ..
            }
        ),
        "{e:?}"
    );
    c5.check_forces(&[200.0; 6]).unwrap();
    let e = c5
        .check_forces(&[0.0, 0.0, 0.0, 0.0, 150.0, -201.0])
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::Limit {
                limit: Limit::Force,
                actuator: 6,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("force limit exceeded at actuator 6: -201"),
        "{e}"
    );
}

/// At zero orientation `Q1 = Q2 = xc`, `Q3 = Q4 = yc`, `Q5 = Q6 = zc` (eq 16), so a stroke of
/// `[a, b]` for every actuator bounds the centres to the box `[a, b]³`: the map is that box,
/// its volume `(b - a)³` to the grid's resolution.
#[test]
fn the_stroke_only_workspace_at_zero_orientation_is_a_box() {
    use c5_runtime::workspace::{map, Grid, Sweep};
    let (a, b) = (-0.06, 0.1);
    let c5 = with_limits(Limits {
        stroke: Some([[a, b]; 6]),
        ..Limits::default()
    });
    let grid = Grid {
        sweep: Sweep::Centres {
            orientation: [0.0; 3],
        },
        lower: [-0.15; 3],
        upper: [0.15; 3],
        points: 61,
    };
    let m = map(c5.as_mechanism(), &grid, &|_| {}).unwrap();
    for cell in &m.reachable {
        let x = grid.coordinates(cell.index);
        assert!(x.iter().all(|&v| v >= a - 1e-12 && v <= b + 1e-12), "{x:?}");
    }
    // Every grid point inside the box is reached.
    let h = grid.step()[0];
    let inside = (0..61)
        .filter(|&i| (a..=b).contains(&(-0.15 + i as f64 * h)))
        .count();
    assert_eq!(m.reachable.len(), inside.pow(3));
    let exact = (b - a).powi(3);
    // A point stands for a cell of side `h`: the count may overstate each side by one cell.
    assert!(
        (m.volume() - exact).abs() <= (b - a + h).powi(3) - exact,
        "{} vs {exact}",
        m.volume()
    );
    // At home a unit force along an axis is shared by that axis' pair of actuators, half
    // each (their moments about `C` cancel): the largest actuator force per newton is 1/2.
    let home = m
        .reachable
        .iter()
        .find(|c| c.index == [30, 30, 30])
        .unwrap();
    assert!(
        (home.force_ratio - 0.5).abs() < 1e-12,
        "{}",
        home.force_ratio
    );
    assert!(m
        .reachable
        .iter()
        .all(|c| c.inverse_condition > 0.0 && c.inverse_condition <= 1.0));
}
