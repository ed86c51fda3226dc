//! What both models share of the dynamics: the bodies' inertial parameters, Newton-Euler of a
//! rigid body, and the platform's wrench (eqs 52-57).
//!
//! Every wrench is written about the body's reference point from its standard parameters (mass
//! `m`, first moment `h = m c`, inertia `I_O` about the reference point), in which the dynamics
//! is linear: the regressor `Y = ∂Γ/∂π` is then the exact derivative, free of `π`.

use crate::dag::{Expr, Graph};
use crate::linalg::{Mat, Mat3, Vec3, Vec6, Vector};
use c5_robot::{RigidBody, Robot};

/// A body's standard inertial parameters: mass `m`, first moment `h = m c` (the centre of mass
/// `c` from the body's reference point) and inertia `I_O` about the reference point, `h` and
/// `I_O` in the body's frame.
#[derive(Clone, Copy)]
pub struct Inertial<'g> {
    pub mass: Expr<'g>,
    pub first_moment: Vec3<'g>,
    pub inertia: Mat3<'g>,
}

impl<'g> Inertial<'g> {
    /// No mass: a body that moves but weighs nothing (kinematics).
    pub fn massless(g: &'g crate::dag::Graph) -> Self {
        Inertial {
            mass: g.zero(),
            first_moment: crate::linalg::Vec3::zeros(g),
            inertia: crate::linalg::Mat3::zeros(g),
        }
    }

    /// From the ten standard parameters `[m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz]`.
    pub fn from_standard(p: &[Expr<'g>]) -> Self {
        Inertial {
            mass: p[0],
            first_moment: Vector([p[1], p[2], p[3]]),
            inertia: Mat([[p[4], p[5], p[6]], [p[5], p[7], p[8]], [p[6], p[8], p[9]]]),
        }
    }
}

/// A mechanism's dynamic parameters as the dynamics uses them: gravity (base frame), the
/// standard parameters of the platform (reference point `C`, platform frame) and of each leg's
/// two moving bodies, each in the frame and about the reference point its mechanism says. For
/// the C5: body 1 is the rod (reference point `B_i`, base frame: it translates, so only its mass
/// counts), body 2 the C5 joint (reference point `B_i`, platform frame: it keeps the platform's
/// orientation).
pub struct Dynamics<'g> {
    pub gravity: Vec3<'g>,
    pub platform: Inertial<'g>,
    /// `[body 1, body 2]` of each leg, in actuator order.
    pub legs: [[Inertial<'g>; 2]; 6],
    /// The part of each C5 rod's inertia that grows with `Q_i1²` (the appendix's `J_Gi1`),
    /// which multiplies a zero angular velocity (slip 5); zero for other mechanisms.
    pub rod_inertia_per_length_squared: [Mat3<'g>; 6],
}

/// The number of standard inertial parameters of the C5: ten for each of the 13 bodies, in the
/// order platform, then rod and body 2 of each segment.
pub const STANDARD_INERTIAL: usize = 130;

impl<'g> Dynamics<'g> {
    /// The C5's, from the parameter vector of the `*_params` kernels (`Robot::kernel_parameters`:
    /// [`Robot::flatten`]'s layout, each body's centre of mass and inertia in standard form,
    /// the first moment `m c` and the inertia about the reference point).
    pub fn from_kernel_parameters(p: &[Expr<'g>]) -> Self {
        let robot = Robot::<Expr<'g>>::unflatten(p);
        // In this vector a body's `com` holds its first moment and `inertia` is about its
        // reference point: the standard parameters.
        let standard = |b: &RigidBody<Expr<'g>>| Inertial {
            mass: b.mass,
            first_moment: Vector(b.com),
            inertia: Mat(b.inertia),
        };
        let zero = p[0].graph().zero();
        Dynamics {
            gravity: Vector(robot.gravity),
            platform: standard(&robot.platform),
            legs: robot.segments.map(|s| {
                let rod = Inertial {
                    mass: s.rod.mass,
                    first_moment: Vector([zero; 3]),
                    inertia: Mat(s.rod.inertia),
                };
                [rod, standard(&s.joint)]
            }),
            rod_inertia_per_length_squared: robot
                .segments
                .map(|s| Mat(s.rod.inertia_per_length_squared)),
        }
    }

    /// The C5's, from the [`STANDARD_INERTIAL`] standard parameters (platform, then rod and
    /// body 2 of segments 1..6, ten each) and gravity.
    pub fn from_standard(g: &'g Graph, gravity: Vec3<'g>, p: &[Expr<'g>]) -> Self {
        let body = |k: usize| Inertial::from_standard(&p[10 * k..10 * k + 10]);
        Dynamics {
            gravity,
            platform: body(0),
            legs: std::array::from_fn(|i| [body(1 + 2 * i), body(2 + 2 * i)]),
            rod_inertia_per_length_squared: [Mat::zeros(g); 6],
        }
    }
}

/// Newton-Euler of a rigid body: its wrench `(n; f)` about a point `O` of the body whose
/// classical acceleration is `a_o`, for a body turning at `ω`, `ω̇` with its centre of mass at
/// `s` from `O`, net of gravity `g`; `n_g` is the moment about the centre of mass (Euler's
/// equations). Every vector in one frame.
#[allow(clippy::too_many_arguments)]
pub fn rigid_body_wrench<'g>(
    mass: Expr<'g>,
    s: &Vec3<'g>,
    n_g: &Vec3<'g>,
    omega: &Vec3<'g>,
    omega_dot: &Vec3<'g>,
    a_o: &Vec3<'g>,
    gravity: &Vec3<'g>,
) -> Vec6<'g> {
    let a_g = *a_o + omega_dot.cross(s) + omega.cross(&omega.cross(s));
    let f = (a_g - *gravity).scale(mass);
    Vec6::spatial(*n_g + s.cross(&f), f)
}

/// `ω̇̃ + ω̃ ω̃`: the map from a body point's offset `r` to its acceleration relative to the
/// reference point, `ω̇ × r + ω × (ω × r)`. One matrix for every point of a body.
pub fn point_acceleration_map<'g>(omega: &Vec3<'g>, omega_dot: &Vec3<'g>) -> Mat3<'g> {
    omega_dot.tilde() + omega.tilde() * omega.tilde()
}

/// The platform's rotation, with the motion seen from the platform frame.
pub struct Frame<'g> {
    /// `R`, eq 15.
    pub r: Mat3<'g>,
    /// `ω_p = Rᵀ ω`.
    pub omega: Vec3<'g>,
    /// `ω̇_p = Rᵀ ω̇`.
    pub omega_dot: Vec3<'g>,
}

impl<'g> Frame<'g> {
    pub fn new(r: Mat3<'g>, omega: &Vec3<'g>, omega_dot: &Vec3<'g>) -> Self {
        let rt = r.transpose();
        Frame {
            r,
            omega: (rt * *omega).keep_where_cheaper("ω in the platform frame"),
            omega_dot: (rt * *omega_dot).keep_where_cheaper("ω̇ in the platform frame"),
        }
    }

    /// `R x` for a platform-frame vector.
    pub fn to_base(&self, v: &Vec3<'g>) -> Vec3<'g> {
        self.r * *v
    }

    /// `Rᵀ x` for a base-frame vector.
    pub fn to_platform(&self, v: &Vec3<'g>) -> Vec3<'g> {
        self.r.transpose() * *v
    }

    /// `ω̇̃_p + ω̃_p ω̃_p`, the point-acceleration map in the platform frame.
    pub fn point_acceleration_map(&self) -> Mat3<'g> {
        point_acceleration_map(&self.omega, &self.omega_dot)
    }
}

/// Newton-Euler about the reference point `O` of a body that turns with the platform, in the
/// base frame: `f = m (a_O - g) + ω̇ × h + ω × (ω × h)`,
/// `n_O = I_O ω̇ + ω × I_O ω + h × (a_O - g)`, with `h = R h_p` and Euler's term in the platform
/// frame (`R (I_O ω̇_p + ω_p × I_O ω_p)`, eq 55 without forming `R I Rᵀ`). `omega`,
/// `omega_dot`, `a_o` and `gravity` in the base frame.
pub fn wrench_turning_with_platform<'g>(
    body: &Inertial<'g>,
    frame: &Frame<'g>,
    omega: &Vec3<'g>,
    omega_dot: &Vec3<'g>,
    a_o: &Vec3<'g>,
    gravity: &Vec3<'g>,
) -> Vec6<'g> {
    let h = frame.to_base(&body.first_moment);
    let a = *a_o - *gravity;
    let f = a.scale(body.mass) + omega_dot.cross(&h) + omega.cross(&omega.cross(&h));
    let euler = body.inertia * frame.omega_dot + frame.omega.cross(&(body.inertia * frame.omega));
    Vec6::spatial(frame.to_base(&euler) + h.cross(&a), f)
}

/// The same, every vector in the platform frame (`a_o` and `gravity` given in it).
pub fn wrench_in_platform_frame<'g>(
    body: &Inertial<'g>,
    frame: &Frame<'g>,
    a_o: &Vec3<'g>,
    gravity: &Vec3<'g>,
) -> Vec6<'g> {
    let (w, wd, h) = (frame.omega, frame.omega_dot, body.first_moment);
    let a = *a_o - *gravity;
    let f = a.scale(body.mass) + wd.cross(&h) + w.cross(&w.cross(&h));
    let euler = body.inertia * wd + w.cross(&(body.inertia * w));
    Vec6::spatial(euler + h.cross(&a), f)
}

/// Eqs 52-57: `F_{N+1} = Λ_C V̇_{N+1} + C_C + G_C` at `C` in the base frame, with the classical
/// acceleration `(ω̇; a_C)`: Newton-Euler of the platform about `C` (eq 54's `I_C` about `C`, so
/// right with a centre of mass off `C` too).
pub fn platform_wrench<'g>(
    dynamics: &Dynamics<'g>,
    frame: &Frame<'g>,
    twist: &Vec6<'g>,
    accel: &Vec6<'g>,
) -> Vec6<'g> {
    wrench_turning_with_platform(
        &dynamics.platform,
        frame,
        &twist.top(),
        &accel.top(),
        &accel.bottom(),
        &dynamics.gravity,
    )
}

/// Bodies that turn with the platform, lumped into one about `C`: the platform (reference point
/// `C`) and bodies at offsets `d` from `C` (base frame) that move as points of the platform.
/// Moving the reference point of standard parameters from `B` to `C = B - d` keeps the mass,
/// adds `m d` to the first moment and `-m d̃d̃ - d̃h̃ - h̃d̃` to the inertia (the parallel-axis
/// theorem for standard parameters): the rotational inertias stay constant in the platform
/// frame and add up there; what the offsets add is a base-frame matrix.
pub struct Lumped<'g> {
    pub mass: Expr<'g>,
    /// `Σ h`, the first moments about the bodies' own reference points (platform frame).
    pub first_moment: Vec3<'g>,
    /// `Σ m d`, what the offsets add to the first moment (base frame).
    pub offset_moment: Vec3<'g>,
    /// `Σ I`, the inertias about the bodies' own reference points (platform frame).
    pub inertia: Mat3<'g>,
    /// `Σ (-m d̃d̃ - d̃h̃ - h̃d̃)`, `h` in the base frame: what the offsets add to the inertia.
    pub offset_inertia: Mat3<'g>,
}

impl<'g> Lumped<'g> {
    /// The platform alone.
    pub fn platform(platform: &Inertial<'g>) -> Self {
        let g = platform.mass.graph();
        Lumped {
            mass: platform.mass,
            first_moment: platform.first_moment,
            offset_moment: Vec3::zeros(g),
            inertia: platform.inertia,
            offset_inertia: Mat3::zeros(g),
        }
    }

    /// With `body`, whose reference point is at `d` from `C` (base frame), turning with the
    /// platform.
    pub fn with(self, body: &Inertial<'g>, frame: &Frame<'g>, d: &Vec3<'g>) -> Self {
        let h = frame.to_base(&body.first_moment);
        let (dt, ht) = (d.tilde(), h.tilde());
        Lumped {
            mass: self.mass + body.mass,
            first_moment: self.first_moment + body.first_moment,
            offset_moment: self.offset_moment + d.scale(body.mass),
            inertia: self.inertia + body.inertia,
            offset_inertia: self.offset_inertia - (dt * dt).scale(body.mass) - dt * ht - ht * dt,
        }
    }

    /// Newton-Euler of the lumped body about `C`, base frame, net of gravity, for the classical
    /// acceleration `a_c` of `C`: `f = M (a_C - g) + ω̇ × H + ω × (ω × H)`,
    /// `n_C = R (Σ I ω̇_p + ω_p × Σ I ω_p) + I_d ω̇ + ω × I_d ω + H × (a_C - g)` with
    /// `H = R Σ h + Σ m d` and `I_d` the offsets' inertia: eqs 52-57 for the whole group.
    pub fn wrench(
        &self,
        frame: &Frame<'g>,
        omega: &Vec3<'g>,
        omega_dot: &Vec3<'g>,
        a_c: &Vec3<'g>,
        gravity: &Vec3<'g>,
    ) -> Vec6<'g> {
        // One first moment `H` for the whole group: `wrench_turning_with_platform` of the summed
        // parameters plus the offsets' own terms gives the same wrench, but costs the `_params`
        // kernels 18 multiplications and 15 additions more (`H × a` and `A H` split in two).
        let h = frame.to_base(&self.first_moment) + self.offset_moment;
        let a = *a_c - *gravity;
        let f = a.scale(self.mass) + omega_dot.cross(&h) + omega.cross(&omega.cross(&h));
        let (w, wd, i) = (frame.omega, frame.omega_dot, self.inertia);
        let euler = i * wd + w.cross(&(i * w));
        let id = self.offset_inertia;
        let n = frame.to_base(&euler) + id * *omega_dot + omega.cross(&(id * *omega)) + h.cross(&a);
        Vec6::spatial(n, f)
    }
}
