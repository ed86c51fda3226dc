//! The derivation against the hand-derived models, and the closed forms of the leg types
//! against the derivation.

use super::psp::Psp;
use super::ups::Ups;
use super::*;
use crate::dag::{Graph, Policy};
use crate::model::bodies::{platform_wrench, Dynamics};
use crate::model::{consistent, geometry, lopsided};
use crate::numeric::Lcg;

fn values<const N: usize>(v: &Vector<'_, N>) -> [f64; N] {
    v.0.map(|e| e.as_const().expect("every input is a constant"))
}

fn close(got: &[f64], want: &[f64], bound: f64) -> bool {
    let scale = want.iter().fold(1.0_f64, |m, w| m.max(w.abs()));
    got.iter()
        .zip(want)
        .all(|(g, w)| (g - w).abs() <= bound * scale)
}

/// Proof the layer is general: the C5 described as six P-S-PP legs, through the derivation of
/// this module (coordinates, exact derivatives, virtual work, normal equations), equals the
/// consistent model's hand-derived `J⁻¹`, `Q̇`, `Q̈`, `Φ` and `Γ` to 1e-12, on a robot whose
/// bodies sit off their reference points, at seeded states. The graph folds constant inputs,
/// so each side is a number.
#[test]
fn the_c5_from_its_legs_is_the_consistent_model() {
    let g = Graph::new(Policy::FLAT);
    let params: Vec<_> = lopsided()
        .kernel_parameters()
        .into_iter()
        .map(|v| g.constant(v))
        .collect();
    let dynamics = Dynamics::from_kernel_parameters(&params);
    let legs: Vec<Box<dyn Leg<'_> + '_>> = (0..6)
        .map(|i| {
            Box::new(Psp {
                segment: i,
                anchor: geometry::anchor(params[0], i),
                rod: dynamics.legs[i][0],
                joint: dynamics.legs[i][1],
            }) as Box<dyn Leg<'_>>
        })
        .collect();
    let mut rng = Lcg::new(17);
    for _ in 0..10 {
        let mut constants = |bounds: &[f64]| -> Vec6<'_> {
            let v = rng.vector(bounds);
            Vector::from_fn(|i| g.constant(v[i]))
        };
        let x = constants(&[0.3, 0.3, 0.3, 0.05, 0.05, 0.05]);
        let motion = Motion::new(
            constants(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]),
            constants(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]),
        );
        let posed = geometry::pose(&params[..4], &x.0);
        let states = leg_states(&legs, &(posed.r, posed.c), &motion, &dynamics.gravity);
        let jinv = inverse_jacobian(&states);
        let frame =
            super::super::bodies::Frame::new(posed.r, &motion.twist.top(), &motion.accel.top());
        let wrench =
            platform_wrench(&dynamics, &frame, &motion.twist, &motion.accel) + leg_wrench(&states);
        let gamma = solve_transposed(&Rows::of(&states), &wrench);
        let want_jinv = consistent::inverse_jacobian(&posed);
        for i in 0..6 {
            assert!(
                close(&values(&jinv.row(i)), &values(&want_jinv.row(i)), 1e-12),
                "J⁻¹ row {i}"
            );
        }
        let qd: Vec<f64> = states.iter().map(|s| s.qd.as_const().unwrap()).collect();
        let qdd: Vec<f64> = states.iter().map(|s| s.qdd.as_const().unwrap()).collect();
        let want_qd = values(&consistent::joint_velocities(&posed, &motion.twist));
        let want_qdd = values(&consistent::joint_accelerations(&posed, &motion));
        assert!(close(&qd, &want_qd, 1e-12), "{qd:?} vs {want_qd:?}");
        assert!(close(&qdd, &want_qdd, 1e-12), "{qdd:?} vs {want_qdd:?}");
        let want_phi = values(&consistent::leg_wrench(&dynamics, &posed, &motion));
        assert!(close(&values(&leg_wrench(&states)), &want_phi, 1e-12), "Φ");
        let want = values(&consistent::inverse_dynamics(&dynamics, &posed, &motion));
        assert!(
            close(&values(&gamma), &want, 1e-12),
            "Γ {:?} vs {want:?}",
            values(&gamma)
        );
    }
}

/// The U-P-S leg's closed-form angular motion (its map and its bias) is the one the
/// derivation finds from the leg frame.
#[test]
fn the_ups_closed_forms_are_the_derived_ones() {
    let g = Graph::new(Policy::FLAT);
    let c = |v: [f64; 3]| Vector(v.map(|x| g.constant(x)));
    let axis = {
        let a: [f64; 3] = [-0.3, 0.9, 0.2];
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|x| x / n)
    };
    let inertial = |m: f64| Inertial {
        mass: g.constant(m),
        first_moment: c([0.0, 0.0, 0.1 * m]),
        inertia: Mat::from_values(&g, [[0.02, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.003]]),
    };
    let leg = |closed_form: bool| Ups {
        base: c([0.4, 0.1, 0.0]),
        axis: c(axis),
        platform: c([0.2, 0.15, 0.0]),
        offset: g.constant(0.01),
        cylinder: inertial(2.0),
        rod: inertial(1.0),
        closed_form,
    };
    let mut rng = Lcg::new(23);
    for _ in 0..10 {
        let v = rng.vector(&[0.2, 0.2, 0.1, 0.3, 0.3, 0.3]);
        let s: Vec<_> = [0.3 + v[0], 0.05 + v[1], 0.4 + v[2]]
            .map(|x| g.constant(x))
            .to_vec();
        let sd: Vec<_> = v[3..6].iter().map(|&x| g.constant(x)).collect();
        let closed = leg(true).bodies(&s, &sd);
        let derived = leg(false).bodies(&s, &sd);
        // The derivation on symbols, evaluated at the same coordinates.
        let symbols_s = symbols(&g, LEG_SYMBOLS, 3);
        let symbols_sd = symbols(&g, LEG_SYMBOLS + MAX_COORDINATES as u32, 3);
        let symbolic = leg(false).bodies(&symbols_s, &symbols_sd);
        let rates = derived_angular_rates(&symbolic[0].rotation, &symbols_s);
        let at: Vec<(Expr<'_>, Expr<'_>)> = symbols_s
            .iter()
            .chain(&symbols_sd)
            .copied()
            .zip(s.iter().chain(&sd).copied())
            .collect();
        let omega = (0..3).fold(Vec3::zeros(&g), |sum, k| {
            sum + rates[k].scale(symbols_sd[k])
        });
        let time: Vec<(Expr<'_>, Expr<'_>)> =
            (0..3).map(|k| (symbols_s[k], symbols_sd[k])).collect();
        let bias = vec3(&g.substitute(&g.tangents(&omega.to_vec(), &time), &at));
        let angular = closed[0].angular.as_ref().unwrap();
        for (k, (got, want)) in angular.rates.iter().zip(&rates).enumerate() {
            let want = vec3(&g.substitute(&want.to_vec(), &at));
            assert!(close(&values(got), &values(&want), 1e-13), "G column {k}");
        }
        assert!(close(&values(&angular.bias), &values(&bias), 1e-12), "bias");
        assert!(derived[0].angular.is_none());
    }
}

/// The R-U-S leg's closed forms (the crank angle's gradient, the crank's and the rods' angular
/// motion through the hidden `cos θ`, `sin θ`, the elbow's velocity and acceleration, the mass
/// matrix from the bodies' energy) give the leg's state the plain derivation gives,
/// differentiating the crank angle's closed form through its square root and `φ` by `s̈`: at
/// seeded states of a platform on one leg with a Delta's two rods, under gravity. Each way,
/// `Tᵀ (φ₀ + M s̈)` is `Tᵀ φ`.
#[test]
fn the_rus_closed_forms_are_the_derived_ones() {
    let g = Graph::new(Policy::FLAT);
    let c = |v: [f64; 3]| Vector(v.map(|x| g.constant(x)));
    let unit = |a: [f64; 3]| {
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        c(a.map(|x| x / n))
    };
    let axis = unit([0.97, 0.25, 0.1]);
    let zero = {
        let z = [-0.25, 0.97, 0.0];
        let r = values(&axis);
        let along = z[0] * r[0] + z[1] * r[1] + z[2] * r[2];
        unit([
            z[0] - along * r[0],
            z[1] - along * r[1],
            z[2] - along * r[2],
        ])
    };
    let inertial = |m: f64, first: [f64; 3]| Inertial {
        mass: g.constant(m),
        first_moment: c(first),
        inertia: Mat::from_values(&g, [[0.02, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.004]]),
    };
    let leg = |closed_form: bool| {
        Box::new(rus::Rus {
            base: c([0.3, 0.08, 0.0]),
            axis,
            zero,
            platform: c([0.17, 0.09, -0.015]),
            crank_length: g.constant(0.085),
            rod_length: g.constant(0.34),
            branch: g.constant(-1.0),
            offset: g.constant(0.02),
            crank: inertial(0.35, [0.014, 0.0, 0.0]),
            rod: inertial(0.22, [0.0, 0.0, 0.035]),
            rods: vec![g.constant(0.035), g.constant(-0.035)],
            closed_form,
        }) as Box<dyn Leg<'_> + '_>
    };
    let plain = NoClosedForms(leg(false));
    let gravity = c([0.0, 0.0, -9.81]);
    let mut rng = Lcg::new(31);
    for _ in 0..10 {
        let mut constants = |bounds: &[f64]| -> Vec6<'_> {
            let v = rng.vector(bounds);
            Vector::from_fn(|i| g.constant(v[i]))
        };
        let x = constants(&[0.1, 0.1, 0.1, 0.02, 0.02, 0.02]);
        let x: Vec6<'_> = Vector::from_fn(|i| if i == 5 { x[i] + 0.33 } else { x[i] });
        let motion = Motion::new(
            constants(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]),
            constants(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]),
        );
        let r = super::super::geometry::rotation_of_pose(&x.0);
        let placement = (r, Vector([x[3], x[4], x[5]]));
        let closed = leg_state(leg(true).as_ref(), &placement, &motion, &gravity);
        let derived = leg_state(&plain, &placement, &motion, &gravity);
        let scalars = |s: &LegState<'_>| [s.q, s.qd, s.qdd].map(|e| e.as_const().unwrap());
        assert!(
            close(&scalars(&closed), &scalars(&derived), 1e-12),
            "q, q̇, q̈"
        );
        assert!(
            close(&values(&closed.jinv_row), &values(&derived.jinv_row), 1e-12),
            "J⁻¹ row"
        );
        assert!(
            close(&values(&closed.wrench), &values(&derived.wrench), 1e-11),
            "{:?} vs {:?}",
            values(&closed.wrench),
            values(&derived.wrench)
        );
        let entries = |s: &LegState<'_>| {
            s.inertia
                .rows()
                .iter()
                .map(|e| e.as_const().unwrap())
                .collect::<Vec<f64>>()
        };
        assert!(
            close(&entries(&closed), &entries(&derived), 1e-11),
            "Tᵀ M T"
        );
        for state in [&closed, &derived] {
            assert!(
                close(
                    &values(&state.wrench_through_mass),
                    &values(&state.wrench),
                    1e-11
                ),
                "φ₀ + M s̈"
            );
        }
    }
}

/// A leg seen without its closed forms: no hidden quantities, the actuator's closed form
/// differentiated, every body's angular motion derived.
struct NoClosedForms<'g>(Box<dyn Leg<'g> + 'g>);

impl<'g> Leg<'g> for NoClosedForms<'g> {
    fn coordinates(&self, placement: &Placement<'g>) -> Vec<Expr<'g>> {
        self.0.coordinates(placement)
    }
    fn actuator(&self, s: &[Expr<'g>]) -> Expr<'g> {
        self.0.actuator(&self.with_hidden(s))
    }
    fn bodies(&self, s: &[Expr<'g>], sd: &[Expr<'g>]) -> Vec<LegBody<'g>> {
        let mut bodies = self.0.bodies(&self.with_hidden(s), sd);
        for body in &mut bodies {
            body.angular = None;
            body.angular_rates = None;
            body.velocity_rates = None;
            body.acceleration_bias = None;
        }
        bodies
    }
}

impl<'g> NoClosedForms<'g> {
    /// `s` and the hidden quantities' closed forms in place of their symbols.
    fn with_hidden(&self, s: &[Expr<'g>]) -> Vec<Expr<'g>> {
        let n = s.len();
        let g = s[0].graph();
        let placeholders = symbols(g, LEG_SYMBOLS + n as u32, self.0.hidden_count());
        let all: Vec<Expr<'g>> = s.iter().chain(&placeholders).copied().collect();
        let mut out = s.to_vec();
        out.extend(self.0.hidden(&all).into_iter().map(|h| h.value));
        out
    }
}

/// `M_x` from each leg's mass matrix in its coordinates, `Tᵀ (∂φ/∂s̈) T` plus the platform's
/// ([`task_inertia`]), is the task wrench differentiated by the six accelerations, for both
/// six-legged mechanisms at seeded poses about home (1e-12 of the largest entry).
#[test]
fn the_projected_task_inertia_is_the_differentiated_one() {
    use crate::model::gough_stewart::GoughStewartMechanics;
    use crate::model::rus_hexapod::RusHexapodMechanics;
    use crate::model::{kernels::jacobian_wrt, Mechanics, Mechanism, INTERNAL_INPUTS};
    fn check<M: Mechanics + Legs>(mechanics: &M, mechanism: &Mechanism) {
        let g = Graph::new(Policy::FLAT);
        let params: Vec<_> = mechanism
            .parameters
            .iter()
            .map(|&v| g.constant(v))
            .collect();
        let structure = mechanism.structure();
        let dynamics = structure.dynamics(&params);
        let geometry = &params[..structure.geometry_parameters()];
        let home = structure.home(&mechanism.parameters);
        let mut rng = Lcg::new(23);
        for _ in 0..5 {
            let d = rng.vector(&[0.1, 0.1, 0.1, 0.01, 0.01, 0.01]);
            let x: Vec<_> = (0..6).map(|k| g.constant(home[k] + d[k])).collect();
            let posed = structure.pose(geometry, &x);
            let projected = task_inertia(mechanics, &dynamics, &posed);
            let unknown: Vec6<'_> = Vector::from_fn(|k| g.input(INTERNAL_INPUTS + k as u32));
            let motion = Motion::new(Vec6::zeros(&g), unknown);
            let w = mechanics.task_wrench(&dynamics, &posed, &motion).to_vec();
            let differentiated = jacobian_wrt(&g, &w, &unknown.0);
            let got: Vec<f64> = projected
                .rows()
                .iter()
                .map(|e| e.as_const().unwrap())
                .collect();
            let want: Vec<f64> = differentiated
                .rows()
                .iter()
                .map(|e| e.as_const().unwrap())
                .collect();
            assert!(
                close(&got, &want, 1e-12),
                "{}: {got:?} vs {want:?}",
                mechanics.name()
            );
        }
    }
    check(
        &GoughStewartMechanics,
        &Mechanism::gough_stewart(&c5_robot::GoughStewart::example()),
    );
    check(
        &RusHexapodMechanics,
        &Mechanism::rus_hexapod(&c5_robot::RusHexapod::example()),
    );
}
