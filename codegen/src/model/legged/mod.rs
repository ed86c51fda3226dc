//! Mechanisms whose platform rides on legs, derived from the legs' types.
//!
//! A leg type ([`Leg`]) gives three things as expressions: the leg's coordinates (a few numbers
//! the platform's placement fixes, such as the position of its platform joint), and, as
//! functions of those coordinates, its actuator's value and the pose of each of its moving
//! bodies. Everything else is derived here, once for every such mechanism, by exact
//! differentiation on the expression graph:
//!
//! - the coordinates' rates and accelerations from the platform's twist and classical
//!   acceleration (`Ṙ = ω̃ R`, `Ċ = v_C`), and their map from the twist, `ṡ = T V`;
//! - the actuator's rate and acceleration, and the row `∇q T` of `J⁻¹`;
//! - each body's angular velocity (in its own frame, from `Rᵀ Ṙ`) and its reference point's
//!   velocity, their accelerations, its Newton-Euler wrench, and through virtual work the
//!   leg's generalized force on its coordinates, `φ = Σ Gᵀ F`, which reaches the platform as
//!   the wrench `Tᵀ φ` at `C`.
//!
//! Each derivation is built on fresh symbols (the placement, the platform's motion, the leg's
//! coordinates) and the symbols are then replaced by the kernel's expressions, so the leg types
//! stay functions of a few numbers and the kernels share every subexpression.

pub mod newton;
pub mod psp;
pub mod rus;
pub mod ups;

use super::bodies::{wrench_in_platform_frame, Dynamics, Frame, Inertial};
use super::geometry::Motion;
use super::geometry::Posed;
use crate::dag::{Expr, Graph};
use crate::linalg::{Mat, Mat3, Mat6, Vec3, Vec6, Vector};
use std::cell::RefCell;

/// The first index of the symbols the derivation builds on; none survives in a kernel.
const SYMBOLS: u32 = 1 << 29;
/// The first index of the platform points' symbols ([`Placement::point`]).
const POINT_SYMBOLS: u32 = SYMBOLS + 24;
/// The first index of a leg's coordinate symbols (its coordinates, their rates, their
/// accelerations, [`MAX_COORDINATES`] each).
const LEG_SYMBOLS: u32 = SYMBOLS + 64;
/// The most coordinates a leg may have.
pub const MAX_COORDINATES: usize = 32;

/// The platform's placement as a leg's coordinates read it: its rotation `R` (eq 15) and its
/// origin `C`, base frame, and the points fixed in the platform ([`Placement::point`]).
pub struct Placement<'g> {
    pub r: Mat3<'g>,
    pub c: Vec3<'g>,
    /// The platform points asked for: each the symbol of `R p` and its `p`.
    points: RefCell<Vec<(Vec3<'g>, Vec3<'g>)>>,
}

impl<'g> Placement<'g> {
    /// `C + R p`, the point at `p` (platform frame) of the platform. Its motion is the
    /// platform's, `ω × R p` and `ω̇ × R p + ω × (ω × R p)`, which the derivation uses
    /// directly: cheaper than through `R`'s entries.
    pub fn point(&self, p: &Vec3<'g>) -> Vec3<'g> {
        let g = p[0].graph();
        let mut points = self.points.borrow_mut();
        let first = POINT_SYMBOLS + 3 * points.len() as u32;
        assert!(first + 3 <= LEG_SYMBOLS, "too many platform points");
        let symbol = vec3(&symbols(g, first, 3));
        points.push((symbol, *p));
        self.c + symbol
    }
}

/// A moving body of a leg, as expressions of the leg's coordinates.
pub struct LegBody<'g> {
    /// The body's frame in the base frame: its columns are the body's axes.
    pub rotation: Mat3<'g>,
    /// The reference point of its inertial parameters, base frame.
    pub origin: Vec3<'g>,
    /// Its standard inertial parameters about `origin`, in its own frame.
    pub inertial: Inertial<'g>,
    /// Its angular motion in closed form, where the leg type knows it (a test of the leg type
    /// holds it to the derived one); `None` derives it from `rotation`.
    pub angular: Option<AngularMotion<'g>>,
    /// Without [`LegBody::angular`]: `G` alone in closed form, the bias derived from it;
    /// `None` derives both.
    pub angular_rates: Option<Vec<Vec3<'g>>>,
    /// Its origin's velocity per unit rate of each coordinate in closed form, in its own
    /// frame: the origin's acceleration, its force's virtual work and the energy's mass matrix
    /// ([`MassMatrix::Energy`]) then read it there, with nothing rotated; `None` derives it in
    /// the base frame.
    pub velocity_rates: Option<Vec<Vec3<'g>>>,
    /// Its origin's acceleration at `s̈ = 0` in closed form (base frame), where the leg type
    /// knows it; `None` differentiates the origin's velocity.
    pub acceleration_bias: Option<Vec3<'g>>,
}

/// A body's angular motion in its own frame, `ω = G ṡ` and `ω̇ = G s̈ + b`.
#[derive(Clone)]
pub struct AngularMotion<'g> {
    /// `G`, by columns: the angular velocity per unit rate of each coordinate.
    pub rates: Vec<Vec3<'g>>,
    /// `b = Ġ ṡ`, the angular acceleration at rest coordinates' accelerations (a function of
    /// the coordinates and their rates).
    pub bias: Vec3<'g>,
}

/// A quantity a leg's expressions read as a coordinate of their own, though the leg's
/// coordinates fix it (a crank's `cos θ` and `sin θ`): its closed form, and its partial
/// derivatives in closed form. The derivation differentiates through the symbol by the chain
/// rule, with these partials, instead of through the closed form.
pub struct Hidden<'g> {
    /// Its value, an expression of the leg's coordinates alone.
    pub value: Expr<'g>,
    /// `∂/∂s_k` for each coordinate `s_k`, expressions of the coordinates and the hidden
    /// symbols.
    pub gradient: Vec<Expr<'g>>,
}

/// A leg type, its parameters given: the seam every leg type implements.
///
/// The coordinates `s` its methods receive are the leg's own ([`Leg::coordinates`]), then the
/// symbols of its [`Leg::hidden`] quantities; the rates `ṡ` are the coordinates' alone.
pub trait Leg<'g> {
    /// The leg's coordinates as expressions of the platform's placement.
    fn coordinates(&self, placement: &Placement<'g>) -> Vec<Expr<'g>>;
    /// The actuator's value as a function of the coordinates `s`.
    fn actuator(&self, s: &[Expr<'g>]) -> Expr<'g>;
    /// The leg's moving bodies as functions of the coordinates `s` (and their rates `ṡ`, which
    /// only a closed-form [`AngularMotion::bias`] reads).
    fn bodies(&self, s: &[Expr<'g>], sd: &[Expr<'g>]) -> Vec<LegBody<'g>>;
    /// Whether the actuator's rate per unit platform velocity, `∂q̇/∂v_C`, is a unit vector
    /// (a leg whose actuator is the distance between two of its joints): the solve with `J⁻ᵀ`
    /// then knows that part of its rows' norms.
    fn unit_translation(&self) -> bool {
        false
    }
    /// How many hidden quantities the leg's expressions read ([`Leg::hidden`]).
    fn hidden_count(&self) -> usize {
        0
    }
    /// The hidden quantities, at the coordinates and hidden symbols `s`.
    fn hidden(&self, _s: &[Expr<'g>]) -> Vec<Hidden<'g>> {
        Vec::new()
    }
    /// `∂q/∂s_k` in closed form, where the leg type has one cheaper than the derivative of
    /// [`Leg::actuator`]; `None` derives it.
    fn actuator_gradient(&self, _s: &[Expr<'g>]) -> Option<Vec<Expr<'g>>> {
        None
    }
    /// How the leg's mass matrix in its coordinates is formed; default
    /// [`MassMatrix::Differentiated`].
    fn mass_matrix(&self) -> MassMatrix {
        MassMatrix::Differentiated
    }
}

/// The two exact ways to a leg's mass matrix `M` in its coordinates (`φ = M s̈ + φ₀`); which
/// costs fewer operations depends on the leg type's bodies.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum MassMatrix {
    /// `∂φ/∂s̈`, the generalized force differentiated: it shares the Newton-Euler terms the
    /// bias reads (the U-P-S leg, whose piston's origin slides along the leg).
    Differentiated,
    /// `Σ Jᵀ I J` over the bodies, the kinetic energy's Hessian in the rates: `M_kl = v_k·p_l +
    /// ω_k·L_l` with `p_l = m v_l + ω_l × h` and `L_l = I ω_l + h × v_l`, each body's velocity
    /// `v` and angular velocity `ω` per unit rate in its own frame (the R-U-S leg, whose rod's
    /// origin, the elbow, moves along one direction only).
    Energy,
}

/// The coordinates of a leg at the platform's state: their values, rates and accelerations,
/// and the rows of `T = ∂ṡ/∂V`.
struct CoordinateMotion<'g> {
    s: Vec<Expr<'g>>,
    sd: Vec<Expr<'g>>,
    sdd: Vec<Expr<'g>>,
    t: Vec<Vec6<'g>>,
}

fn symbols(g: &Graph, first: u32, n: usize) -> Vec<Expr<'_>> {
    (0..n as u32).map(|k| g.input(first + k)).collect()
}

fn vec3<'g>(v: &[Expr<'g>]) -> Vec3<'g> {
    Vector([v[0], v[1], v[2]])
}

/// `Σₖ aₖ bₖ`.
fn dot<'g>(a: &[Expr<'g>], b: &[Expr<'g>]) -> Expr<'g> {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| x * y)
        .fold(a[0].graph().zero(), |sum, t| sum + t)
}

/// The leg's coordinates at the platform's state: from `Ṙ = ω̃ R`, `Ċ = v_C`, `ω̇`, `a_C`, the
/// exact first and second time derivatives of the coordinates, and `T`.
fn coordinate_motion<'g>(
    leg: &dyn Leg<'g>,
    placement: &(Mat3<'g>, Vec3<'g>),
    motion: &Motion<'g>,
) -> CoordinateMotion<'g> {
    let g = placement.1[0].graph();
    let r_hat = symbols(g, SYMBOLS, 9);
    let c_hat = symbols(g, SYMBOLS + 9, 3);
    let twist = symbols(g, SYMBOLS + 12, 6);
    let accel = symbols(g, SYMBOLS + 18, 6);
    let r = Mat::from_fn(|i, j| r_hat[3 * i + j]);
    let symbolic = Placement {
        r,
        c: vec3(&c_hat),
        points: RefCell::new(Vec::new()),
    };
    let s = leg.coordinates(&symbolic);
    let points = symbolic.points.into_inner();
    // `Ṙ = ω̃ R`, `(R p)˙ = ω × R p` and `Ċ = v_C`; then `ω̇` and `a_C` are the rates of the
    // twist.
    let omega = vec3(&twist[..3]);
    let r_dot = omega.tilde() * r;
    let mut rates: Vec<(Expr<'g>, Expr<'g>)> = (0..9)
        .map(|k| (r_hat[k], r_dot.0[k / 3][k % 3]))
        .chain((0..3).map(|k| (c_hat[k], twist[3 + k])))
        .chain(points.iter().flat_map(|(symbol, _)| {
            let rate = omega.cross(symbol);
            (0..3).map(move |k| (symbol[k], rate[k]))
        }))
        .collect();
    let sd = g.tangents(&s, &rates);
    rates.extend((0..6).map(|k| (twist[k], accel[k])));
    let sdd = g.tangents(&sd, &rates);
    let columns: Vec<Vec<Expr<'g>>> = twist.iter().map(|&w| g.derivatives(&sd, w)).collect();
    // The symbols replaced by the kernel's expressions.
    let (rotation, centre) = placement;
    let values: Vec<(Expr<'g>, Expr<'g>)> = (0..9)
        .map(|k| (r_hat[k], rotation.0[k / 3][k % 3]))
        .chain((0..3).map(|k| (c_hat[k], centre[k])))
        .chain(points.iter().flat_map(|(symbol, p)| {
            // A unit, so that with `p` constant its three products are not re-evaluated in
            // every expression that reads the point.
            let at = *rotation * *p;
            (0..3).map(move |k| (symbol[k], at[k].keep()))
        }))
        .chain((0..6).map(|k| (twist[k], motion.twist[k])))
        .chain((0..6).map(|k| (accel[k], motion.accel[k])))
        .collect();
    let n = s.len();
    let flat: Vec<Expr<'g>> = s
        .iter()
        .chain(&sd)
        .chain(&sdd)
        .chain(columns.iter().flatten())
        .copied()
        .collect();
    let all = g.substitute(&flat, &values);
    CoordinateMotion {
        s: all[..n].to_vec(),
        sd: all[n..2 * n].to_vec(),
        sdd: all[2 * n..3 * n].to_vec(),
        t: (0..n)
            .map(|k| Vector::from_fn(|j| all[3 * n + j * n + k]))
            .collect(),
    }
}

/// One body's angular velocity in its own frame per unit coordinate rate: column `k` is
/// `vee(Rᵀ ∂R/∂s_k) = (z·∂y, x·∂z, y·∂x)` for the body's axes `x, y, z`.
pub fn derived_angular_rates<'g>(rotation: &Mat3<'g>, s: &[Expr<'g>]) -> Vec<Vec3<'g>> {
    let g = s[0].graph();
    angular_rates_by(rotation, s.len(), &|v, k| g.derivatives(v, s[k]))
}

/// [`derived_angular_rates`] with the partial derivative `∂v/∂s_k` given as `partial(v, k)`, for
/// `n` coordinates.
fn angular_rates_by<'g>(
    rotation: &Mat3<'g>,
    n: usize,
    partial: &dyn Fn(&[Expr<'g>], usize) -> Vec<Expr<'g>>,
) -> Vec<Vec3<'g>> {
    let axes: Vec<Expr<'g>> = rotation.rows();
    (0..n)
        .map(|k| {
            let d = partial(&axes, k);
            let dm: Mat3<'g> = Mat::from_fn(|i, j| d[3 * i + j]);
            let (x, y, z) = (rotation.column(0), rotation.column(1), rotation.column(2));
            let (dx, dy, dz) = (dm.column(0), dm.column(1), dm.column(2));
            Vector([z.dot(&dy), x.dot(&dz), y.dot(&dx)])
        })
        .collect()
}

/// Adds `load` to the entry of `map` in `list`, or a new entry.
fn add_to<'g>(list: &mut Vec<(Vec<Vec3<'g>>, Vec3<'g>)>, map: Vec<Vec3<'g>>, load: Vec3<'g>) {
    let same = |a: &[Vec3<'g>], b: &[Vec3<'g>]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| x.0.iter().zip(&y.0).all(|(p, q)| p.id == q.id))
    };
    match list.iter_mut().find(|(m, _)| same(m, &map)) {
        Some((_, total)) => *total = *total + load,
        None => list.push((map, load)),
    }
}

/// Adds one body's `Jᵀ I J` to the lower triangle of `mass` (row-major `n × n`), from its
/// velocity `v_l` and angular velocity `ω_l` per unit rate `ṡ_l`, both in its frame
/// ([`MassMatrix::Energy`]).
fn add_energy_mass<'g>(
    mass: &mut [Expr<'g>],
    body: &Inertial<'g>,
    velocities: &[Vec3<'g>],
    angular: &[Vec3<'g>],
) {
    let n = velocities.len();
    let h = body.first_moment;
    for l in 0..n {
        let (v, w) = (velocities[l], angular[l]);
        let momentum = Vector((v.scale(body.mass) + w.cross(&h)).0.map(Expr::keep));
        let angular_momentum = Vector((body.inertia * w + h.cross(&v)).0.map(Expr::keep));
        for k in l..n {
            mass[k * n + l] =
                mass[k * n + l] + velocities[k].dot(&momentum) + angular[k].dot(&angular_momentum);
        }
    }
}

/// What a leg gives, derived on its coordinate symbols `s`, `ṡ`, `s̈`.
struct LegEquations<'g> {
    q: Expr<'g>,
    grad: Vec<Expr<'g>>,
    qdd: Expr<'g>,
    /// The generalized force on the coordinates that moves the leg's bodies against gravity.
    phi: Vec<Expr<'g>>,
    /// `∂φ/∂s̈`, row-major `n × n`: the leg's mass matrix in its coordinates (`φ` is affine in
    /// `s̈`).
    mass: Vec<Expr<'g>>,
    /// `φ₀`, `φ` at `s̈ = 0`.
    phi_at_rest: Vec<Expr<'g>>,
}

/// A leg's coordinate symbols `s` (its own, then its hidden quantities'), `ṡ`, `s̈`, and the
/// derivatives the derivation takes on them.
struct LegSymbols<'g> {
    g: &'g Graph,
    n: usize,
    all: Vec<Expr<'g>>,
    sd: Vec<Expr<'g>>,
    sdd: Vec<Expr<'g>>,
    hidden: Vec<Hidden<'g>>,
    /// The time derivative of every symbol: `ṡ`, `s̈`, and each hidden quantity's rate.
    rates: Vec<(Expr<'g>, Expr<'g>)>,
}

impl<'g> LegSymbols<'g> {
    fn new(leg: &dyn Leg<'g>, g: &'g Graph, n: usize) -> Self {
        let m = n + leg.hidden_count();
        assert!(m <= MAX_COORDINATES, "a leg of {m} coordinates");
        let all = symbols(g, LEG_SYMBOLS, m);
        let sd = symbols(g, LEG_SYMBOLS + MAX_COORDINATES as u32, n);
        let sdd = symbols(g, LEG_SYMBOLS + 2 * MAX_COORDINATES as u32, n);
        let hidden = leg.hidden(&all);
        let rates = (0..n)
            .map(|k| (all[k], sd[k]))
            .chain((0..n).map(|k| (sd[k], sdd[k])))
            .chain(
                all[n..]
                    .iter()
                    .zip(&hidden)
                    .map(|(&h, q)| (h, dot(&q.gradient, &sd))),
            )
            .collect();
        LegSymbols {
            g,
            n,
            all,
            sd,
            sdd,
            hidden,
            rates,
        }
    }

    /// `∂v/∂s_k`, through the hidden symbols by the chain rule.
    fn partial(&self, v: &[Expr<'g>], k: usize) -> Vec<Expr<'g>> {
        let rates: Vec<(Expr<'g>, Expr<'g>)> = std::iter::once((self.all[k], self.g.one()))
            .chain(
                self.all[self.n..]
                    .iter()
                    .zip(&self.hidden)
                    .map(|(&h, q)| (h, q.gradient[k])),
            )
            .collect();
        self.g.tangents(v, &rates)
    }

    fn time_derivative(&self, v: &[Expr<'g>]) -> Vec<Expr<'g>> {
        self.g.tangents(v, &self.rates)
    }

    /// `v` at `s̈ = 0`.
    fn at_rest(&self, v: &[Expr<'g>]) -> Vec<Expr<'g>> {
        let zeros: Vec<(Expr<'g>, Expr<'g>)> =
            self.sdd.iter().map(|&a| (a, self.g.zero())).collect();
        self.g.substitute(v, &zeros)
    }

    /// `Σₖ columnsₖ weightsₖ`.
    fn combine(&self, columns: &[Vec3<'g>], weights: &[Expr<'g>]) -> Vec3<'g> {
        (0..self.n).fold(Vec3::zeros(self.g), |sum, k| {
            sum + columns[k].scale(weights[k])
        })
    }

    /// A body's angular motion: the leg type's closed form, or derived from its rates (given
    /// or derived from its rotation).
    fn angular_motion(&self, body: &LegBody<'g>) -> AngularMotion<'g> {
        body.angular.clone().unwrap_or_else(|| {
            let rates = body.angular_rates.clone().unwrap_or_else(|| {
                angular_rates_by(&body.rotation, self.n, &|v: &[Expr<'g>], k| {
                    self.partial(v, k)
                })
            });
            let omega = self.combine(&rates, &self.sd);
            let bias = self.at_rest(&self.time_derivative(&omega.to_vec()));
            AngularMotion {
                rates,
                bias: vec3(&bias),
            }
        })
    }

    /// A body's origin's acceleration in the body's frame, from the leg type's closed forms
    /// where it gives them; `linear` is the origin's `∂/∂s_k` (base frame).
    fn origin_acceleration(&self, body: &LegBody<'g>, linear: &[Vec3<'g>]) -> Vec3<'g> {
        let to_body = body.rotation.transpose();
        match (&body.velocity_rates, body.acceleration_bias) {
            (Some(velocities), Some(bias)) => self.combine(velocities, &self.sdd) + to_body * bias,
            (None, Some(bias)) => to_body * (self.combine(linear, &self.sdd) + bias),
            (_, None) => {
                let velocity = self.combine(linear, &self.sd).to_vec();
                to_body * vec3(&self.time_derivative(&velocity))
            }
        }
    }
}

/// The loads a leg's bodies put on its coordinates, grouped by the map that reads them:
/// bodies that turn alike (one angular map) add their moments before the map's transpose
/// reads them, and those whose origins move alike add their forces.
#[derive(Default)]
struct Loads<'g> {
    moments: Vec<(Vec<Vec3<'g>>, Vec3<'g>)>,
    forces: Vec<(Vec<Vec3<'g>>, Vec3<'g>)>,
}

impl<'g> Loads<'g> {
    /// `φ = Σ Gᵀ F` by virtual work.
    fn generalized_force(&self, g: &'g Graph, n: usize) -> Vec<Expr<'g>> {
        let mut phi = vec![g.zero(); n];
        for (map, load) in self.moments.iter().chain(&self.forces) {
            for k in 0..n {
                phi[k] = phi[k] + map[k].dot(load);
            }
        }
        phi
    }
}

/// The leg's actuator and bodies differentiated on its coordinate symbols; the bodies'
/// Newton-Euler wrenches under `gravity`, and their generalized force by virtual work.
fn leg_equations<'g>(
    leg: &dyn Leg<'g>,
    g: &'g Graph,
    n: usize,
    gravity: &Vec3<'g>,
) -> (LegEquations<'g>, [Vec<Expr<'g>>; 3]) {
    let symbols = LegSymbols::new(leg, g, n);
    let (all, sd, sdd) = (&symbols.all, &symbols.sd, &symbols.sdd);
    let q = leg.actuator(all);
    let grad: Vec<Expr<'g>> = leg
        .actuator_gradient(all)
        .unwrap_or_else(|| (0..n).map(|k| symbols.partial(&[q], k)[0]).collect());
    let qdd = symbols.time_derivative(&[dot(&grad, sd)])[0];
    let mut energy_mass = vec![g.zero(); n * n];
    let mut loads = Loads::default();
    for body in leg.bodies(all, sd) {
        let angular = symbols.angular_motion(&body);
        let linear: Vec<Vec3<'g>> = (0..n)
            .map(|k| vec3(&symbols.partial(&body.origin.to_vec(), k)))
            .collect();
        // The body's motion in its frame as units: the Newton-Euler products read them whole
        // instead of re-multiplying their factors in every term.
        let unit = |v: Vec3<'g>| Vector(v.0.map(Expr::keep));
        let to_body = body.rotation.transpose();
        if leg.mass_matrix() == MassMatrix::Energy {
            let velocities = body
                .velocity_rates
                .clone()
                .unwrap_or_else(|| linear.iter().map(|c| unit(to_body * *c)).collect());
            add_energy_mass(
                &mut energy_mass,
                &body.inertial,
                &velocities,
                &angular.rates,
            );
        }
        let frame = Frame {
            r: body.rotation,
            omega: unit(symbols.combine(&angular.rates, sd)),
            omega_dot: unit(symbols.combine(&angular.rates, sdd) + angular.bias),
        };
        let wrench = wrench_in_platform_frame(
            &body.inertial,
            &frame,
            &unit(symbols.origin_acceleration(&body, &linear)),
            &unit(to_body * *gravity),
        );
        add_to(&mut loads.moments, angular.rates, wrench.top());
        match body.velocity_rates {
            // Its force read in its own frame, as its velocity is given.
            Some(velocities) => add_to(&mut loads.forces, velocities, wrench.bottom()),
            None if linear
                .iter()
                .any(|c| c.0.iter().any(|e| e.as_const() != Some(0.0))) =>
            {
                add_to(&mut loads.forces, linear, body.rotation * wrench.bottom());
            }
            None => {}
        }
    }
    let phi = loads.generalized_force(g, n);
    let lower = match leg.mass_matrix() {
        MassMatrix::Energy => energy_mass,
        MassMatrix::Differentiated => {
            // `∂φ_i/∂s̈_l` at `l n + i`.
            let columns: Vec<Expr<'g>> = sdd.iter().flat_map(|&a| g.derivatives(&phi, a)).collect();
            (0..n * n).map(|k| columns[k % n + (k / n) * n]).collect()
        }
    };
    // Entry `(i, l)` of the mass matrix at `i n + l`, each pair formed once (it is symmetric).
    let mass = (0..n * n).map(|k| lower[(k / n).max(k % n) * n + (k / n).min(k % n)]);
    let phi_at_rest = symbols.at_rest(&phi);
    let flat: Vec<Expr<'g>> = [q, qdd]
        .into_iter()
        .chain(grad)
        .chain(phi)
        .chain(mass)
        .chain(phi_at_rest)
        .collect();
    // The hidden symbols replaced by their closed forms.
    let values: Vec<(Expr<'g>, Expr<'g>)> = all[n..]
        .iter()
        .zip(&symbols.hidden)
        .map(|(&h, q)| (h, q.value))
        .collect();
    let flat = if values.is_empty() {
        flat
    } else {
        g.substitute(&flat, &values)
    };
    let equations = LegEquations {
        q: flat[0],
        qdd: flat[1],
        grad: flat[2..2 + n].to_vec(),
        phi: flat[2 + n..2 + 2 * n].to_vec(),
        mass: flat[2 + 2 * n..2 + 2 * n + n * n].to_vec(),
        phi_at_rest: flat[2 + 2 * n + n * n..].to_vec(),
    };
    (equations, [all[..n].to_vec(), symbols.sd, symbols.sdd])
}

/// One leg at the platform's state: its actuator's value, rate and acceleration, its row of
/// `J⁻¹`, and the wrench at `C` (base frame) its bodies need, `Tᵀ φ`.
pub struct LegState<'g> {
    pub q: Expr<'g>,
    pub qd: Expr<'g>,
    pub qdd: Expr<'g>,
    pub jinv_row: Vec6<'g>,
    pub wrench: Vec6<'g>,
    /// [`Leg::unit_translation`].
    pub unit_translation: bool,
    /// [`LegState::wrench`] as `Tᵀ (φ₀ + M s̈)`: the same value, cheaper where `M` is formed
    /// anyway (the forward dynamics), for then only `φ₀` balances the bodies.
    pub wrench_through_mass: Vec6<'g>,
    /// `∂(Tᵀ φ)/∂V̇ = Tᵀ (∂φ/∂s̈) T`, lower triangle: the leg's part of `M_x`.
    pub inertia: Mat6<'g>,
}

/// `leg` at the platform's placement (`R`, `C`) and motion, its bodies under `gravity`.
pub fn leg_state<'g>(
    leg: &dyn Leg<'g>,
    placement: &(Mat3<'g>, Vec3<'g>),
    motion: &Motion<'g>,
    gravity: &Vec3<'g>,
) -> LegState<'g> {
    let g = placement.1[0].graph();
    let coordinates = coordinate_motion(leg, placement, motion);
    let n = coordinates.s.len();
    let (equations, [s, sd, sdd]) = leg_equations(leg, g, n, gravity);
    let values: Vec<(Expr<'g>, Expr<'g>)> = (0..n)
        .flat_map(|k| {
            [
                (s[k], coordinates.s[k]),
                (sd[k], coordinates.sd[k]),
                (sdd[k], coordinates.sdd[k]),
            ]
        })
        .collect();
    let flat: Vec<Expr<'g>> = [equations.q, equations.qdd]
        .into_iter()
        .chain(equations.grad)
        .chain(equations.phi)
        .chain(equations.mass)
        .chain(equations.phi_at_rest)
        .collect();
    let all = g.substitute(&flat, &values);
    let (grad, phi) = (&all[2..2 + n], &all[2 + n..2 + 2 * n]);
    let (mass, phi_at_rest) = all[2 + 2 * n..].split_at(n * n);
    // `φ = φ₀ + M s̈`.
    let through_mass: Vec<Expr<'g>> = (0..n)
        .map(|i| {
            (0..n).fold(phi_at_rest[i], |sum, l| {
                sum + mass[i * n + l] * coordinates.sdd[l]
            })
        })
        .collect();
    let along = |weights: &[Expr<'g>]| {
        (0..n).fold(Vec6::zeros(g), |sum, k| {
            sum + coordinates.t[k].scale(weights[k])
        })
    };
    let jinv_row = along(grad);
    LegState {
        q: all[0],
        qd: jinv_row.dot(&motion.twist),
        qdd: all[1],
        jinv_row,
        wrench: along(phi),
        wrench_through_mass: along(&through_mass),
        unit_translation: leg.unit_translation(),
        inertia: projected_inertia(&coordinates.t, mass),
    }
}

/// `Tᵀ M T`, lower triangle (the rest zero): a leg's mass matrix `M` in its coordinates seen
/// from the platform's acceleration, `T = ∂ṡ/∂V` (rows `t`). With `M T` formed once, each entry
/// costs `n` products.
fn projected_inertia<'g>(t: &[Vec6<'g>], mass: &[Expr<'g>]) -> Mat6<'g> {
    let n = t.len();
    let g = t[0][0].graph();
    let mt: Vec<Vec6<'g>> = (0..n)
        .map(|i| {
            let row = (0..n).fold(Vec6::zeros(g), |sum, l| sum + t[l].scale(mass[i * n + l]));
            Vector(row.0.map(Expr::keep))
        })
        .collect();
    Mat::from_fn(|a, b| {
        if b > a {
            g.zero()
        } else {
            (0..n).fold(g.zero(), |sum, k| sum + t[k][a] * mt[k][b])
        }
    })
}

/// Every leg at the platform's state.
pub fn leg_states<'g>(
    legs: &[Box<dyn Leg<'g> + 'g>],
    placement: &(Mat3<'g>, Vec3<'g>),
    motion: &Motion<'g>,
    gravity: &Vec3<'g>,
) -> Vec<LegState<'g>> {
    legs.iter()
        .map(|leg| leg_state(leg.as_ref(), placement, motion, gravity))
        .collect()
}

/// The [`super::Mechanics`] methods of a mechanism that implements [`Legs`], in its impl
/// block: `J⁻¹` from the legs' rows, `J` and the inverse dynamics through the normal
/// equations, the rates, accelerations and the legs' wrench from the derivation.
macro_rules! legged_mechanics {
    () => {
        fn inverse_jacobian<'g>(
            &self,
            posed: &$crate::model::geometry::Posed<'g>,
        ) -> $crate::linalg::Mat6<'g> {
            $crate::model::legged::rows_at(self, posed).m
        }

        fn jacobian<'g>(
            &self,
            posed: &$crate::model::geometry::Posed<'g>,
        ) -> $crate::linalg::Mat6<'g> {
            $crate::model::legged::jacobian(&$crate::model::legged::rows_at(self, posed))
        }

        fn joint_velocities<'g>(
            &self,
            posed: &$crate::model::geometry::Posed<'g>,
            twist: &$crate::linalg::Vec6<'g>,
        ) -> $crate::linalg::Vec6<'g> {
            self.inverse_jacobian(posed) * *twist
        }

        fn joint_accelerations<'g>(
            &self,
            posed: &$crate::model::geometry::Posed<'g>,
            motion: &$crate::model::geometry::Motion<'g>,
        ) -> $crate::linalg::Vec6<'g> {
            let legs = $crate::model::legged::states_at(self, posed, motion, None);
            $crate::linalg::Vector::from_fn(|i| legs[i].qdd)
        }

        fn leg_wrench<'g>(
            &self,
            dynamics: &$crate::model::bodies::Dynamics<'g>,
            posed: &$crate::model::geometry::Posed<'g>,
            motion: &$crate::model::geometry::Motion<'g>,
        ) -> $crate::linalg::Vec6<'g> {
            $crate::model::legged::leg_wrench(&$crate::model::legged::states_at(
                self,
                posed,
                motion,
                Some(dynamics),
            ))
        }

        fn task_inertia<'g>(
            &self,
            dynamics: &$crate::model::bodies::Dynamics<'g>,
            posed: &$crate::model::geometry::Posed<'g>,
        ) -> $crate::linalg::Mat6<'g> {
            $crate::model::legged::task_inertia(self, dynamics, posed)
        }

        fn forward_dynamics<'g>(
            &self,
            dynamics: &$crate::model::bodies::Dynamics<'g>,
            posed: &$crate::model::geometry::Posed<'g>,
            twist: &$crate::linalg::Vec6<'g>,
            gamma: &$crate::linalg::Vec6<'g>,
        ) -> $crate::linalg::Vec6<'g> {
            $crate::model::legged::forward_dynamics(self, dynamics, posed, twist, gamma)
        }

        fn inverse_dynamics<'g>(
            &self,
            dynamics: &$crate::model::bodies::Dynamics<'g>,
            posed: &$crate::model::geometry::Posed<'g>,
            motion: &$crate::model::geometry::Motion<'g>,
        ) -> $crate::linalg::Vec6<'g> {
            let wrench = self.task_wrench(dynamics, posed, motion);
            let rows = $crate::model::legged::rows_at(self, posed);
            $crate::model::legged::solve_transposed(&rows, &wrench)
        }

        fn inverse_dynamics_jacobians<'g>(
            &self,
            dynamics: &$crate::model::bodies::Dynamics<'g>,
            posed: &$crate::model::geometry::Posed<'g>,
            motion: &$crate::model::geometry::Motion<'g>,
            gamma: &$crate::linalg::Vec6<'g>,
            wrt: &[Vec<$crate::Expr<'g>>],
        ) -> Vec<Vec<$crate::Expr<'g>>> {
            let wrench = self.task_wrench(dynamics, posed, motion).to_vec();
            let rows = $crate::model::legged::rows_at(self, posed);
            let six = |v: &[$crate::Expr<'g>]| $crate::linalg::Vector::from_fn(|i| v[i]);
            let inertia = self.task_inertia(dynamics, posed);
            $crate::model::derivatives::by_wrench_residual(
                &wrench,
                |x| (rows.m.transpose() * six(x)).to_vec(),
                &gamma.to_vec(),
                |w| $crate::model::legged::solve_transposed(&rows, &six(w)).to_vec(),
                |x| {
                    let k = motion.accel.0.iter().position(|a| a.id == x.id)?;
                    Some(inertia.column(k).to_vec())
                },
                wrt,
            )
        }
    };
}
pub(crate) use legged_mechanics;

/// The kernels of the shared table a legged mechanism lacks: the C5's closed forms (its
/// forward kinematics and what reads actuator positions, its plates' limits) and its divisors;
/// a legged mechanism has its own singularity terms.
pub const LACKS: &[super::Kernel] = &[
    super::Kernel::SingularityTerms,
    super::Kernel::ForwardKinematics,
    super::Kernel::RpyAngles,
    super::Kernel::PlatformTwist,
    super::Kernel::PlatformAcceleration,
    super::Kernel::PlatformState,
    super::Kernel::InverseDynamicsJoint,
    super::Kernel::JointInertia,
    super::Kernel::JointBias,
    super::Kernel::LimitGeometry,
    super::Kernel::InverseDynamicsJointDerivatives,
];

/// A mechanism whose platform rides on six legs of known types: the legs, from its geometric
/// parameters and (for the dynamics) its bodies' parameters.
pub trait Legs: Sync {
    /// The legs in actuator order; massless without `dynamics`.
    fn legs<'g>(
        &self,
        geometry: &[Expr<'g>],
        dynamics: Option<&Dynamics<'g>>,
    ) -> Vec<Box<dyn Leg<'g> + 'g>>;
    /// [`Rows::translation_weight`] from the geometric parameters; default none.
    fn translation_weight<'g>(&self, _geometry: &[Expr<'g>]) -> Option<Expr<'g>> {
        None
    }
}

/// The legs of `mechanism` at the pose and motion, under the dynamics' gravity (or none, for
/// kinematics).
pub fn states_at<'g>(
    mechanism: &dyn Legs,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
    dynamics: Option<&Dynamics<'g>>,
) -> Vec<LegState<'g>> {
    let g = posed.c[0].graph();
    let placement = (posed.r, posed.c);
    let gravity = dynamics.map_or(Vec3::zeros(g), |d| d.gravity);
    leg_states(
        &mechanism.legs(&posed.geometry, dynamics),
        &placement,
        motion,
        &gravity,
    )
}

/// The legs of `mechanism` at the pose with the platform at rest, massless: what `J⁻¹`, `J`
/// and the solve read.
pub fn rows_at<'g>(mechanism: &dyn Legs, posed: &Posed<'g>) -> Rows<'g> {
    let g = posed.c[0].graph();
    let rest = Motion::new(Vec6::zeros(g), Vec6::zeros(g));
    Rows {
        translation_weight: mechanism.translation_weight(&posed.geometry),
        ..Rows::of(&states_at(mechanism, posed, &rest, None))
    }
}

/// `M_x = ∂W/∂(ω̇; a_C)` of `mechanism` at the pose: the platform's part, differentiated,
/// plus each leg's `Tᵀ (∂φ/∂s̈) T` (a leg's mass matrix in its few coordinates, projected),
/// instead of every leg body's Newton-Euler differentiated by each of the six accelerations.
/// Symmetric, both triangles filled.
pub fn task_inertia<'g>(
    mechanism: &dyn Legs,
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
) -> Mat6<'g> {
    let g = posed.c[0].graph();
    let rest = Motion::new(Vec6::zeros(g), Vec6::zeros(g));
    let legs = states_at(mechanism, posed, &rest, Some(dynamics));
    let unknown: Vec6<'g> = Vector::from_fn(|k| g.input(super::INTERNAL_INPUTS + k as u32));
    let frame = super::bodies::Frame::new(posed.r, &Vec3::zeros(g), &unknown.top());
    let platform =
        super::bodies::platform_wrench(dynamics, &frame, &Vec6::zeros(g), &unknown).to_vec();
    let columns: Vec<Vec<Expr<'g>>> = unknown
        .0
        .iter()
        .map(|&u| g.derivatives(&platform, u))
        .collect();
    let lower: Mat6<'g> = Mat::from_fn(|a, b| {
        if b > a {
            g.zero()
        } else {
            let legs = legs
                .iter()
                .fold(g.zero(), |sum, leg| sum + leg.inertia.0[a][b]);
            (columns[b][a] + legs).keep()
        }
    });
    Mat::from_fn(|a, b| lower.0[a.max(b)][a.min(b)])
}

/// The direct dynamic model, `M_x V̇ = J⁻ᵀ Γ - h`, with each leg's part of `h` formed as
/// `Tᵀ (φ₀ + M s̈₀)` ([`LegState::wrench_through_mass`]): `M` is already `M_x`'s, so the legs'
/// bodies are balanced at `s̈ = 0` only, where their Newton-Euler terms lose every product
/// with `s̈`.
pub fn forward_dynamics<'g>(
    mechanism: &dyn Legs,
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    gamma: &Vec6<'g>,
) -> Vec6<'g> {
    let g = posed.c[0].graph();
    let at_rest = Vec6::zeros(g);
    let motion = Motion::new(*twist, at_rest);
    let legs = states_at(mechanism, posed, &motion, Some(dynamics));
    let frame = super::bodies::Frame::new(posed.r, &twist.top(), &at_rest.top());
    let bias = legs.iter().fold(
        super::bodies::platform_wrench(dynamics, &frame, twist, &at_rest),
        |sum, leg| sum + leg.wrench_through_mass,
    );
    let driving = inverse_jacobian(&legs).transpose() * *gamma;
    task_inertia(mechanism, dynamics, posed).ldlt_solve(&(driving - bias))
}

/// `J⁻¹` from the legs' rows.
pub fn inverse_jacobian<'g>(states: &[LegState<'g>]) -> Mat6<'g> {
    Mat(std::array::from_fn(|i| states[i].jinv_row.0))
}

/// `J⁻¹` with what the solve may know of its rows: which translation parts are unit vectors,
/// and the weight of the translation columns.
#[derive(Clone, Copy)]
pub struct Rows<'g> {
    pub m: Mat6<'g>,
    pub unit_translation: [bool; 6],
    /// `ℓ²` of the normal equations `M D² Mᵀ`, `D = diag(1, 1, 1, ℓ, ℓ, ℓ)`, where the rows'
    /// rotation parts (rad per rad) and translation parts (per metre) differ by a length
    /// `ℓ`: balanced, the pivots measure the legs' hold rather than the units (a rotary
    /// hexapod's rows are nearly alike in their translation parts, and unweighted its pivots
    /// are 1e-3 at home). `None`: `D = I`.
    pub translation_weight: Option<Expr<'g>>,
}

impl<'g> Rows<'g> {
    pub fn of(states: &[LegState<'g>]) -> Self {
        Rows {
            m: inverse_jacobian(states),
            unit_translation: std::array::from_fn(|i| states[i].unit_translation),
            translation_weight: None,
        }
    }

    /// `D² v`.
    fn weighted(&self, v: &Vec6<'g>) -> Vec6<'g> {
        match self.translation_weight {
            Some(w) => Vector::from_fn(|k| if k < 3 { v[k] } else { v[k] * w }),
            None => *v,
        }
    }

    /// `a D² b` of two rows.
    fn product(&self, a: &Vec6<'g>, b: &Vec6<'g>) -> Expr<'g> {
        match self.translation_weight {
            Some(w) => a.top().dot(&b.top()) + a.bottom().dot(&b.bottom()) * w,
            None => a.dot(b),
        }
    }
}

/// `Σ Tᵀ φ`: the wrench at `C` (base frame) the legs' bodies need, `Φ` of
/// `Γ = Jᵀ (F_{N+1} + Φ)`.
pub fn leg_wrench<'g>(states: &[LegState<'g>]) -> Vec6<'g> {
    let g = states[0].q.graph();
    states
        .iter()
        .fold(Vec6::zeros(g), |sum, leg| sum + leg.wrench)
}

/// `x` with `J⁻ᵀ x = w`, `M = J⁻¹`: through the normal equations `M Mᵀ x = M w`, whose
/// matrix is symmetric positive definite wherever `M` is regular, so the unrolled `LDLᵀ` needs
/// no pivoting.
pub fn solve_transposed<'g>(rows: &Rows<'g>, w: &Vec6<'g>) -> Vec6<'g> {
    normal_solve(rows, &(rows.m * rows.weighted(w)))
}

/// `L` and `D` of `A = L D Lᵀ` (lower triangle of `A` read), with `L_ik D_k` kept as units:
/// each term of the recursion then costs one product, not two.
fn ldlt<'g>(a: &Mat6<'g>) -> ([[Expr<'g>; 6]; 6], [Expr<'g>; 6]) {
    let g = a.0[0][0].graph();
    let mut l = [[g.zero(); 6]; 6];
    let mut ld = [[g.zero(); 6]; 6];
    let mut d = [g.zero(); 6];
    for j in 0..6 {
        d[j] = (0..j)
            .fold(a.0[j][j], |acc, k| acc - ld[j][k] * l[j][k])
            .keep();
        let d_inv = d[j].recip();
        for i in j + 1..6 {
            ld[i][j] = (0..j)
                .fold(a.0[i][j], |acc, k| acc - ld[i][k] * l[j][k])
                .keep();
            l[i][j] = (ld[i][j] * d_inv).keep();
        }
    }
    (l, d)
}

/// `M D² Mᵀ`, lower triangle (the `LDLᵀ` reads nothing else; the upper is its mirror); a
/// row's unit translation part adds `ℓ²` (one) to its diagonal entry.
pub fn normal_matrix<'g>(rows: &Rows<'g>) -> Mat6<'g> {
    let r: [Vec6<'g>; 6] = std::array::from_fn(|i| rows.m.row(i));
    let g = rows.m.0[0][0].graph();
    Mat::from_fn(|i, j| {
        if j < i {
            rows.product(&r[i], &r[j])
        } else if j == i && rows.unit_translation[i] {
            r[i].top().dot(&r[i].top()) + rows.translation_weight.unwrap_or(g.one())
        } else if j == i {
            rows.product(&r[i], &r[i])
        } else {
            g.zero()
        }
    })
}

/// `J = (J⁻¹)⁻¹`: column `j` solves `M x = e_j`, that is `x = D² Mᵀ y` with
/// `M D² Mᵀ y = e_j`, one factorization for the six columns.
pub fn jacobian<'g>(rows: &Rows<'g>) -> Mat6<'g> {
    let g = rows.m.0[0][0].graph();
    let mt = rows.m.transpose();
    let columns: Vec<Vec6<'g>> = (0..6)
        .map(|j| {
            let e: Vec6<'g> = Vector::from_fn(|i| if i == j { g.one() } else { g.zero() });
            rows.weighted(&(mt * normal_solve(rows, &e)))
        })
        .collect();
    Mat::from_fn(|i, j| columns[j][i])
}

/// `y` with `M Mᵀ y = b`.
fn normal_solve<'g>(rows: &Rows<'g>, b: &Vec6<'g>) -> Vec6<'g> {
    let (l, d) = ldlt(&normal_matrix(rows));
    let g = b[0].graph();
    let mut z = [g.zero(); 6];
    for i in 0..6 {
        z[i] = (0..i).fold(b[i], |acc, k| acc - l[i][k] * z[k]);
    }
    let mut y = [g.zero(); 6];
    for i in (0..6).rev() {
        y[i] = (i + 1..6).fold(z[i] * d[i].recip(), |acc, k| acc - l[k][i] * y[k]);
    }
    Vector(y)
}

/// The pivots of the `LDLᵀ` of `M Mᵀ` over its diagonal: each in `(0, 1]` where `M` is regular
/// (their product is `det(M)² / Π |m_i|²`, one at orthogonal rows); the solve loses about as
/// many digits as the smallest takes from one.
pub fn pivot_ratios<'g>(rows: &Rows<'g>) -> Vec<Expr<'g>> {
    let a = normal_matrix(rows);
    ldlt_pivots(&a)
        .into_iter()
        .enumerate()
        .map(|(j, d)| d / a.0[j][j])
        .collect()
}

/// The pivots `D_jj` of the unrolled `LDLᵀ` of a symmetric matrix (lower triangle): the
/// same expressions [`solve_transposed`] divides by.
fn ldlt_pivots<'g>(m: &Mat6<'g>) -> Vec<Expr<'g>> {
    ldlt(m).1.to_vec()
}

#[cfg(test)]
mod tests;
