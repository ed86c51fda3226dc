//! Identification: the regressor `Y(state)` with `Γ = Y π` over the standard parameters
//! (`c5_robot::standard_parameter_names`), and the base parameters, the combinations of them
//! that the forces determine.
//!
//! The dynamics is linear in each body's standard parameters ([`Dynamics`](super::bodies::Dynamics)), so column `j` of
//! `Y` is the exact derivative `∂Γ/∂π_j`, built by the engine and free of `π`; the friction
//! columns are `Q̇_i1` and `sign(Q̇_i1)`. The base parameters are found the standard way: `Y`
//! stacked over seeded states, QR with column pivoting, the columns of `R` past its numerical
//! rank rebuilt from the others; the base regressor keeps only the independent columns.

use super::kernels::{
    self, Build, Cite, Columns, Context, Decl, Entry, Guard, Input, Kernel, Output, Reads,
};
use super::{Freedom, Mechanics, Mechanism, Quantity, Structure, INTERNAL_INPUTS};
use crate::dag::Expr;
use crate::error::Error;
use crate::kernel::{Compiled, Shape};
use crate::numeric::{pivoted_qr, Lcg};

/// The names of a mechanism's standard parameters, the columns of its regressor: the inertial
/// ones of its structure, then viscous (`fv1`..) and Coulomb (`fc1`..) friction per actuator.
pub fn standard_parameter_names(mech: &dyn Mechanics) -> Vec<String> {
    let structure = mech.structure();
    let mut names = structure.standard_inertial_names();
    let n = structure.actuators();
    names.extend((1..=n).map(|i| format!("fv{i}")));
    names.extend((1..=n).map(|i| format!("fc{i}")));
    names
}

/// The columns of `Y` (each the actuators' entries) for the model's inverse dynamics at the
/// kernel's state, with the bodies' standard parameters as unknowns and gravity as given.
pub fn regressor<'g>(cx: &Context<'_, 'g>) -> Vec<Vec<Expr<'g>>> {
    let (mech, g) = (cx.mech, cx.graph());
    let structure = mech.structure();
    let unknown: Vec<Expr<'g>> = (0..structure.standard_inertial_names().len())
        .map(|j| g.input(INTERNAL_INPUTS + j as u32))
        .collect();
    let dynamics = structure.dynamics_from_standard(g, cx.dynamics.gravity, &unknown);
    let (gamma, qd) = mech.regressor_terms(cx, &dynamics);
    let mut columns: Vec<Vec<Expr<'g>>> =
        unknown.iter().map(|&p| g.derivatives(&gamma, p)).collect();
    // Friction: Γ_f,i = Fv_i Q̇_i1 + Fc_i sign(Q̇_i1).
    let zero = g.zero();
    let only = |k: usize, value: Expr<'g>| {
        (0..qd.len())
            .map(|i| if i == k { value } else { zero })
            .collect::<Vec<_>>()
    };
    columns.extend((0..qd.len()).map(|k| only(k, qd[k])));
    columns.extend((0..qd.len()).map(|k| only(k, qd[k].sign())));
    columns
}

/// Rows of the regressor at the kernel's state, all the columns or those of `columns`, for
/// [`Build::Regressor`](super::kernels::Build::Regressor).
pub(crate) fn rows<'g>(cx: &Context<'_, 'g>, columns: Option<&[usize]>) -> Vec<Expr<'g>> {
    let all = regressor(cx);
    let chosen: Vec<usize> = columns.map_or_else(|| (0..all.len()).collect(), <[usize]>::to_vec);
    let actuators = cx.mech.structure().actuators();
    (0..actuators)
        .flat_map(|r| chosen.iter().map(|&c| all[c][r]).collect::<Vec<_>>())
        .collect()
}

/// The inputs of a platform state of `freedom`: the pose, twist and acceleration of one free
/// in space; the position, velocity and acceleration of one that only translates.
fn state_inputs(freedom: Freedom) -> &'static [Input] {
    match freedom {
        Freedom::Free => &[Input::Pose, Input::Twist, Input::Accel],
        Freedom::Translations => &[Input::Position, Input::Velocity, Input::LinearAccel],
    }
}

/// The regressor's output; its width is the mechanism's number of standard (or base)
/// parameters, set when the kernel is specified.
const Y: Output = Output {
    name: "y",
    shape: Shape::Matrix(6, 0),
    doc: "row `i` for actuator `i+1`, one column per parameter (N per unit)",
};

/// The identification kernels of every model: the regressors of its inverse dynamics, for
/// any robot of the family (the geometry and gravity are their `params`).
pub const KERNELS: [Decl; 2] = [
    Decl {
        kernel: Kernel::Regressor,
        title: "The regressor `Y` of the standard parameters: `Γ = Y π`.",
        doc: "Columns in the order of `STANDARD_PARAMETERS`: ten per body (mass, first moment \
              `m c`, inertia about the reference point) for the platform, then the rod and body \
              2 of each segment, then viscous and Coulomb friction per actuator. The inertial \
              parameters and friction are the unknowns.",
        equations: Cite::Model(Quantity::Identification),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[Y],
        guard: Guard::Solve,
        reads: Reads::Geometry,
        batch: false,
        chapter: None,
        build: Build::Regressor(Columns::Standard),
    },
    Decl {
        kernel: Kernel::BaseRegressor,
        title: "The regressor `Y_b` of the base parameters: `Γ = Y_b β`.",
        doc: "Columns in the order of `BASE_PARAMETERS`: the columns of their leading standard \
              parameters (`BASE_RELATIONS` says what each base parameter groups). The inertial \
              parameters and friction are the unknowns.",
        equations: Cite::Model(Quantity::Identification),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        // The width is the model's number of base parameters, set when they are known.
        outputs: &[Y],
        guard: Guard::Solve,
        reads: Reads::Geometry,
        batch: false,
        chapter: None,
        build: Build::Regressor(Columns::Base),
    },
];

/// The full regressor kernel of `mechanism`: `Γ = Y π` with `π` the standard parameters.
pub fn regressor_spec(mechanism: &Mechanism) -> Entry {
    let width = standard_parameter_names(mechanism.mechanics).len();
    identification_spec(&KERNELS[0], mechanism, None, width)
}

/// `decl`, one of [`KERNELS`], for `mechanism`: its state's inputs, `Y` of `width` columns.
fn identification_spec(
    decl: &Decl,
    mechanism: &Mechanism,
    base: Option<Vec<usize>>,
    width: usize,
) -> Entry {
    let structure = mechanism.structure();
    let decl = Decl {
        inputs: state_inputs(structure.freedom()),
        ..*decl
    };
    let mut entry = kernels::spec(&decl, mechanism, &[], "", base);
    entry.spec.outputs[0].shape = Shape::Matrix(structure.actuators(), width);
    entry
}

/// The base parameters of a model: each a standard parameter (its lead) with the standard
/// parameters whose columns depend on it folded in, `β_j = π_lead + Σ c_k π_k`.
#[derive(Clone, Debug, PartialEq)]
pub struct BaseParameters {
    /// The standard parameters' names.
    pub names: Vec<String>,
    /// Per base parameter, its terms `(standard index, coefficient)`, the lead first with 1.
    pub groups: Vec<Vec<(usize, f64)>>,
}

impl BaseParameters {
    /// The standard parameters whose columns make the base regressor.
    pub fn leads(&self) -> Vec<usize> {
        self.groups.iter().map(|g| g[0].0).collect()
    }

    /// Base parameter `j`'s name: its lead's, with `_R` (regrouped) when others fold into it.
    pub fn name(&self, j: usize) -> String {
        let group = &self.groups[j];
        let lead = &self.names[group[0].0];
        if group.len() > 1 {
            format!("{lead}_R")
        } else {
            lead.clone()
        }
    }

    /// Base parameter `j` as a readable relation, `platform_izz_R = platform_izz + joint1_izz ...`.
    pub fn relation(&self, j: usize) -> String {
        let names = &self.names;
        let mut out = format!("{} = {}", self.name(j), names[self.groups[j][0].0]);
        for &(k, c) in &self.groups[j][1..] {
            let (sign, magnitude) = if c < 0.0 { ("-", -c) } else { ("+", c) };
            if (magnitude - 1.0).abs() < 1e-12 {
                out.push_str(&format!(" {sign} {}", names[k]));
            } else {
                out.push_str(&format!(" {sign} {magnitude:.12}·{}", names[k]));
            }
        }
        out
    }
}

/// How many seeded states the base parameters are found from.
const STATES: usize = 120;

/// The base parameters of a mechanism from its compiled full regressor ([`regressor_spec`]) for
/// its geometry: `Y` on seeded states of the workspace, stacked, pivoted QR, rank at `1e-9` of
/// the largest pivot.
pub fn base_parameters(regressor: &Compiled, mechanism: &Mechanism) -> BaseParameters {
    let names = standard_parameter_names(mechanism.mechanics);
    let width = names.len();
    let structure = mechanism.structure();
    let actuators = structure.actuators();
    let geometry = mechanism.geometry();
    let home = structure.home(&mechanism.parameters);
    let mut rng = Lcg::new(0x5eed_c5c5);
    let mut rows: Vec<Vec<f64>> = Vec::with_capacity(actuators * STATES);
    for _ in 0..STATES {
        let mut input = seeded_state(structure, &home, &mut rng);
        input.extend(geometry);
        let y = regressor.program.eval(&input);
        rows.extend(y[..actuators * width].chunks(width).map(<[f64]>::to_vec));
    }
    let qr = pivoted_qr(&rows);
    let rank = qr.rank(1e-9);
    let k = qr.dependencies(rank);
    let mut groups: Vec<Vec<(usize, f64)>> = (0..rank)
        .map(|i| {
            let mut group = vec![(qr.permutation[i], 1.0)];
            for (d, &c) in k[i].iter().enumerate() {
                // The relations are structural (equal columns, mostly): an integer up to
                // rounding is that integer, so the generated relations read exactly.
                let c = if (c - c.round()).abs() < 1e-9 {
                    c.round()
                } else {
                    c
                };
                if c != 0.0 {
                    group.push((qr.permutation[rank + d], c));
                }
            }
            group[1..].sort_by_key(|&(idx, _)| idx);
            group
        })
        .collect();
    groups.sort_by_key(|g| g[0].0);
    BaseParameters { names, groups }
}

/// A state drawn about `home` (the six-freedom pose; a translating platform's is its last
/// three), its pose, rates and accelerations in the platform's coordinates.
fn seeded_state(structure: &dyn Structure, home: &[f64; 6], rng: &mut Lcg) -> Vec<f64> {
    let t = structure.turn_reach();
    let (reach, rates, accels) = (
        [t, t, t, 0.05, 0.05, 0.05],
        [1.0, 1.0, 1.0, 0.5, 0.5, 0.5],
        [5.0, 5.0, 5.0, 2.0, 2.0, 2.0],
    );
    let from = 6 - structure.freedom().dimension();
    let offset = rng.vector(&reach[from..]);
    let mut state: Vec<f64> = offset
        .iter()
        .zip(&home[from..])
        .map(|(d, h)| h + d)
        .collect();
    state.extend(rng.vector(&rates[from..]));
    state.extend(rng.vector(&accels[from..]));
    state
}

/// The base regressor kernel: the columns of the base parameters' leads, `Γ = Y_b β`.
pub fn base_regressor_spec(mechanism: &Mechanism, base: &BaseParameters) -> Entry {
    identification_spec(
        &KERNELS[1],
        mechanism,
        Some(base.leads()),
        base.groups.len(),
    )
}

/// The identification data of a mechanism as Rust constants: the standard and base parameters'
/// names (`standard_doc` says what the standard ones are), the relations, and `β = B π` as
/// sparse rows.
pub fn constants(base: &BaseParameters, standard_doc: &str) -> Result<String, Error> {
    let names = &base.names;
    let nb = base.groups.len();
    let base_names: Vec<String> = (0..nb).map(|j| base.name(j)).collect();
    let relations: Vec<String> = (0..nb).map(|j| base.relation(j)).collect();
    let rows: Vec<String> = base
        .groups
        .iter()
        .map(|g| {
            let terms: Vec<String> = g.iter().map(|(k, c)| format!("({k}, {c:?})")).collect();
            format!("&[{}]", terms.join(", "))
        })
        .collect();
    let quoted = |v: &[String]| {
        v.iter()
            .map(|s| format!("{s:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let code = format!(
        "/// The standard parameters, the columns of [`regressor`]: {standard_doc}, then viscous \
         and Coulomb friction per actuator.\n\
         pub const STANDARD_PARAMETERS: [&str; {}] = [{}];\n\
         /// The base parameters, the columns of [`base_regressor`].\n\
         pub const BASE_PARAMETERS: [&str; {nb}] = [{}];\n\
         /// What each base parameter groups, as a relation between standard parameters.\n\
         pub const BASE_RELATIONS: [&str; {nb}] = [{}];\n\
         /// `β = B π`: row `j` holds base parameter `j`'s terms `(standard index, coefficient)`.\n\
         pub const BASE_OF_STANDARD: [&[(usize, f64)]; {nb}] = [{}];\n",
        names.len(),
        quoted(names),
        quoted(&base_names),
        quoted(&relations),
        rows.join(", ")
    );
    let file: syn::File = syn::parse_str(&code).map_err(|e| Error::Emit {
        kernel: "identification constants".to_string(),
        message: e.to_string(),
    })?;
    Ok(prettyplease::unparse(&file))
}

/// A model's identification kernels, compiled: the full regressor, the base parameters found
/// from it for a robot's geometry, and the base regressor.
pub struct Identification {
    pub base: BaseParameters,
    pub entries: [Entry; 2],
    pub compiled: [Compiled; 2],
}

impl Identification {
    /// Compiles `mechanism`'s regressors, the base parameters found with its geometry.
    ///
    /// # Errors
    /// A mechanism the engine cannot emit (a bug).
    pub fn compile(mechanism: &Mechanism) -> Result<Self, Error> {
        let full = regressor_spec(mechanism);
        let full_compiled = full.spec.compile()?;
        let base = base_parameters(&full_compiled, mechanism);
        let reduced = base_regressor_spec(mechanism, &base);
        let reduced_compiled = reduced.spec.compile()?;
        Ok(Identification {
            base,
            entries: [full, reduced],
            compiled: [full_compiled, reduced_compiled],
        })
    }

    /// The kernels with their programs, for the emitters.
    pub fn pairs(&self) -> Vec<(&Entry, &Compiled)> {
        self.entries.iter().zip(&self.compiled).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::bodies::STANDARD_INERTIAL;
    use crate::model::kernels;
    use crate::model::{lopsided, Model};
    use crate::ParameterSet;
    use c5_robot::{Friction, Robot, GEOMETRY_PARAMETERS as GEOMETRY, STANDARD_PARAMETERS};

    #[test]
    fn the_regressor_times_the_standard_parameters_is_the_inverse_dynamics() {
        let robot = lopsided();
        let friction: [Friction; 6] = std::array::from_fn(|i| Friction {
            viscous: 3.0 + i as f64,
            coulomb: 1.5 - 0.2 * i as f64,
        });
        let pi = robot.standard_parameters(&friction);
        for model in Model::ALL {
            let mechanism = Mechanism::c5(&robot, model);
            let y = regressor_spec(&mechanism).spec.compile().unwrap();
            let id = kernels::specs(&mechanism, &ParameterSet::None, "")
                .unwrap()
                .into_iter()
                .find(|e| e.id.kernel == Kernel::InverseDynamics)
                .unwrap()
                .spec
                .compile()
                .unwrap();
            let mut rng = Lcg::new(7);
            for _ in 0..5 {
                let mut input = rng.vector(&[0.3, 0.3, 0.3, 0.05, 0.05, 0.05]);
                input.extend(rng.vector(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]));
                input.extend(rng.vector(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]));
                let gamma = id.program.eval(&input);
                input.extend(&robot.kernel_parameters()[..GEOMETRY]);
                let yv = y.program.eval(&input);
                for i in 0..6 {
                    let qd = yv[i * STANDARD_PARAMETERS + STANDARD_INERTIAL + i];
                    let friction_force =
                        friction[i].viscous * qd + friction[i].coulomb * qd.signum();
                    let predicted: f64 = (0..STANDARD_PARAMETERS)
                        .map(|j| yv[i * STANDARD_PARAMETERS + j] * pi[j])
                        .sum();
                    let want = gamma[i] + friction_force;
                    assert!(
                        (predicted - want).abs() <= 1e-12 * want.abs().max(1.0),
                        "{model} actuator {i}: Y π = {predicted}, Γ = {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_base_regressor_times_the_base_parameters_is_the_regressor_times_any_parameters() {
        let robot = Robot::default();
        let geometry = &robot.kernel_parameters()[..GEOMETRY];
        for (model, expected) in [(Model::Consistent, 46), (Model::Paper, 52)] {
            let mechanism = Mechanism::c5(&robot, model);
            let y = regressor_spec(&mechanism).spec.compile().unwrap();
            let base = base_parameters(&y, &mechanism);
            assert_eq!(base.groups.len(), expected, "{model}");
            let yb = base_regressor_spec(&mechanism, &base)
                .spec
                .compile()
                .unwrap();
            let nb = base.groups.len();
            let mut rng = Lcg::new(11);
            let pi = rng.vector(&[1.0; STANDARD_PARAMETERS]);
            let beta: Vec<f64> = base
                .groups
                .iter()
                .map(|g| g.iter().map(|&(k, c)| c * pi[k]).sum())
                .collect();
            for _ in 0..5 {
                let mut input = rng.vector(&[0.3, 0.3, 0.3, 0.05, 0.05, 0.05]);
                input.extend(rng.vector(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]));
                input.extend(rng.vector(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]));
                input.extend(geometry);
                let (full, reduced) = (y.program.eval(&input), yb.program.eval(&input));
                for i in 0..6 {
                    let a: f64 = (0..STANDARD_PARAMETERS)
                        .map(|j| full[i * STANDARD_PARAMETERS + j] * pi[j])
                        .sum();
                    let b: f64 = (0..nb).map(|j| reduced[i * nb + j] * beta[j]).sum();
                    assert!(
                        (a - b).abs() < 1e-10 * a.abs().max(1.0),
                        "{model}: {a} vs {b}"
                    );
                }
            }
            // Every base parameter's relation names its lead first.
            assert!(base
                .relation(0)
                .starts_with(&format!("{} = ", base.name(0))));
        }
    }

    #[test]
    fn the_build_api_emits_the_regressors_and_their_constants() {
        let robot = Robot {
            half_spacing: 0.25,
            ..Robot::default()
        };
        let code = crate::Config::new()
            .robot(robot)
            .model(Model::Paper)
            .regressors(true)
            .generate_to_string()
            .unwrap();
        for item in [
            "pub fn regressor(",
            "pub fn base_regressor(",
            "pub const BASE_RELATIONS: [&str; 52]",
            "\"rod1_mass\"",
        ] {
            assert!(code.contains(item), "{item}");
        }
        syn::parse_file(&code).unwrap();
    }
}
