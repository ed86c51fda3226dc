//! Kernel specifications (what a model hands the engine) and their compilation.
//!
//! A [`KernelSpec`] is plain data plus a build function over the symbolic layer; the engine
//! knows nothing of robots. Compilation builds the DAG under each rewriting policy, factors and
//! lowers it, and keeps the cheapest program.

use crate::count::OpCount;
use crate::dag::{Graph, NodeId, Policy};
use crate::error::Error;
use crate::lower::{factor, lower, Program};
use crate::Expr;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The inputs a kernel works from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Setting {
    /// Free inputs: the kernel reads quantities its caller gives directly (for instance the
    /// vectors of a published derivation, as its own operation counts assume).
    Free,
    /// From the platform state (pose, twist, acceleration), end to end.
    Pose,
    /// From the actuators' positions, rates and accelerations (what the robot measures), end
    /// to end through the forward kinematics.
    Joint,
}

impl fmt::Display for Setting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Setting::Free => "free",
            Setting::Pose => "pose",
            Setting::Joint => "joint",
        })
    }
}

/// Shape of a kernel argument or result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shape {
    Vector(usize),
    Matrix(usize, usize),
}

impl Shape {
    pub const fn len(self) -> usize {
        match self {
            Shape::Vector(n) => n,
            Shape::Matrix(r, c) => r * c,
        }
    }
    pub const fn is_empty(self) -> bool {
        self.len() == 0
    }
}

/// One argument or result of a kernel.
#[derive(Clone, Debug)]
pub struct Arg {
    pub name: String,
    pub shape: Shape,
    /// Names of the scalar elements in row-major order (inputs only), used in the emitted code.
    pub elements: Vec<String>,
    pub doc: String,
}

impl Arg {
    pub fn new(name: &str, shape: Shape, elements: Vec<String>, doc: &str) -> Self {
        assert_eq!(elements.len(), shape.len(), "element names of {name}");
        Arg {
            name: name.to_string(),
            shape,
            elements,
            doc: doc.to_string(),
        }
    }

    pub fn output(name: &str, shape: Shape, doc: &str) -> Self {
        Arg {
            name: name.to_string(),
            shape,
            elements: Vec::new(),
            doc: doc.to_string(),
        }
    }
}

/// The chapter's published count for a kernel (division counted as multiplication).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChapterCount {
    pub m: u32,
    pub a: u32,
}

/// Builds the outputs of a kernel from its inputs, one `Vec` per argument.
pub type BuildFn =
    Box<dyn for<'g> Fn(&'g Graph, &[Vec<Expr<'g>>]) -> Vec<Vec<Expr<'g>>> + Send + Sync>;

/// What the optimizer minimises for a kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Objective {
    /// [`OpCount::weight`], an estimate of run time (divisions and calls are dear).
    #[default]
    Speed,
    /// The chapter's own cost model, `m + a` with a division counted as a multiplication, for
    /// the kernels audited against the chapter's table; ties go to speed.
    ChapterCount,
}

impl Objective {
    fn cost(self, c: &OpCount) -> (f64, f64) {
        match self {
            Objective::Speed => (c.weight(), 0.0),
            Objective::ChapterCount => (f64::from(c.chapter_m() + c.chapter_a()), c.weight()),
        }
    }
}

/// A kernel to generate.
pub struct KernelSpec {
    pub name: String,
    /// The family the kernel belongs to: the caller's name for the equations it computes (a
    /// model or a mechanism). Kernels of one family are emitted side by side; the engine reads
    /// nothing else into it.
    pub family: String,
    pub setting: Setting,
    pub equations: Vec<String>,
    /// One line saying what the kernel computes.
    pub title: String,
    /// Further documentation (conventions, orderings).
    pub doc: String,
    pub chapter: Option<ChapterCount>,
    pub objective: Objective,
    pub inputs: Vec<Arg>,
    pub outputs: Vec<Arg>,
    pub build: BuildFn,
}

/// A compiled kernel: its program, counts and the policy that won.
#[derive(Clone, Debug)]
pub struct Compiled {
    pub program: Program,
    pub count: OpCount,
    pub policy: Policy,
}

/// The weight ([`OpCount::weight`]) of the best flat program past which the policies that
/// distribute products over sums are not tried. On larger kernels (the derivatives: 3 000 to
/// 16 000) they never won and multiplied the graph by 7 to 100, which made them nine tenths of
/// the generation's time; every kernel below it (the largest, `joint_inertia_params`, about
/// 2 500) still tries them all.
pub const EXPANSION_LIMIT: f64 = 3000.0;

/// The rewriting policies the optimizer tries on every kernel.
fn policies() -> impl Iterator<Item = Policy> {
    [1, 8, 64].into_iter().flat_map(|expand_limit| {
        [false, true].into_iter().flat_map(move |absorb_constants| {
            [true, false]
                .into_iter()
                .flat_map(move |share_reciprocals| {
                    [false, true].map(move |distribute_offsets| Policy {
                        expand_limit,
                        absorb_constants,
                        share_reciprocals,
                        distribute_offsets,
                    })
                })
        })
    })
}

impl KernelSpec {
    /// Builds the symbolic outputs on `graph`, inputs numbered in argument order.
    pub fn build_on<'g>(&self, graph: &'g Graph) -> Result<Vec<NodeId>, Error> {
        let mut next = 0u32;
        let inputs: Vec<Vec<Expr<'g>>> = self
            .inputs
            .iter()
            .map(|arg| {
                (0..arg.shape.len())
                    .map(|_| {
                        next += 1;
                        graph.input(next - 1)
                    })
                    .collect()
            })
            .collect();
        let outputs = (self.build)(graph, &inputs);
        if outputs.len() != self.outputs.len()
            || outputs
                .iter()
                .zip(&self.outputs)
                .any(|(o, a)| o.len() != a.shape.len())
        {
            return Err(Error::InvalidModel {
                kernel: self.name.clone(),
                reason: "outputs do not match the declared shapes".to_string(),
            });
        }
        if let Some(reason) = graph.arena().invalid().map(str::to_string) {
            return Err(Error::InvalidModel {
                kernel: self.name.clone(),
                reason,
            });
        }
        Ok(outputs.into_iter().flatten().map(|e| e.id).collect())
    }

    /// Number of scalar inputs.
    pub fn input_len(&self) -> usize {
        self.inputs.iter().map(|a| a.shape.len()).sum()
    }

    /// The program under `policy`, its sums planned with shared sub-sums or not.
    fn program(&self, policy: Policy, share_subsums: bool) -> Result<Program, Error> {
        let graph = Graph::new(policy);
        let outputs = self.build_on(&graph)?;
        let mut arena = graph.into_arena();
        let outputs = factor(&mut arena, &outputs);
        let program = lower(&arena, &outputs, share_subsums);
        let declared = self.input_len() as u32;
        if let Some(i) = program.used_inputs().into_iter().find(|&i| i >= declared) {
            return Err(Error::InvalidModel {
                kernel: self.name.clone(),
                reason: format!("the outputs depend on the undeclared input {i}"),
            });
        }
        Ok(program)
    }

    /// The count of the program under every policy, sub-sums shared (for studying the optimizer).
    ///
    /// # Errors
    /// As [`KernelSpec::compile`].
    pub fn costs_by_policy(&self) -> Result<Vec<(Policy, OpCount)>, Error> {
        policies()
            .map(|p| Ok((p, self.program(p, true)?.count())))
            .collect()
    }

    /// Compiles under every policy, keeps the cheapest, and lowers that one again sharing the
    /// sub-sums its sums have in common (which only ever saves additions). The policies that
    /// distribute products over sums are tried only when the best flat program weighs at most
    /// [`EXPANSION_LIMIT`].
    pub fn compile(&self) -> Result<Compiled, Error> {
        let mut best: Option<(Policy, f64, f64)> = None;
        let (flat, expanding): (Vec<Policy>, Vec<Policy>) =
            policies().partition(|p| p.expand_limit == 1);
        for policy in flat.into_iter().chain(expanding) {
            let too_large = |&(_, cost, _): &(Policy, f64, f64)| cost > EXPANSION_LIMIT;
            if policy.expand_limit > 1
                && self.objective == Objective::Speed
                && best.as_ref().is_some_and(too_large)
            {
                break;
            }
            let count = self.program(policy, false)?.count();
            let (cost, tie) = self.objective.cost(&count);
            if best.is_none_or(|(_, c, t)| (cost, tie) < (c, t)) {
                best = Some((policy, cost, tie));
            }
        }
        let (policy, ..) = best.expect("at least one policy");
        let program = self.program(policy, true)?;
        Ok(Compiled {
            count: program.count(),
            program,
            policy,
        })
    }
}
