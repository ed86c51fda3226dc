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

/// Shape of a kernel argument or result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Vector(usize),
    Matrix(usize, usize),
}

impl Shape {
    pub fn len(self) -> usize {
        match self {
            Shape::Vector(n) => n,
            Shape::Matrix(r, c) => r * c,
        }
    }
    pub fn is_empty(self) -> bool {
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
pub type BuildFn = Box<dyn for<'g> Fn(&'g Graph, &[Vec<Expr<'g>>]) -> Vec<Vec<Expr<'g>>>>;

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
    /// `"chapter"` (components of `P_i2` as free inputs) or `"pose"` (from the platform state).
    pub setting: String,
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

/// The rewriting policies the optimizer tries on every kernel.
fn policies() -> impl Iterator<Item = Policy> {
    [1, 8, 64].into_iter().flat_map(|expand_limit| {
        [false, true].into_iter().flat_map(move |absorb_constants| {
            [true, false].map(move |share_reciprocals| Policy {
                expand_limit,
                absorb_constants,
                share_reciprocals,
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
        if let Some(reason) = graph.arena().invalid.clone() {
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

    /// Compiles under every policy and keeps the cheapest program.
    pub fn compile(&self) -> Result<Compiled, Error> {
        let mut best: Option<Compiled> = None;
        for policy in policies() {
            let graph = Graph::new(policy);
            let outputs = self.build_on(&graph)?;
            let mut arena = graph.into_arena();
            let outputs = factor(&mut arena, &outputs);
            let program = lower(&arena, &outputs);
            let count = program.count();
            let cost = self.objective.cost(&count);
            if best
                .as_ref()
                .is_none_or(|b| cost < self.objective.cost(&b.count))
            {
                best = Some(Compiled {
                    program,
                    count,
                    policy,
                });
            }
        }
        Ok(best.expect("at least one policy"))
    }
}
