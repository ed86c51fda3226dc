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
                        ..Policy::FLAT
                    })
                })
        })
    })
}

/// What a kernel's graph meets that makes more of a [`Policy`] matter: whether it takes
/// Jacobians (their mode), and how many values it offers as units.
#[derive(Clone, Copy, Debug, Default)]
struct Switches {
    jacobian: bool,
    offers: usize,
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

    /// The program under `policy`, its sums planned with shared sub-sums or not, and what
    /// building it met that makes more of the policy matter.
    fn program(&self, policy: Policy, share_subsums: bool) -> Result<(Program, Switches), Error> {
        let graph = Graph::new(policy);
        let outputs = self.build_on(&graph)?;
        let mut arena = graph.into_arena();
        let met = Switches {
            jacobian: arena.took_jacobian(),
            offers: arena.offers().len().min(32),
        };
        let outputs = factor(&mut arena, &outputs);
        let program = lower(&arena, &outputs, share_subsums);
        let declared = self.input_len() as u32;
        if let Some(i) = program.used_inputs().into_iter().find(|&i| i >= declared) {
            return Err(Error::InvalidModel {
                kernel: self.name.clone(),
                reason: format!("the outputs depend on the undeclared input {i}"),
            });
        }
        Ok((program, met))
    }

    /// The count of the program under each policy, in order, until `stop_before` a policy
    /// says stop given the counts so far. Where the graph meets them ([`Switches`]), the first
    /// policy chooses the switches ([`KernelSpec::choose_switches`]) and the others are tried
    /// in each mode with the offers it kept there.
    fn search(
        &self,
        share_subsums: bool,
        stop_before: impl Fn(Policy, &[(Policy, OpCount)]) -> bool,
    ) -> Result<Vec<(Policy, OpCount)>, Error> {
        let mut tried: Vec<(Policy, OpCount)> = Vec::new();
        let mut chosen: Vec<Policy> = Vec::new();
        for base in policies() {
            if stop_before(base, &tried) {
                break;
            }
            if chosen.is_empty() {
                chosen = self.choose_switches(base, share_subsums, &mut tried)?;
                continue;
            }
            for setting in &chosen {
                let policy = Policy {
                    reverse_mode: setting.reverse_mode,
                    kept_offers: setting.kept_offers,
                    ..base
                };
                let (program, _) = self.program(policy, share_subsums)?;
                tried.push((policy, program.count()));
            }
        }
        Ok(tried)
    }

    /// Under `base`, for each differentiation mode the graph needs, the offers to keep: each
    /// offer in turn is kept where that lowers the cost so far (greedy, one build an offer).
    /// Every program built is pushed on `tried`.
    fn choose_switches(
        &self,
        base: Policy,
        share_subsums: bool,
        tried: &mut Vec<(Policy, OpCount)>,
    ) -> Result<Vec<Policy>, Error> {
        let mut cost_of = |policy: Policy| -> Result<((f64, f64), Switches), Error> {
            let (program, met) = self.program(policy, share_subsums)?;
            let count = program.count();
            let cost = self.objective.cost(&count);
            tried.push((policy, count));
            Ok((cost, met))
        };
        let (first, met) = cost_of(base)?;
        let modes: &[bool] = if met.jacobian {
            &[false, true]
        } else {
            &[false]
        };
        let mut chosen = Vec::new();
        for &reverse_mode in modes {
            let mut best = Policy {
                reverse_mode,
                ..base
            };
            let mut best_cost = if reverse_mode {
                cost_of(best)?.0
            } else {
                first
            };
            for offer in 0..met.offers {
                let candidate = Policy {
                    kept_offers: best.kept_offers | 1 << offer,
                    ..best
                };
                let (cost, _) = cost_of(candidate)?;
                if cost < best_cost {
                    (best, best_cost) = (candidate, cost);
                }
            }
            chosen.push(best);
        }
        Ok(chosen)
    }

    /// The count of the program under every policy, sub-sums shared (for studying the
    /// optimizer).
    ///
    /// # Errors
    /// As [`KernelSpec::compile`].
    pub fn costs_by_policy(&self) -> Result<Vec<(Policy, OpCount)>, Error> {
        self.search(true, |_, _| false)
    }

    /// Compiles under every policy, keeps the cheapest, and lowers that one again sharing the
    /// sub-sums its sums have in common (which only ever saves additions). The policies that
    /// distribute products over sums are tried only when the best flat program weighs at most
    /// [`EXPANSION_LIMIT`]. A kernel that takes Jacobians is tried in both differentiation
    /// modes, and one offered units with the offers its first policy kept: each
    /// derivative kernel gets the cheaper mode.
    pub fn compile(&self) -> Result<Compiled, Error> {
        let cost = |count: &OpCount| self.objective.cost(count);
        let cheapest = |tried: &[(Policy, OpCount)]| {
            tried
                .iter()
                .map(|(policy, count)| (*policy, cost(count)))
                .reduce(|best, next| if next.1 < best.1 { next } else { best })
        };
        let tried = self.search(false, |base, tried| {
            base.expand_limit > 1
                && self.objective == Objective::Speed
                && cheapest(tried).is_some_and(|(_, (weight, _))| weight > EXPANSION_LIMIT)
        })?;
        let best: Option<(Policy, (f64, f64))> = cheapest(&tried);
        let (policy, _) = best.expect("at least one policy");
        let (program, _) = self.program(policy, true)?;
        Ok(Compiled {
            count: program.count(),
            program,
            policy,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(build: BuildFn) -> KernelSpec {
        KernelSpec {
            name: "probe".into(),
            family: "test".into(),
            setting: Setting::Free,
            equations: vec![],
            title: String::new(),
            doc: String::new(),
            chapter: None,
            objective: Objective::Speed,
            inputs: vec![Arg::new(
                "x",
                Shape::Vector(3),
                ["x0", "x1", "x2"].map(String::from).to_vec(),
                "",
            )],
            outputs: vec![Arg::output("y", Shape::Vector(3), "")],
            build,
        }
    }

    /// The switches are tried only where the graph meets them: a kernel that takes no
    /// Jacobian and offers nothing is built under the rewriting policies alone; one that
    /// takes a Jacobian in both modes; an offer both kept and folded.
    #[test]
    fn the_search_tries_the_switches_a_kernel_meets_and_no_others() {
        let plain = spec(Box::new(|_, x| {
            vec![vec![x[0][0] * x[0][1], x[0][1], x[0][2]]]
        }));
        let costs = plain.costs_by_policy().unwrap();
        assert_eq!(costs.len(), policies().count());
        assert!(costs
            .iter()
            .all(|(p, _)| !p.reverse_mode && p.kept_offers == 0));

        let differentiated = spec(Box::new(|g, x| {
            let f = [(x[0][0] * x[0][1]).sin() * x[0][2]];
            vec![g.jacobian(&f, &x[0])]
        }));
        let costs = differentiated.costs_by_policy().unwrap();
        assert!(costs.iter().any(|(p, _)| p.reverse_mode));
        assert!(costs.iter().any(|(p, _)| !p.reverse_mode));

        let offered = spec(Box::new(|_, x| {
            let s = (x[0][0] + x[0][1]).keep_where_cheaper("s");
            vec![vec![s * x[0][2], s * x[0][1], s]]
        }));
        let costs = offered.costs_by_policy().unwrap();
        assert!(costs.iter().any(|(p, _)| p.kept_offers == 1));
        assert!(costs.iter().all(|(p, _)| p.kept_offers <= 1));
    }

    /// Whichever mode wins, the compiled Jacobian is the derivative: both modes agree with
    /// the hand-derived gradient of `sin(x0 x1) x2`.
    #[test]
    fn the_compiled_jacobian_is_the_derivative_in_either_mode() {
        let differentiated = spec(Box::new(|g, x| {
            let f = [(x[0][0] * x[0][1]).sin() * x[0][2]];
            vec![g.jacobian(&f, &x[0])]
        }));
        let x: [f64; 3] = [0.3, -1.2, 2.5];
        let expected = [
            (x[0] * x[1]).cos() * x[1] * x[2],
            (x[0] * x[1]).cos() * x[0] * x[2],
            (x[0] * x[1]).sin(),
        ];
        for reverse_mode in [false, true] {
            let policy = Policy {
                reverse_mode,
                ..Policy::FLAT
            };
            let (program, met) = differentiated.program(policy, true).unwrap();
            assert!(met.jacobian);
            for (got, want) in program.eval(&x).iter().zip(expected) {
                assert!((got - want).abs() < 1e-15, "{got} != {want}");
            }
        }
        let compiled = differentiated.compile().unwrap();
        for (got, want) in compiled.program.eval(&x).iter().zip(expected) {
            assert!((got - want).abs() < 1e-15, "{got} != {want}");
        }
    }
}
