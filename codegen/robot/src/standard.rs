//! The standard parameters of identification: ten per body, then friction per actuator.
//!
//! Bodies in the order platform, then rod and body 2 of segments 1..6; each as mass, first
//! moment `m c` and inertia about its reference point (xx, xy, xz, yy, yz, zz):
//!
//! - the platform: reference point `C`, platform frame;
//! - rod `i` (body 1): reference point `B_i`, base frame. It only translates, so only its mass
//!   enters the forces; its nine other parameters are not identifiable;
//! - body 2 of segment `i` (plates and ball housing): reference point `B_i`, platform frame (it
//!   keeps the platform's orientation).
//!
//! Then the viscous `Fv_i` and Coulomb `Fc_i` friction of each actuator,
//! `Γ_f,i = Fv_i Q̇_i1 + Fc_i sign(Q̇_i1)`.

use crate::robot::standard_of;
use crate::Robot;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

/// The number of standard parameters: 13 bodies × 10, and 2 × 6 friction coefficients.
pub const STANDARD_PARAMETERS: usize = 142;

/// An actuator's friction: `Γ_f = viscous · Q̇ + coulomb · sign(Q̇)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Friction {
    /// N·s/m.
    pub viscous: f64,
    /// N.
    pub coulomb: f64,
}

const SUFFIXES: [&str; 10] = [
    "mass", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz",
];

/// The names of the standard parameters, in order: `platform_mass`, `platform_mx`, ...,
/// `rod1_mass`, ..., `joint1_izz`, ..., `fv1`..`fv6`, `fc1`..`fc6`.
pub fn standard_parameter_names() -> Vec<String> {
    let mut out: Vec<String> = SUFFIXES.iter().map(|s| format!("platform_{s}")).collect();
    for n in 1..=6 {
        for body in ["rod", "joint"] {
            out.extend(SUFFIXES.iter().map(|s| format!("{body}{n}_{s}")));
        }
    }
    out.extend((1..=6).map(|n| format!("fv{n}")));
    out.extend((1..=6).map(|n| format!("fc{n}")));
    out
}

/// `inertial` (a mechanism's standard inertial parameters) followed by the actuators'
/// viscous, then Coulomb, friction coefficients: the standard parameters of identification.
pub fn with_friction(mut inertial: Vec<f64>, friction: &[Friction]) -> Vec<f64> {
    inertial.extend(friction.iter().map(|f| f.viscous));
    inertial.extend(friction.iter().map(|f| f.coulomb));
    inertial
}

impl Robot<f64> {
    /// The robot's standard parameters with the actuators' `friction`. A rod's first moment is
    /// given as zero and its inertia as its constant part: neither enters the forces.
    pub fn standard_parameters(&self, friction: &[Friction; 6]) -> Vec<f64> {
        let mut out = Vec::with_capacity(STANDARD_PARAMETERS);
        out.extend(standard_of(&self.platform));
        for s in &self.segments {
            let i = &s.rod.inertia;
            out.extend([
                s.rod.mass, 0.0, 0.0, 0.0, i[0][0], i[0][1], i[0][2], i[1][1], i[1][2], i[2][2],
            ]);
            out.extend(standard_of(&s.joint));
        }
        out.extend(friction.iter().map(|f| f.viscous));
        out.extend(friction.iter().map(|f| f.coulomb));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_values_line_up() {
        let names = standard_parameter_names();
        let values = Robot::default().standard_parameters(
            &[Friction {
                viscous: 3.0,
                coulomb: 1.5,
            }; 6],
        );
        assert_eq!(
            (names.len(), values.len()),
            (STANDARD_PARAMETERS, STANDARD_PARAMETERS)
        );
        let at = |n: &str| values[names.iter().position(|x| x == n).unwrap()];
        assert_eq!((at("platform_mass"), at("platform_ixx")), (10.0, 0.375));
        assert_eq!((at("rod4_mass"), at("joint6_mass")), (2.0, 1.67));
        assert_eq!((at("fv3"), at("fc6")), (3.0, 1.5));
    }
}
