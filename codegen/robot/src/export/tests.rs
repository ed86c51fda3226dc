use super::*;
use crate::tree::{dot, norm, sub, JointKind};
use crate::{GoughStewart, Robot};
use alloc::vec::Vec;

fn examples() -> [Description; 2] {
    [
        Description::C5(Robot::default()),
        Description::GoughStewart(GoughStewart::example()),
    ]
}

#[test]
fn numbers_read_back_exactly_and_tiny_ones_in_exponent_form() {
    for x in [0.1, -2.5e-17, 1.0 / 3.0, 6.02e23, 0.4251176316354555] {
        let text = alloc::format!("{}", Num(x));
        assert_eq!(text.parse::<f64>().unwrap(), x, "{text}");
    }
    assert_eq!(alloc::format!("{}", Num(-0.0)), "0");
    assert_eq!(alloc::format!("{}", Num(-2.5e-17)), "-2.5e-17");
}

#[test]
fn formats_parse_by_name_and_refuse_others() {
    assert_eq!("mjcf".parse::<Format>().unwrap(), Format::Mjcf);
    assert_eq!("urdf".parse::<Format>().unwrap(), Format::Urdf);
    let err = "sdf".parse::<Format>().unwrap_err().to_string();
    assert!(err.contains("`mjcf` or `urdf`, got `sdf`"), "{err}");
}

#[test]
fn the_trees_carry_every_mass_of_the_description() {
    let c5 = Robot::default();
    let want = c5.platform.mass
        + c5.segments
            .iter()
            .map(|s| s.rod.mass + s.joint.mass)
            .sum::<f64>();
    assert!((c5.body_tree().mass() - want).abs() < 1e-12);
    let gs = GoughStewart::example();
    let want = gs.platform.mass
        + gs.legs
            .iter()
            .map(|l| l.rod.mass + l.cylinder.mass)
            .sum::<f64>();
    assert!((gs.body_tree().mass() - want).abs() < 1e-12);
}

#[test]
fn a_hexapod_leg_spans_its_length_at_home_along_its_frame() {
    let gs = GoughStewart::example();
    let tree = gs.body_tree();
    for (i, leg) in tree.legs.iter().enumerate() {
        let (u, length) = gs.leg(i, &tree.home);
        let (rod, cylinder) = (&leg.bodies[0], &leg.bodies[1]);
        assert!((norm(sub(rod.origin, cylinder.origin)) - length).abs() < 1e-15);
        // z' is the leg's direction, and the actuated slide runs along it.
        let z = [rod.rotation[0][2], rod.rotation[1][2], rod.rotation[2][2]];
        assert!((dot(z, u) - 1.0).abs() < 1e-15);
        let (b, j) = leg.actuated;
        assert_eq!(
            leg.bodies[b].joints[j].name,
            alloc::format!("leg{}_stroke", i + 1)
        );
    }
}

#[test]
fn a_c5_segment_closes_on_its_actuator_axis_at_home() {
    let robot = Robot::default();
    let tree = robot.body_tree();
    for (i, leg) in tree.legs.iter().enumerate() {
        let (plates, rod, guide) = (&leg.bodies[0], &leg.bodies[1], &leg.bodies[2]);
        // Eq 16 at the level home: the ball at A_i (Q_i1 = 0), on the platform plane.
        assert_eq!(plates.origin, robot.anchor(i));
        assert_eq!(rod.origin, plates.origin);
        assert_eq!(guide.origin, robot.anchor(i));
        let JointKind::Slide { axis } = guide.joints[0].kind else {
            panic!("the actuator is a slide");
        };
        assert_eq!(
            axis[crate::AXIS[i]],
            -1.0,
            "along -n_i from the rod: +Γ pushes +n_i"
        );
    }
}

#[test]
fn mjcf_is_well_formed_with_one_weld_motor_and_keyframe_entry_per_joint() {
    for description in examples() {
        let text = description.to_mjcf().unwrap();
        let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
        let count = |tag: &str| doc.descendants().filter(|n| n.has_tag_name(tag)).count();
        let tree = description.body_tree();
        let bodies = 1 + tree.legs.iter().map(|l| l.bodies.len()).sum::<usize>();
        assert_eq!(count("body"), bodies);
        assert_eq!(count("weld"), 6);
        assert_eq!(count("motor"), 6);
        assert_eq!(count("freejoint"), 1);
        let joints: Vec<_> = doc
            .descendants()
            .filter(|n| n.has_tag_name("joint"))
            .collect();
        let nq = 7 + joints
            .iter()
            .map(|j| {
                if j.attribute("type") == Some("ball") {
                    4
                } else {
                    1
                }
            })
            .sum::<usize>();
        let key = doc
            .descendants()
            .find(|n| n.has_tag_name("key"))
            .and_then(|n| n.attribute("qpos"))
            .unwrap();
        assert_eq!(key.split(' ').count(), nq);
        let mut names: Vec<_> = joints.iter().filter_map(|j| j.attribute("name")).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), joints.len(), "joint names are unique");
        // A body that carries no mass in the description gets a real one (MuJoCo's rule).
        for inertial in doc.descendants().filter(|n| n.has_tag_name("inertial")) {
            assert!(inertial.attribute("mass").unwrap().parse::<f64>().unwrap() > 0.0);
        }
    }
}

#[test]
fn urdf_is_well_formed_a_tree_with_one_constraint_per_leg() {
    for description in examples() {
        let text = description.to_urdf().unwrap();
        let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
        let links = doc.descendants().filter(|n| n.has_tag_name("link")).count();
        let joints: Vec<_> = doc
            .descendants()
            .filter(|n| n.has_tag_name("joint"))
            .collect();
        // A tree: one joint into every link but the root.
        assert_eq!(joints.len() + 1, links);
        let mut children: Vec<_> = joints
            .iter()
            .map(|j| {
                j.children()
                    .find(|c| c.has_tag_name("child"))
                    .and_then(|c| c.attribute("link"))
                    .unwrap()
            })
            .collect();
        children.sort_unstable();
        children.dedup();
        assert_eq!(children.len(), joints.len(), "each link has one parent");
        let constraints = doc
            .descendants()
            .filter(|n| n.has_tag_name("constraint"))
            .count();
        assert_eq!(constraints, 6);
    }
}

#[test]
fn an_invalid_description_is_refused_and_nothing_is_made() {
    let mut robot = GoughStewart::example();
    robot.platform.mass = -1.0;
    let err = Description::GoughStewart(robot)
        .to_mjcf()
        .unwrap_err()
        .to_string();
    assert!(err.contains("`platform.mass` must be positive"), "{err}");
}
