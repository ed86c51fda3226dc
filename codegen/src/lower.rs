//! From a simplified DAG to a counted straight-line program: factoring, scheduling, counting.
//!
//! Factoring pulls the most frequent factor out of the private terms of every sum (greedy,
//! Horner-like); lowering then walks the DAG from the outputs (so dead nodes never reach the
//! program), turns sums and products into chains of binary operations, shares a reciprocal
//! whenever two products divide by the same base, and memoises every instruction so that equal
//! instructions are emitted once.

use crate::count::OpCount;
use crate::dag::{Arena, Func, Node, NodeId, Real};
use crate::subsum::{self, Item, Plan};
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use std::collections::BTreeMap;

/// An operand of an instruction.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Operand {
    Temp(u32),
    Input(u32),
    Const(Real),
}

/// One instruction; its result is the temporary with the instruction's index.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Instr {
    Add(Operand, Operand),
    Sub(Operand, Operand),
    Mul(Operand, Operand),
    Div(Operand, Operand),
    Neg(Operand),
    Call(Func, Operand),
    /// `sin a`, with `cos a` in the next temporary ([`Instr::PairedCos`]): one call computes
    /// both.
    SinCos(Operand),
    /// `cos a`, computed by the [`Instr::SinCos`] just before it.
    PairedCos(Operand),
}

impl Instr {
    /// The instruction's operands.
    pub fn operands(&self) -> Vec<Operand> {
        match *self {
            Instr::Add(a, b) | Instr::Sub(a, b) | Instr::Mul(a, b) | Instr::Div(a, b) => {
                vec![a, b]
            }
            Instr::Neg(a) | Instr::Call(_, a) | Instr::SinCos(a) | Instr::PairedCos(a) => vec![a],
        }
    }

    /// The same operation on operands mapped by `f` (renumbering temporaries).
    pub fn map_operands(self, f: impl Fn(Operand) -> Operand) -> Instr {
        match self {
            Instr::Add(a, b) => Instr::Add(f(a), f(b)),
            Instr::Sub(a, b) => Instr::Sub(f(a), f(b)),
            Instr::Mul(a, b) => Instr::Mul(f(a), f(b)),
            Instr::Div(a, b) => Instr::Div(f(a), f(b)),
            Instr::Neg(a) => Instr::Neg(f(a)),
            Instr::Call(func, a) => Instr::Call(func, f(a)),
            Instr::SinCos(a) => Instr::SinCos(f(a)),
            Instr::PairedCos(a) => Instr::PairedCos(f(a)),
        }
    }
}

/// A straight-line program: instructions in dependency order and the output operands.
#[derive(Clone, Debug, Default)]
pub struct Program {
    pub instrs: Vec<Instr>,
    pub outputs: Vec<Operand>,
}

impl Program {
    pub fn count(&self) -> OpCount {
        let mut c = OpCount::default();
        for i in &self.instrs {
            match i {
                Instr::Add(..) | Instr::Sub(..) => c.add += 1,
                Instr::Mul(..) => c.mul += 1,
                Instr::Div(..) => c.div += 1,
                Instr::Neg(..) => c.neg += 1,
                Instr::Call(f, _) => *c.calls.entry(f.name().to_string()).or_insert(0) += 1,
                Instr::SinCos(_) => *c.calls.entry("sin_cos".to_string()).or_insert(0) += 1,
                Instr::PairedCos(_) => {}
            }
        }
        c
    }

    /// Evaluates the program on `inputs` (used by the tests and the optimizer's self-check).
    pub fn eval(&self, inputs: &[f64]) -> Vec<f64> {
        let mut t = Vec::with_capacity(self.instrs.len());
        let val = |t: &Vec<f64>, o: Operand| match o {
            Operand::Temp(i) => t[i as usize],
            Operand::Input(i) => inputs[i as usize],
            Operand::Const(c) => c.get(),
        };
        for i in &self.instrs {
            let v = match *i {
                Instr::Add(a, b) => val(&t, a) + val(&t, b),
                Instr::Sub(a, b) => val(&t, a) - val(&t, b),
                Instr::Mul(a, b) => val(&t, a) * val(&t, b),
                Instr::Div(a, b) => val(&t, a) / val(&t, b),
                Instr::Neg(a) => -val(&t, a),
                Instr::Call(f, a) => {
                    let x = val(&t, a);
                    match f {
                        Func::Sin => x.sin(),
                        Func::Cos => x.cos(),
                        Func::Sqrt => x.sqrt(),
                        Func::Sign => crate::dag::sign(x),
                        Func::Atan => x.atan(),
                        Func::Keep => x,
                    }
                }
                Instr::SinCos(a) => val(&t, a).sin(),
                Instr::PairedCos(a) => val(&t, a).cos(),
            };
            t.push(v);
        }
        self.outputs.iter().map(|&o| val(&t, o)).collect()
    }

    /// Checks the program's invariants: every temporary is defined before it is read (so the
    /// program runs in one forward pass), every paired cosine directly follows the sine-cosine
    /// call of the same operand, every sine-cosine call is followed by its pair, and
    /// the outputs read defined temporaries.
    ///
    /// # Errors
    /// The first broken invariant, with the instruction's index.
    pub fn verify(&self) -> Result<(), String> {
        let defined = |o: Operand, at: usize| match o {
            Operand::Temp(t) if t as usize >= at => {
                Err(format!("instruction {at} reads t{t} before it is defined"))
            }
            _ => Ok(()),
        };
        for (i, instr) in self.instrs.iter().enumerate() {
            for o in instr.operands() {
                defined(o, i)?;
            }
            let previous = i.checked_sub(1).map(|p| self.instrs[p]);
            match (instr, previous) {
                (Instr::PairedCos(a), Some(Instr::SinCos(b))) if *a == b => {}
                (Instr::PairedCos(_), _) => {
                    return Err(format!(
                        "instruction {i}: a paired cosine not right after its sine"
                    ))
                }
                (Instr::SinCos(a), _) if self.instrs.get(i + 1) != Some(&Instr::PairedCos(*a)) => {
                    return Err(format!(
                        "instruction {i}: a sine-cosine pair without its cosine"
                    ))
                }
                _ => {}
            }
        }
        for &o in &self.outputs {
            defined(o, self.instrs.len())?;
        }
        Ok(())
    }

    /// Indices of the inputs the program reads.
    pub fn used_inputs(&self) -> HashSet<u32> {
        self.instrs
            .iter()
            .flat_map(Instr::operands)
            .chain(self.outputs.iter().copied())
            .filter_map(|o| match o {
                Operand::Input(i) => Some(i),
                _ => None,
            })
            .collect()
    }

    /// Indices of the temporaries the outputs are.
    pub fn output_temps(&self) -> HashSet<u32> {
        self.outputs
            .iter()
            .filter_map(|o| match o {
                Operand::Temp(i) => Some(*i),
                _ => None,
            })
            .collect()
    }
}

/// How often each node reachable from `outputs` is referenced.
fn use_counts(arena: &Arena, outputs: &[NodeId]) -> HashMap<NodeId, usize> {
    let mut uses: HashMap<NodeId, usize> = HashMap::default();
    let mut stack: Vec<NodeId> = Vec::new();
    for &o in outputs {
        if *uses.entry(o).or_insert(0) == 0 {
            stack.push(o);
        }
        *uses.get_mut(&o).unwrap() += 1;
    }
    while let Some(id) = stack.pop() {
        for c in arena.node(id).children() {
            let n = uses.entry(c).or_insert(0);
            if *n == 0 {
                stack.push(c);
            }
            *n += 1;
        }
    }
    uses
}

/// Greedy factoring of every sum reachable from `outputs`; returns the new outputs.
pub fn factor(arena: &mut Arena, outputs: &[NodeId]) -> Vec<NodeId> {
    let uses = use_counts(arena, outputs);
    let mut f = Factorer {
        arena,
        uses,
        memo: HashMap::default(),
    };
    outputs.iter().map(|&o| f.opt(o)).collect()
}

struct Factorer<'a> {
    arena: &'a mut Arena,
    uses: HashMap<NodeId, usize>,
    memo: HashMap<NodeId, NodeId>,
}

type Monomial = (Vec<(NodeId, i32)>, f64);

impl Factorer<'_> {
    fn opt(&mut self, id: NodeId) -> NodeId {
        if let Some(&r) = self.memo.get(&id) {
            return r;
        }
        let r = match self.arena.node(id).clone() {
            Node::Const(_) | Node::Input(_) => id,
            Node::Call(f, a) => {
                let a = self.opt(a);
                self.arena.call(f, a)
            }
            Node::Product(fs) => {
                let fs: Vec<_> = fs.into_iter().map(|(b, e)| (self.opt(b), e)).collect();
                self.arena.make_product(fs)
            }
            Node::Sum { terms, constant } => {
                let mut constant = constant.get();
                let mut done: BTreeMap<NodeId, f64> = BTreeMap::new();
                let mut pool: Vec<Monomial> = Vec::new();
                for (t, c) in terms {
                    let shared = self.uses.get(&t).copied().unwrap_or(0) > 1;
                    let t = self.opt(t);
                    if shared {
                        self.accumulate(&mut done, &mut constant, t, c.get());
                    } else {
                        pool.push((self.arena.factors(t), c.get()));
                    }
                }
                self.factor_pool(&mut pool, &mut done, &mut constant);
                for (fs, c) in pool {
                    let p = self.arena.make_product(fs);
                    self.accumulate(&mut done, &mut constant, p, c);
                }
                if constant != 0.0 && self.arena.policy().absorb_constants {
                    self.absorb_constant(&mut done, &mut constant);
                }
                self.arena.make_sum(done, constant)
            }
        };
        self.memo.insert(id, r);
        r
    }

    /// Adds `c · node` to a linear form, flattening sums so the form stays canonical.
    fn accumulate(
        &self,
        form: &mut BTreeMap<NodeId, f64>,
        constant: &mut f64,
        node: NodeId,
        c: f64,
    ) {
        let (terms, k) = self.arena.linear(node);
        *constant += c * k;
        for (t, tc) in terms {
            *form.entry(t).or_insert(0.0) += c * tc;
        }
    }

    /// Rewrites `k·Q/S + c` as `k·(Q + (c/k)·S)/S` when the new numerator has fewer terms.
    fn absorb_constant(&mut self, done: &mut BTreeMap<NodeId, f64>, constant: &mut f64) {
        let candidates: Vec<(NodeId, f64)> = done.iter().map(|(&t, &k)| (t, k)).collect();
        for (t, k) in candidates {
            let factors = self.arena.factors(t);
            for &(s, e) in &factors {
                if e != -1 {
                    continue;
                }
                let rest: Vec<_> = factors.iter().copied().filter(|&(b, _)| b != s).collect();
                let q = self.arena.make_product(rest);
                let n = self.arena.combine(q, 1.0, s, *constant / k);
                let width = |a: &Arena, id| {
                    let (terms, c) = a.linear(id);
                    terms.len() + usize::from(c != 0.0)
                };
                if width(self.arena, n) < width(self.arena, q) + 1 {
                    let term = self.arena.make_product([(n, 1), (s, -1)]);
                    done.remove(&t);
                    *constant = 0.0;
                    self.accumulate(done, constant, term, k);
                    return;
                }
            }
        }
    }

    fn factor_pool(
        &mut self,
        pool: &mut Vec<Monomial>,
        done: &mut BTreeMap<NodeId, f64>,
        done_constant: &mut f64,
    ) {
        loop {
            let mut counts: BTreeMap<(NodeId, bool), usize> = BTreeMap::new();
            for (fs, _) in pool.iter() {
                for &(b, e) in fs {
                    *counts.entry((b, e < 0)).or_insert(0) += 1;
                }
            }
            let best = counts
                .iter()
                .filter(|(_, &n)| n >= 2)
                .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0)))
                .map(|(&k, _)| k);
            let Some((base, inverse)) = best else { return };
            let unit = if inverse { -1 } else { 1 };
            let (group, rest): (Vec<Monomial>, Vec<Monomial>) = pool
                .drain(..)
                .partition(|(fs, _)| fs.iter().any(|&(b, e)| b == base && (e < 0) == inverse));
            *pool = rest;
            let mut quotient: BTreeMap<NodeId, f64> = BTreeMap::new();
            let mut constant = 0.0;
            for (fs, c) in group {
                let q: Vec<_> = fs
                    .into_iter()
                    .map(|(b, e)| if b == base { (b, e - unit) } else { (b, e) })
                    .collect();
                let q = self.arena.make_product(q);
                self.accumulate(&mut quotient, &mut constant, q, c);
            }
            let q = self.arena.make_sum(quotient, constant);
            let q = self.opt(q);
            let (k, m) = self.arena.split_sign(q);
            let term = match m {
                Some(m) => self.arena.make_product([(base, unit), (m, 1)]),
                None => self.arena.make_product([(base, unit)]),
            };
            self.accumulate(done, done_constant, term, k);
        }
    }
}

/// Lowers the DAG reachable from `outputs` into a program; with `share_subsums`, the pairs of
/// terms several sums share are added once ([`subsum`]).
pub fn lower(arena: &Arena, outputs: &[NodeId], share_subsums: bool) -> Program {
    let program = lower_unchecked(arena, outputs, share_subsums);
    debug_assert_eq!(program.verify(), Ok(()), "the lowering breaks an invariant");
    program
}

fn lower_unchecked(arena: &Arena, outputs: &[NodeId], share_subsums: bool) -> Program {
    let uses = use_counts(arena, outputs);
    let mut reciprocal_uses: HashMap<NodeId, usize> = HashMap::default();
    for &id in uses.keys() {
        if let Node::Product(fs) = arena.node(id) {
            for &(b, e) in fs {
                if e < 0 {
                    *reciprocal_uses.entry(b).or_insert(0) += 1;
                }
            }
        }
    }
    let min_uses = if arena.policy().share_reciprocals {
        2
    } else {
        usize::MAX
    };
    let shared_reciprocals = reciprocal_uses
        .into_iter()
        .filter(|&(_, n)| n >= min_uses)
        .map(|(b, _)| b)
        .collect();
    // Arguments whose sine and cosine are both needed: one `SinCos` computes the two.
    let calls: HashMap<(Func, NodeId), NodeId> = uses
        .keys()
        .filter_map(|&id| match *arena.node(id) {
            Node::Call(f, a) => Some(((f, a), id)),
            _ => None,
        })
        .collect();
    let sin_cos_pairs = calls
        .iter()
        .filter(|((f, _), _)| *f == Func::Sin)
        .filter_map(|(&(_, a), &sin)| calls.get(&(Func::Cos, a)).map(|&cos| (a, (sin, cos))))
        .collect();
    let plan = if share_subsums {
        subsum::plan(arena, uses.keys())
    } else {
        subsum::unshared(arena, uses.keys())
    };
    let mut l = Lowerer {
        arena,
        program: Program::default(),
        values: HashMap::default(),
        memo: HashMap::default(),
        shared_reciprocals,
        sin_cos_pairs,
        plan,
        subsum_values: HashMap::default(),
    };
    let outs: Vec<Operand> = outputs.iter().map(|&o| l.value(o)).collect();
    l.program.outputs = outs;
    l.program
}

struct Lowerer<'a> {
    arena: &'a Arena,
    program: Program,
    values: HashMap<NodeId, Operand>,
    memo: HashMap<Instr, Operand>,
    shared_reciprocals: HashSet<NodeId>,
    /// For an argument whose sine and cosine are both used, the two call nodes.
    sin_cos_pairs: HashMap<NodeId, (NodeId, NodeId)>,
    /// How every sum adds up, with the sub-sums several of them share.
    plan: Plan,
    subsum_values: HashMap<usize, Operand>,
}

impl Lowerer<'_> {
    fn emit(&mut self, instr: Instr) -> Operand {
        let instr = match instr {
            // Commutative operations take their operands in a fixed order, so equal
            // instructions meet in the memo.
            Instr::Add(a, b) if key(b) < key(a) => Instr::Add(b, a),
            Instr::Mul(a, b) if key(b) < key(a) => Instr::Mul(b, a),
            other => other,
        };
        if let Some(&o) = self.memo.get(&instr) {
            return o;
        }
        let o = Operand::Temp(self.program.instrs.len() as u32);
        self.program.instrs.push(instr);
        self.memo.insert(instr, o);
        o
    }

    fn value(&mut self, id: NodeId) -> Operand {
        if let Some(&o) = self.values.get(&id) {
            return o;
        }
        let o = match self.arena.node(id).clone() {
            Node::Const(c) => Operand::Const(c),
            Node::Input(i) => Operand::Input(i),
            // A unit is its argument's value: no instruction.
            Node::Call(Func::Keep, a) => self.value(a),
            Node::Call(f, arg) if matches!(f, Func::Sin | Func::Cos) => {
                let a = self.value(arg);
                match self.sin_cos_pairs.get(&arg).copied() {
                    Some((sin, cos)) => {
                        let s = self.emit(Instr::SinCos(a));
                        let c = self.emit(Instr::PairedCos(a));
                        self.values.insert(sin, s);
                        self.values.insert(cos, c);
                        if f == Func::Sin {
                            s
                        } else {
                            c
                        }
                    }
                    None => self.emit(Instr::Call(f, a)),
                }
            }
            Node::Call(f, a) => {
                let a = self.value(a);
                self.emit(Instr::Call(f, a))
            }
            Node::Product(fs) => self.product(&fs),
            Node::Sum { constant, .. } => {
                let items = self.plan.sums[&id].clone();
                let (o, negative) = self.sum(&items, constant.get());
                if negative {
                    self.emit(Instr::Neg(o))
                } else {
                    o
                }
            }
        };
        self.values.insert(id, o);
        o
    }

    fn power(&mut self, base: Operand, exp: u32) -> Operand {
        match exp {
            1 => base,
            _ if exp.is_multiple_of(2) => {
                let h = self.power(base, exp / 2);
                self.emit(Instr::Mul(h, h))
            }
            _ => {
                let h = self.power(base, exp - 1);
                self.emit(Instr::Mul(h, base))
            }
        }
    }

    fn chain(&mut self, items: Vec<Operand>, op: fn(Operand, Operand) -> Instr) -> Option<Operand> {
        let mut it = items.into_iter();
        let first = it.next()?;
        Some(it.fold(first, |acc, x| self.emit(op(acc, x))))
    }

    fn product(&mut self, fs: &[(NodeId, i32)]) -> Operand {
        let mut num = Vec::new();
        let mut den = Vec::new();
        for &(b, e) in fs {
            if e > 0 {
                let v = self.value(b);
                num.push(self.power(v, e as u32));
            } else if self.shared_reciprocals.contains(&b) {
                let v = self.value(b);
                let one = Operand::Const(Real::new(1.0));
                let r = self.emit(Instr::Div(one, v));
                num.push(self.power(r, (-e) as u32));
            } else {
                let v = self.value(b);
                den.push(self.power(v, (-e) as u32));
            }
        }
        let num = self.chain(num, Instr::Mul);
        let den = self.chain(den, Instr::Mul);
        match (num, den) {
            (Some(n), None) => n,
            (Some(n), Some(d)) => self.emit(Instr::Div(n, d)),
            (None, Some(d)) => self.emit(Instr::Div(Operand::Const(Real::new(1.0)), d)),
            (None, None) => Operand::Const(Real::new(1.0)),
        }
    }

    /// The value of a planned addend: a term, or a shared sub-sum, computed once.
    fn item(&mut self, item: Item) -> Operand {
        match item {
            Item::Term(id) => self.value(id),
            Item::Sub(k) => {
                if let Some(&o) = self.subsum_values.get(&k) {
                    return o;
                }
                let sub = self.plan.subsums[k];
                let (a, b) = (self.item(sub.first), self.item(sub.second));
                let o = self.emit(if sub.negative {
                    Instr::Sub(a, b)
                } else {
                    Instr::Add(a, b)
                });
                self.subsum_values.insert(k, o);
                o
            }
        }
    }

    /// Lowers `Σ cᵢ·itemᵢ + constant`; returns the operand and whether it holds the negated
    /// value.
    fn sum(&mut self, items: &[(Item, f64)], constant: f64) -> (Operand, bool) {
        // Terms sharing a coefficient magnitude are summed first and scaled once.
        let mut groups: BTreeMap<u64, Vec<(Operand, bool)>> = BTreeMap::new();
        let mut order: Vec<u64> = Vec::new();
        for &(item, c) in items {
            let v = self.item(item);
            let mag = c.abs().to_bits();
            if !groups.contains_key(&mag) {
                order.push(mag);
            }
            groups.entry(mag).or_default().push((v, c < 0.0));
        }
        let mut items: Vec<(Operand, bool)> = Vec::new();
        for mag in order {
            let group = groups.remove(&mag).unwrap();
            let m = f64::from_bits(mag);
            if m == 1.0 {
                items.extend(group);
            } else {
                let (inner, negative) = self.signed_sum(group);
                let scaled = self.emit(Instr::Mul(inner, Operand::Const(Real::new(m))));
                items.push((scaled, negative));
            }
        }
        if constant != 0.0 {
            items.push((Operand::Const(Real::new(constant.abs())), constant < 0.0));
        }
        self.signed_sum(items)
    }

    /// Sums as a balanced tree, so long sums do not become one serial dependency chain.
    fn balanced_sum(&mut self, mut items: Vec<Operand>) -> Option<Operand> {
        while items.len() > 1 {
            let mut next = Vec::with_capacity(items.len().div_ceil(2));
            for pair in items.chunks(2) {
                next.push(match *pair {
                    [a, b] => self.emit(Instr::Add(a, b)),
                    [a] => a,
                    _ => unreachable!("chunks of two"),
                });
            }
            items = next;
        }
        items.pop()
    }

    fn signed_sum(&mut self, items: Vec<(Operand, bool)>) -> (Operand, bool) {
        let (pos, neg): (Vec<_>, Vec<_>) = items.into_iter().partition(|&(_, n)| !n);
        let pos: Vec<Operand> = pos.into_iter().map(|p| p.0).collect();
        let neg: Vec<Operand> = neg.into_iter().map(|p| p.0).collect();
        let Some(p) = self.balanced_sum(pos) else {
            let n = self.balanced_sum(neg).expect("a sum has a term");
            return (n, true);
        };
        match self.balanced_sum(neg) {
            Some(n) => (self.emit(Instr::Sub(p, n)), false),
            None => (p, false),
        }
    }
}

fn key(o: Operand) -> (u8, u64) {
    match o {
        Operand::Input(i) => (0, i as u64),
        Operand::Temp(i) => (1, i as u64),
        Operand::Const(c) => (2, c.get().to_bits()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dag::{Graph, Policy};

    fn compile(policy: Policy, build: impl for<'g> Fn(&'g Graph) -> Vec<NodeId>) -> Program {
        let g = Graph::new(policy);
        let outs = build(&g);
        let mut arena = g.into_arena();
        let outs = factor(&mut arena, &outs);
        lower(&arena, &outs, true)
    }

    #[test]
    fn factoring_saves_a_multiplication() {
        let p = compile(
            Policy {
                expand_limit: 64,
                ..Policy::FLAT
            },
            |g| {
                let (a, b, c) = (g.input(0), g.input(1), g.input(2));
                vec![(a * b + a * c).id]
            },
        );
        let n = p.count();
        assert_eq!((n.mul, n.add), (1, 1));
        assert_eq!(p.eval(&[2.0, 3.0, 5.0]), vec![16.0]);
    }

    #[test]
    fn shared_products_are_not_refactored() {
        let p = compile(
            Policy {
                expand_limit: 64,
                ..Policy::FLAT
            },
            |g| {
                let (a, b, c) = (g.input(0), g.input(1), g.input(2));
                vec![(a * b + a * c).id, (a * b).id, (a * c).id]
            },
        );
        let n = p.count();
        assert_eq!((n.mul, n.add), (2, 1));
    }

    #[test]
    fn equal_instructions_are_emitted_once() {
        let p = compile(Policy::default(), |g| {
            let (a, b, c) = (g.input(0), g.input(1), g.input(2));
            vec![(a * b * c).id, (a * b).id]
        });
        assert_eq!(p.count().mul, 2);
    }

    #[test]
    fn shared_reciprocal_is_computed_once() {
        let p = compile(Policy::default(), |g| {
            let (a, b, c) = (g.input(0), g.input(1), g.input(2));
            let d = b - c;
            vec![(a / d).id, (c / d).id]
        });
        let n = p.count();
        assert_eq!((n.div, n.mul, n.add), (1, 2, 1));
        let out = p.eval(&[1.0, 3.0, 1.0]);
        assert_eq!(out, vec![0.5, 0.5]);
    }

    #[test]
    fn negated_output_costs_one_negation() {
        let p = compile(Policy::default(), |g| {
            let (a, b) = (g.input(0), g.input(1));
            vec![(-(a * b)).id, (b - a).id]
        });
        let n = p.count();
        assert_eq!((n.mul, n.neg, n.add), (1, 1, 1));
        assert_eq!(p.eval(&[2.0, 3.0]), vec![-6.0, 1.0]);
    }

    #[test]
    fn sine_and_cosine_of_one_argument_are_one_call() {
        let p = compile(Policy::default(), |g| {
            let (a, b) = (g.input(0), g.input(1));
            vec![(a.sin() * b).id, (a.cos() + b).id, b.sin().id]
        });
        let n = p.count();
        assert_eq!(n.calls.get("sin_cos"), Some(&1));
        assert_eq!(n.calls.get("sin"), Some(&1), "b has no cosine to pair with");
        let pos = p
            .instrs
            .iter()
            .position(|i| matches!(i, Instr::SinCos(_)))
            .unwrap();
        assert!(matches!(p.instrs[pos + 1], Instr::PairedCos(_)));
        let out = p.eval(&[0.3, 2.0]);
        assert_eq!(
            out,
            vec![0.3f64.sin() * 2.0, 0.3f64.cos() + 2.0, 2.0f64.sin()]
        );
    }

    #[test]
    fn coefficient_groups_scale_once() {
        let p = compile(Policy::default(), |g| {
            let (a, b, c) = (g.input(0), g.input(1), g.input(2));
            vec![(a * 2.0 + b * 2.0 + c).id]
        });
        let n = p.count();
        assert_eq!((n.mul, n.add), (1, 2));
        assert_eq!(p.eval(&[1.0, 2.0, 3.0]), vec![9.0]);
    }

    #[test]
    fn verify_refuses_each_broken_invariant() {
        let (x, t) = (Operand::Input(0), Operand::Temp);
        let good = Program {
            instrs: vec![
                Instr::SinCos(x),
                Instr::PairedCos(x),
                Instr::Mul(t(0), t(1)),
            ],
            outputs: vec![t(2)],
        };
        assert_eq!(good.verify(), Ok(()));
        let early = Program {
            instrs: vec![Instr::Mul(t(1), x), Instr::Neg(x)],
            outputs: vec![t(0)],
        };
        assert!(early.verify().unwrap_err().contains("reads t1 before"));
        let lone = Program {
            instrs: vec![Instr::Neg(x), Instr::PairedCos(x)],
            outputs: vec![t(1)],
        };
        assert!(lone.verify().unwrap_err().contains("paired cosine"));
        let unpaired = Program {
            instrs: vec![Instr::SinCos(x), Instr::Neg(x)],
            outputs: vec![t(0)],
        };
        assert!(unpaired
            .verify()
            .unwrap_err()
            .contains("without its cosine"));
        let dangling = Program {
            instrs: vec![Instr::Neg(x)],
            outputs: vec![t(3)],
        };
        assert!(dangling.verify().is_err());
    }

    #[test]
    fn the_model_kernels_verify_after_lowering_and_scheduling() {
        use crate::model::kernels::specs;
        use crate::{Mechanism, Model, ParameterSet, Robot};
        for model in Model::ALL {
            let mechanism = Mechanism::c5(&Robot::default(), model);
            for entry in specs(&mechanism, &ParameterSet::None, "").unwrap() {
                let program = entry.spec.compile().unwrap().program;
                assert_eq!(program.verify(), Ok(()), "{}", entry.spec.name);
                let scheduled = crate::schedule::schedule(&program);
                assert_eq!(scheduled.verify(), Ok(()), "{}", entry.spec.name);
            }
        }
    }
}
