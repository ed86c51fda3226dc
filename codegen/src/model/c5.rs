//! The C5 robot's structure, which both of its models share: the chapter's parameter vector,
//! eqs 15, 16 and 27 and the closed-form forward kinematics ([`geometry`]), the bodies'
//! parameters ([`Dynamics`]) and the divisors of eq 16, the poses where it is singular.

use super::bodies::{Dynamics, STANDARD_INERTIAL};
use super::geometry::{self, Posed};
use super::kernels::{Guard, Output, Reads};
use super::Structure;
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::Vec3;
use c5_robot::{standard_parameter_names, Robot, GEOMETRY_PARAMETERS};

/// The C5's [`Structure`].
pub struct C5;

const DIVISORS: Output = Output {
    name: "r",
    shape: Shape::Vector(3),
    doc: "`[r11 r22 r33]`, the divisors of eq 16: the other results are meaningless where one \
          is near zero",
};
const FORWARD: Output = Output {
    name: "singular",
    shape: Shape::Vector(4),
    doc: "`[1 + abc, r11, r22, r33]`: the forward singularity term (the actuator positions \
          belong to a pose of the workspace only where it is positive; the other results are \
          meaningless where it is near zero or negative) and the divisors of eq 16",
};

impl Structure for C5 {
    fn parameter_names(&self) -> Vec<String> {
        Robot::<f64>::kernel_parameter_names()
    }

    fn geometry_parameters(&self) -> usize {
        GEOMETRY_PARAMETERS
    }

    fn pose<'g>(&self, geometry: &[Expr<'g>], x: &[Expr<'g>]) -> Posed<'g> {
        geometry::pose(geometry, x)
    }

    fn forward_kinematics<'g>(
        &self,
        geometry: &[Expr<'g>],
        q: &[Expr<'g>; 6],
    ) -> Option<Posed<'g>> {
        Some(geometry::forward_kinematics(geometry, q))
    }

    fn dynamics<'g>(&self, parameters: &[Expr<'g>]) -> Dynamics<'g> {
        Dynamics::from_kernel_parameters(parameters)
    }

    fn standard_inertial_names(&self) -> Vec<String> {
        standard_parameter_names()[..STANDARD_INERTIAL].to_vec()
    }

    fn standard_inertial_doc(&self) -> &'static str {
        "ten per body (mass, first moment `m c`, inertia about the reference point; the \
         platform about `C` in its frame, each rod about `B_i` in the base frame, each body 2 \
         about `B_i` in the platform frame)"
    }

    fn dynamics_from_standard<'g>(
        &self,
        g: &'g Graph,
        gravity: Vec3<'g>,
        p: &[Expr<'g>],
    ) -> Dynamics<'g> {
        Dynamics::from_standard(g, gravity, p)
    }

    fn guard<'g>(&self, guard: Guard, posed: &Posed<'g>) -> Vec<Expr<'g>> {
        match guard {
            Guard::Never => Vec::new(),
            Guard::Pose | Guard::Solve => geometry::divisors(&posed.r),
            Guard::Forward => {
                let forward = posed.forward.unwrap_or_else(|| {
                    let g = posed.c[0].graph();
                    g.invalidate("a forward guard on a kernel without actuator positions".into());
                    g.zero()
                });
                std::iter::once(forward)
                    .chain(geometry::divisors(&posed.r))
                    .collect()
            }
        }
    }

    fn guard_output(&self, guard: Guard) -> (Output, &'static str) {
        match guard {
            Guard::Forward => (
                FORWARD,
                "\nThe last result holds the forward singularity term and the divisors of eq 16 \
                 for a singularity check.",
            ),
            _ => (
                DIVISORS,
                "\nThe last result holds the divisors of eq 16 for a singularity check.",
            ),
        }
    }

    fn conventions(&self) -> &'static str {
        "Actuators are in segment order 1..6; the chapter lists them 6..1."
    }

    fn parameter_doc(&self, reads: Reads) -> &'static str {
        match reads {
            Reads::Geometry => {
                "`[L gx gy gz]`, the robot's half spacing and gravity (the first four of \
                 `Robot::kernel_parameters`)"
            }
            _ => {
                "robot parameters (`Robot::kernel_parameters`: each body's first moment `m c` \
                 and inertia about its reference point), in the order of the names in this \
                 signature"
            }
        }
    }

    fn home(&self, _parameters: &[f64]) -> [f64; 6] {
        [0.0; 6]
    }

    fn reach(&self, parameters: &[f64]) -> f64 {
        parameters[0]
    }
}
