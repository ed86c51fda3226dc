//! The operation-count manifest (`ops.json`, `OPS.md`) and the generated files' header.

use crate::count::OpCount;
use crate::error::Error;
use crate::kernel::{ChapterCount, Compiled, KernelSpec, Setting};
use crate::model::{Kernel, KernelId};
use c5_robot::Robot;
use serde::{Deserialize, Serialize};

/// One kernel's entry in `ops.json`. The counts hold for every scalar type and every output
/// language: they are the counts of the one program all of them print.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    pub name: String,
    /// The family whose equations the kernel computes: the model or mechanism
    /// (`"consistent"`, `"paper"`, `"gough-stewart"`).
    pub model: String,
    pub setting: Setting,
    pub equations: Vec<String>,
    #[serde(flatten)]
    pub count: OpCount,
    pub chapter: Option<ChapterCount>,
}

/// The whole manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub kernels: Vec<Entry>,
}

fn entries(kernels: &[(&KernelSpec, &Compiled)]) -> Vec<Entry> {
    kernels
        .iter()
        .map(|(s, c)| Entry {
            name: s.name.clone(),
            model: s.family.clone(),
            setting: s.setting,
            equations: s.equations.clone(),
            count: c.count.clone(),
            chapter: s.chapter,
        })
        .collect()
}

pub fn json(kernels: &[(&KernelSpec, &Compiled)]) -> String {
    let m = Manifest {
        kernels: entries(kernels),
    };
    serde_json::to_string_pretty(&m).expect("manifest serialises") + "\n"
}

fn calls(c: &OpCount) -> String {
    if c.calls.is_empty() {
        "0".to_string()
    } else {
        c.calls
            .iter()
            .map(|(n, k)| format!("{k} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `ops.json` as a Markdown table.
pub fn markdown(kernels: &[(&KernelSpec, &Compiled)]) -> String {
    let mut out = String::from(
        "# Operation counts of the generated kernels\n\n\
         Generated with the kernels; `m` counts a division as a multiplication, as the chapter does. \
         The counts hold for the Rust and the C output alike, in `f64` and `f32`: all print one program.\n\n\
         | model | kernel | setting | equations | mul | div | add | neg | calls | generated m + a | chapter m + a |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for e in entries(kernels) {
        let c = &e.count;
        out.push_str(&format!(
            "| {} | `{}` | {} | {} | {} | {} | {} | {} | {} | {}m + {}a | {} |\n",
            e.model,
            e.name,
            e.setting,
            e.equations.join(", "),
            c.mul,
            c.div,
            c.add,
            c.neg,
            calls(c),
            c.chapter_m(),
            c.chapter_a(),
            e.chapter
                .map_or("—".to_string(), |ch| format!("{}m + {}a", ch.m, ch.a)),
        ));
    }
    out
}

/// The `@generated` header with a cost summary; `what` says which model and robot.
pub fn header(kernels: &[(&KernelSpec, &Compiled)], how: &str, what: &str) -> String {
    let mut out = format!(
        "// @generated {how}. Do not edit.\n// {what}\n//\n// Kernel operation counts (mul, div, add, neg, calls):\n"
    );
    for (s, c) in kernels {
        let n = &c.count;
        out.push_str(&format!(
            "//   {:<32} {:>5} {:>4} {:>5} {:>4}  {}\n",
            s.name,
            n.mul,
            n.div,
            n.add,
            n.neg,
            calls(n)
        ));
    }
    if kernels
        .iter()
        .any(|(_, c)| c.program.instrs.len() > crate::blocks::MAX_LETS_PER_SCOPE)
    {
        out.push_str(&format!(
            "//\n// Bodies of more than {} `let`s are cut into blocks, `let (t7, t9) = {{ ... }};`, each\n\
             // handing on what is read after it: one scope that long overflows rustc's stack in a\n\
             // debug build (codegen/src/blocks.rs).\n",
            crate::blocks::MAX_LETS_PER_SCOPE
        ));
    }
    out
}

fn rust_file(how: &str, what: &str, code: &str) -> Result<String, Error> {
    let file: syn::File = syn::parse_str(code).map_err(|e| Error::Emit {
        kernel: what.to_string(),
        message: e.to_string(),
    })?;
    Ok(format!(
        "// @generated {how}. Do not edit.\n// {what}\n\n{}",
        prettyplease::unparse(&file)
    ))
}

/// The length and names of the C5's `*_params` kernels' parameter vector, from the one
/// definition (`Robot::kernel_parameter_names`), as Rust constants.
///
/// # Errors
/// Emitted code that does not parse (a bug).
pub fn parameter_constants(how: &str) -> Result<String, Error> {
    let names = Robot::<f64>::kernel_parameter_names();
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    let code = format!(
        "/// Length of the parameter vector of the `*_params` kernels \
         (`c5_robot::Robot::kernel_parameters`).\n\
         pub const PARAMETERS: usize = {};\n\
         /// The parameters' names, in the order of the vector.\n\
         pub const PARAMETER_NAMES: [&str; {}] = [{}];\n\
         /// How many of the first parameters the identification kernels read (the half-spacing \
         and gravity): their `params` argument.\n\
         pub const GEOMETRY_PARAMETERS: usize = {};\n",
        names.len(),
        names.len(),
        quoted.join(", "),
        c5_robot::GEOMETRY_PARAMETERS
    );
    rust_file(how, "The robot parameters of the kernels.", &code)
}

/// A mechanism's parameter vector as Rust constants in its module: its length, the names, and
/// how many open it as the geometry (the identification kernels' `params`); and its kernel set
/// ([`kernel_set`]) over `kernels`, the names of the module's kernels.
///
/// # Errors
/// Emitted code that does not parse (a bug).
pub fn mechanism_parameter_constants(
    mechanism: &crate::Mechanism,
    kernels: &[&str],
    fitted: Option<usize>,
) -> Result<String, Error> {
    let structure = mechanism.structure();
    let names = structure.parameter_names();
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    let code = format!(
        "/// Length of the parameter vector of the `*_params` kernels.\n\
         pub const PARAMETERS: usize = {};\n\
         /// The parameters' names, in the order of the vector.\n\
         pub const PARAMETER_NAMES: [&str; {}] = [{}];\n\
         /// How many of the first parameters are the geometry and gravity (the identification \
         kernels' `params`).\n\
         pub const GEOMETRY_PARAMETERS: usize = {};\n",
        names.len(),
        names.len(),
        quoted.join(", "),
        structure.geometry_parameters()
    ) + &term_constants(
        "SINGULARITY_TERMS",
        "What each singularity term the kernels return measures, in order (a kernel's terms are \
         the first of these): what the runtime bounds and names them by.",
        &structure.singularity_terms(),
    ) + &term_constants(
        "FORWARD_KINEMATICS_TERMS",
        "What each singularity term of `forward_kinematics_params` measures, in order.",
        &structure.forward_kinematics_terms(),
    ) + &kernel_set(mechanism, kernels, fitted);
    let file: syn::File = syn::parse_str(&code).map_err(|e| Error::Emit {
        kernel: "parameter constants".to_string(),
        message: e.to_string(),
    })?;
    Ok(format!("\n{}", prettyplease::unparse(&file)))
}

/// The kernel set of a legged mechanism (`c5_generated::legged`): a unit type `Kernels` whose
/// trait implementations call the module's `*_params` kernels, for those of `kernels` (the
/// names the module holds, `*_x4` for its batch forms) each trait needs; nothing for a mechanism without singularity
/// terms (the C5's kernels, checked by hand), nor without kernels (the set is `f64`'s).
/// `fitted` is the number of geometry entries the calibration kernel fits per leg, where the
/// module has one.
pub fn kernel_set(mechanism: &crate::Mechanism, kernels: &[&str], fitted: Option<usize>) -> String {
    let structure = mechanism.structure();
    if structure.singularity_terms().is_empty() || kernels.is_empty() {
        return String::new();
    }
    let n = structure.freedom().dimension();
    let has = |names: &[&str]| {
        names
            .iter()
            .all(|name| kernels.contains(&format!("{name}_params").as_str()))
    };
    let guard = "impl AsRef<[f64]>";
    let call = |name: &str, args: &str| format!("{name}_params({args}, p)");
    let mut out = format!(
        "/// This mechanism's `*_params` kernels as one set (`crate::legged`), for callers \
         generic over the mechanism.\n\
         #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]\n\
         pub struct Kernels;\n\
         impl crate::legged::Legs<{n}> for Kernels {{\n\
         const MECHANISM: &'static str = {name:?};\n\
         const SINGULARITY_TERMS: &'static [crate::guard::SingularityTerm] = &SINGULARITY_TERMS;\n\
         type Parameters = [f64; PARAMETERS];\n\
         type Terms = [f64; {terms}];\n\
         #[inline] fn parameters(values: &[f64]) -> Option<[f64; PARAMETERS]> {{ values.try_into().ok() }}\n\
         #[inline] fn singularity_terms(x: &[f64; {n}], p: &[f64; PARAMETERS]) -> [f64; {terms}] {{ {singular} }}\n\
         #[inline] fn actuators(x: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], {guard}) {{ {actuators} }}\n\
         #[inline] fn inverse_jacobian(x: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([[f64; {n}]; {n}], {guard}) {{ {inverse_jacobian} }}\n\
         #[inline] fn jacobian(x: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([[f64; {n}]; {n}], {guard}) {{ {jacobian} }}\n\
         #[inline] fn joint_velocities(x: &[f64; {n}], v: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], {guard}) {{ {velocities} }}\n\
         #[inline] fn joint_accelerations(x: &[f64; {n}], v: &[f64; {n}], a: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], {guard}) {{ {accelerations} }}\n\
         #[inline] fn inverse_dynamics(x: &[f64; {n}], v: &[f64; {n}], a: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], {guard}) {{ {inverse_dynamics} }}\n\
         #[inline] fn forward_dynamics(x: &[f64; {n}], v: &[f64; {n}], gamma: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], {guard}) {{ {forward_dynamics} }}\n\
         {batch}\
         }}\n",
        name = mechanism.name(),
        terms = structure.singularity_terms().len(),
        singular = call("singularity_terms", "x"),
        actuators = if matches!(structure.freedom(), crate::model::Freedom::Free) {
            format!("let (q, _, guard) = {}; (q, guard)", call("inverse_kinematics", "x"))
        } else {
            call("inverse_kinematics", "x")
        },
        inverse_jacobian = call("inverse_jacobian_pose", "x"),
        jacobian = call("jacobian_pose", "x"),
        velocities = call("joint_velocities", "x, v"),
        accelerations = call("joint_accelerations", "x, v, a"),
        inverse_dynamics = call("inverse_dynamics", "x, v, a"),
        forward_dynamics = call("forward_dynamics", "x, v, gamma"),
        batch = if kernels.contains(&"inverse_dynamics_params_x4") {
            format!(
                "#[cfg(feature = \"batch\")] #[inline] fn inverse_dynamics_x4(x: &[[f64; 4]; {n}], v: &[[f64; 4]; {n}], a: &[[f64; 4]; {n}], p: &[f64; PARAMETERS]) -> Option<([[f64; 4]; {n}], impl AsRef<[[f64; 4]]>)> {{ Some(inverse_dynamics_params_x4(x, v, a, p)) }}\n"
            )
        } else {
            String::new()
        },
    );
    if has(&["task_inertia", "task_bias"]) {
        out += &format!(
            "impl crate::legged::TaskSpace<{n}> for Kernels {{\n\
             #[inline] fn task_inertia(x: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([[f64; {n}]; {n}], {guard}) {{ {} }}\n\
             #[inline] fn task_bias(x: &[f64; {n}], v: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], {guard}) {{ {} }}\n\
             }}\n",
            call("task_inertia", "x"),
            call("task_bias", "x, v"),
        );
    }
    if n == 6 && has(&["inverse_kinematics", "forward_kinematics_step"]) {
        out += &format!(
            "impl crate::legged::Spatial for Kernels {{\n\
             #[inline] fn inverse_kinematics(x: &[f64; 6], p: &[f64; PARAMETERS]) -> ([f64; 6], [[f64; 3]; 6], {guard}) {{ {} }}\n\
             #[inline] fn forward_kinematics_step(x: &[f64; 6], q: &[f64; 6], p: &[f64; PARAMETERS]) -> ([f64; 6], [f64; 6], [f64; 7], {guard}) {{ {} }}\n\
             }}\n",
            call("inverse_kinematics", "x"),
            call("forward_kinematics_step", "x, q"),
        );
    }
    if has(&[
        "inverse_dynamics_derivatives",
        "forward_dynamics_derivatives",
    ]) {
        let jacobians = format!(
            "([f64; {n}], [[f64; {n}]; {n}], [[f64; {n}]; {n}], [[f64; {n}]; {n}], {guard})"
        );
        out += &format!(
            "#[cfg(feature = \"derivatives\")]\n\
             impl crate::legged::Derivatives<{n}> for Kernels {{\n\
             #[inline] fn inverse_dynamics_derivatives(x: &[f64; {n}], v: &[f64; {n}], a: &[f64; {n}], p: &[f64; PARAMETERS]) -> {jacobians} {{ {} }}\n\
             #[inline] fn forward_dynamics_derivatives(x: &[f64; {n}], v: &[f64; {n}], gamma: &[f64; {n}], p: &[f64; PARAMETERS]) -> {jacobians} {{ {} }}\n\
             }}\n",
            call("inverse_dynamics_derivatives", "x, v, a"),
            call("forward_dynamics_derivatives", "x, v, gamma"),
        );
    }
    if let Some(fitted) = fitted {
        out += &format!(
            "impl crate::legged::Calibrated<{n}> for Kernels {{\n\
             type FittedRow = [f64; {fitted}];\n\
             #[inline] fn calibration_residuals(x: &[f64; {n}], q: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([f64; {n}], [[f64; {fitted}]; {n}], [[f64; {n}]; {n}]) {{ calibration_residuals(x, q, &crate::legged::geometry(p)) }}\n\
             }}\n",
        );
    }
    if !structure.forward_kinematics_terms().is_empty() && has(&["forward_kinematics"]) {
        out += &format!(
            "impl crate::legged::ClosedForm<{n}> for Kernels {{\n\
             const FORWARD_KINEMATICS_TERMS: &'static [crate::guard::SingularityTerm] = &FORWARD_KINEMATICS_TERMS;\n\
             #[inline] fn forward_kinematics(q: &[f64; {n}], p: &[f64; PARAMETERS]) -> ([[f64; {n}]; 2], {guard}) {{ {} }}\n\
             }}\n",
            call("forward_kinematics", "q"),
        );
    }
    out
}

/// The identification kernels of a legged mechanism as the kernel set's `Regressors`
/// (`c5_generated::legged`), beside the regressors; nothing for a mechanism without
/// singularity terms (the C5's models).
///
/// # Errors
/// Emitted code that does not parse (a bug).
pub fn regressor_set(mechanism: &crate::Mechanism) -> Result<String, Error> {
    let structure = mechanism.structure();
    if structure.singularity_terms().is_empty() {
        return Ok(String::new());
    }
    let n = structure.freedom().dimension();
    let guard = "impl AsRef<[f64]>";
    let state = format!("x: &[f64; {n}], v: &[f64; {n}], a: &[f64; {n}], p: &[f64; PARAMETERS]");
    let code = format!(
        "\nimpl crate::legged::Regressors<{n}> for Kernels {{\n\
         type StandardRow = [f64; STANDARD_PARAMETERS.len()];\n\
         type BaseRow = [f64; BASE_PARAMETERS.len()];\n\
         const STANDARD_PARAMETERS: &'static [&'static str] = &STANDARD_PARAMETERS;\n\
         const BASE_PARAMETERS: &'static [&'static str] = &BASE_PARAMETERS;\n\
         const BASE_OF_STANDARD: &'static [&'static [(usize, f64)]] = &BASE_OF_STANDARD;\n\
         #[inline] fn regressor({state}) -> ([[f64; STANDARD_PARAMETERS.len()]; {n}], {guard}) {{ regressor(x, v, a, &crate::legged::geometry(p)) }}\n\
         #[inline] fn base_regressor({state}) -> ([[f64; BASE_PARAMETERS.len()]; {n}], {guard}) {{ base_regressor(x, v, a, &crate::legged::geometry(p)) }}\n\
         }}\n"
    );
    let file: syn::File = syn::parse_str(&code).map_err(|e| Error::Emit {
        kernel: "regressor set".to_string(),
        message: e.to_string(),
    })?;
    Ok(format!("\n{}", prettyplease::unparse(&file)))
}

/// `terms` as the constant `name` documented by `doc`; nothing where there are none.
fn term_constants(name: &str, doc: &str, terms: &[crate::model::terms::SingularityTerm]) -> String {
    if terms.is_empty() {
        return String::new();
    }
    let values: Vec<String> = terms.iter().map(|t| t.to_rust()).collect();
    format!(
        "/// {doc}\npub const {name}: [crate::guard::SingularityTerm; {}] = [{}];\n",
        terms.len(),
        values.join(", ")
    )
}

/// The manifest as Rust constants (`c5_generated::manifest::KERNELS`), for the audit and the
/// operation budget without parsing `ops.json`.
///
/// # Errors
/// Emitted code that does not parse (a bug).
pub fn rust_constants(
    how: &str,
    kernels: &[(KernelId, &KernelSpec, &Compiled)],
) -> Result<String, Error> {
    let specs: Vec<_> = kernels.iter().map(|(_, s, c)| (*s, *c)).collect();
    let items: Vec<String> = entries(&specs)
        .iter()
        .zip(kernels)
        .map(|(e, (id, _, _))| {
            let c = &e.count;
            let calls: Vec<String> = c
                .calls
                .iter()
                .map(|(n, k)| format!("({n:?}, {k})"))
                .collect();
            let equations: Vec<String> = e.equations.iter().map(|q| format!("{q:?}")).collect();
            let chapter = e.chapter.map_or("None".to_string(), |ch| {
                format!("Some(ChapterCount {{ m: {}, a: {} }})", ch.m, ch.a)
            });
            format!(
                "Entry {{ kernel: Kernel::{:?}, parameters: {}, name: {:?}, model: {:?}, \
                 setting: {:?}, equations: &[{}], \
                 count: Count {{ mul: {}, div: {}, add: {}, neg: {}, calls: &[{}] }}, \
                 chapter: {chapter} }}",
                id.kernel,
                id.parameters,
                e.name,
                e.model,
                e.setting.to_string(),
                equations.join(", "),
                c.mul,
                c.div,
                c.add,
                c.neg,
                calls.join(", ")
            )
        })
        .collect();
    let variants: Vec<String> = Kernel::ALL
        .iter()
        .map(|k| format!("/// `{}`.\n{k:?}", k.name()))
        .collect();
    let names: Vec<String> = Kernel::ALL
        .iter()
        .map(|k| format!("Kernel::{k:?} => {:?}", k.name()))
        .collect();
    let code = format!(
        "/// What a kernel computes, the same for every model, scalar and variant.\n\
         #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]\n\
         pub enum Kernel {{ {} }}\n\
         impl Kernel {{\n\
         /// The generated function's base name (`_params` is appended when the robot's \
         parameters are inputs).\n\
         pub const fn name(self) -> &'static str {{ match self {{ {} }} }}\n\
         }}\n\
         /// Every generated kernel with its counted operations, as `ops.json` lists them.\n\
         pub const KERNELS: &[Entry] = &[{}];\n",
        variants.join(",\n"),
        names.join(",\n"),
        items.join(",\n")
    );
    rust_file(how, "The operation-count manifest as constants.", &code)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mechanism;
    use c5_robot::{Delta, GoughStewart, Model, Robot};

    const SPATIAL: &[&str] = &[
        "singularity_terms_params",
        "inverse_kinematics_params",
        "inverse_jacobian_pose_params",
        "jacobian_pose_params",
        "joint_velocities_params",
        "joint_accelerations_params",
        "inverse_dynamics_params",
        "forward_dynamics_params",
        "task_inertia_params",
        "task_bias_params",
        "forward_kinematics_step_params",
    ];

    /// A platform free in space gets the shared set and the spatial one; a translating platform
    /// with a closed-form forward kinematics the shared set and the closed form; the C5, whose
    /// kernels are checked by hand, none; and the sets parse as Rust.
    #[test]
    fn each_mechanism_gets_the_kernel_sets_its_kernels_make() {
        let with_derivatives: Vec<&str> = SPATIAL
            .iter()
            .copied()
            .chain([
                "inverse_dynamics_derivatives_params",
                "forward_dynamics_derivatives_params",
            ])
            .collect();
        let hexapod = kernel_set(
            &Mechanism::gough_stewart(&GoughStewart::example()),
            &with_derivatives,
            Some(7),
        );
        assert!(hexapod.contains(
            "#[cfg(feature = \"derivatives\")]\nimpl crate::legged::Derivatives<6> for Kernels"
        ));
        assert!(hexapod.contains("crate::legged::Legs<6> for Kernels"));
        assert!(hexapod.contains("crate::legged::Spatial for Kernels"));
        assert!(hexapod.contains("crate::legged::TaskSpace<6> for Kernels"));
        assert!(!hexapod.contains("ClosedForm"));
        assert!(hexapod.contains("crate::legged::Calibrated<6> for Kernels"));
        assert!(hexapod.contains("type FittedRow = [f64; 7];"));
        let mut translating: Vec<&str> = SPATIAL[..10].to_vec();
        translating.remove(1);
        translating.push("forward_kinematics_params");
        let delta = kernel_set(&Mechanism::delta(&Delta::example()), &translating, None);
        assert!(delta.contains("crate::legged::Legs<3> for Kernels"));
        assert!(delta.contains("crate::legged::ClosedForm<3> for Kernels"));
        assert!(delta.contains("crate::legged::TaskSpace<3> for Kernels"));
        assert!(!delta.contains("Spatial") && !delta.contains("Derivatives"));
        let c5 = Mechanism::c5(&Robot::default(), Model::Consistent);
        assert_eq!(kernel_set(&c5, SPATIAL, None), "");
        for code in [hexapod, delta] {
            syn::parse_str::<syn::File>(&code).expect("the kernel set parses");
        }
    }

    /// Without the kernels a trait needs (here the Newton step), its implementation is left
    /// out rather than written against a function that is not there.
    #[test]
    fn a_trait_whose_kernels_are_missing_is_not_implemented() {
        let hexapod = kernel_set(
            &Mechanism::gough_stewart(&GoughStewart::example()),
            &SPATIAL[..10],
            None,
        );
        assert!(hexapod.contains("Legs<6>") && hexapod.contains("TaskSpace<6>"));
        assert!(!hexapod.contains("Spatial"));
    }

    /// The batch inverse dynamics joins the shared set where the module has it (behind the
    /// feature that compiles it), and is left to the trait's `None` where not.
    #[test]
    fn the_batch_inverse_dynamics_joins_the_set_where_it_is_generated() {
        let hexapod = Mechanism::gough_stewart(&GoughStewart::example());
        let without = kernel_set(&hexapod, SPATIAL, None);
        assert!(!without.contains("inverse_dynamics_x4"));
        let mut names = SPATIAL.to_vec();
        names.push("inverse_dynamics_params_x4");
        let with = kernel_set(&hexapod, &names, None);
        assert!(with.contains("#[cfg(feature = \"batch\")] #[inline] fn inverse_dynamics_x4("));
        assert!(with.contains("Some(inverse_dynamics_params_x4(x, v, a, p))"));
        syn::parse_str::<syn::File>(&with).expect("the kernel set parses");
    }
}
