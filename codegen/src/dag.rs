//! The expression DAG: an arena of hash-consed nodes whose constructors simplify.
//!
//! Every node is built through [`Arena`]'s constructors, which are the simplifier's front door:
//! constants fold, zeros and ones disappear, sums are canonical coefficient maps (so
//! `(yc - L) - (yc + L)` is `-2L`), products are monic factor maps with integer exponents, and
//! signs float up into the enclosing sum where they cost nothing. Children always precede their
//! parents, and equal nodes are one node, so hash-consing is the common-subexpression elimination.

use rustc_hash::FxHashMap as HashMap;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Index of a node in the arena; prints as `v12`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
pub struct NodeId(u32);

impl NodeId {
    /// The node at `index` of an arena (for walking it).
    pub fn from_index(index: usize) -> Self {
        NodeId(index as u32)
    }
}

impl fmt::Display for NodeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "v{}", self.0)
    }
}

/// A finite `f64` that hashes by its bits; `-0.0` is stored as `0.0`.
#[derive(Clone, Copy, Debug, PartialOrd)]
pub struct Real(f64);

impl Real {
    pub fn new(value: f64) -> Self {
        Real(if value == 0.0 { 0.0 } else { value })
    }
    pub fn get(self) -> f64 {
        self.0
    }
}

impl PartialEq for Real {
    fn eq(&self, other: &Self) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}
impl Eq for Real {}
impl Hash for Real {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.to_bits().hash(state);
    }
}

/// Elementary functions the kernels may call.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub enum Func {
    Sin,
    Cos,
    Sqrt,
    /// `-1`, `0` or `1` (zero at zero, unlike `f64::signum`): Coulomb friction.
    Sign,
    /// The arc tangent, in `(-π/2, π/2)`: the RPY angles of a rotation in the workspace.
    Atan,
    /// The identity, as a unit: a subexpression computed once whose value products and sums
    /// use whole, without flattening through it (a unit vector's component, say, that many
    /// dot products read). It costs nothing: the lowering gives it its argument's value.
    Keep,
}

/// `sign x`: `-1`, `0` or `1`.
pub fn sign(x: f64) -> f64 {
    f64::from(i8::from(x > 0.0) - i8::from(x < 0.0))
}

impl Func {
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Sqrt => "sqrt",
            Func::Sign => "sign",
            Func::Atan => "atan",
            Func::Keep => "keep",
        }
    }
}

/// One node of the DAG, always in canonical form.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Node {
    Const(Real),
    /// The `n`-th scalar input of the kernel.
    Input(u32),
    /// `Σ cᵢ·termᵢ + constant`: at least one term, terms sorted by id, never a `Sum` or `Const`
    /// themselves, coefficients non-zero, and never the bare `1·x`.
    Sum {
        terms: Vec<(NodeId, Real)>,
        constant: Real,
    },
    /// `Π baseᵢ^expᵢ`, monic: bases sorted by id, never `Product` or `Const`, exponents non-zero.
    Product(Vec<(NodeId, i32)>),
    Call(Func, NodeId),
}

impl Node {
    /// The nodes this one is built from (they precede it in the arena).
    pub fn children(&self) -> Vec<NodeId> {
        match self {
            Node::Const(_) | Node::Input(_) => vec![],
            Node::Sum { terms, .. } => terms.iter().map(|t| t.0).collect(),
            Node::Product(f) => f.iter().map(|t| t.0).collect(),
            Node::Call(_, a) => vec![*a],
        }
    }
}

/// Rewriting policy of an arena, chosen per kernel by the optimizer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Policy {
    /// Distribute a product of sums when the expanded sum has at most this many terms
    /// (1 disables expansion).
    pub expand_limit: usize,
    /// Fold a constant into a quotient when that cancels terms: `y5/(y6 - y5) + 1 = y6/(y6 - y5)`.
    pub absorb_constants: bool,
    /// Compute `1/s` once when several products divide by `s` (else divide in each product).
    pub share_reciprocals: bool,
    /// Distribute a product over a sum that is one term plus a constant, `t·(x + c) = t·x + c·t`,
    /// so that offsets such as the `±L` of a pair of legs cancel where their terms meet.
    pub distribute_offsets: bool,
    /// Take the Jacobians a kernel asks for ([`Graph::jacobian`]) by reverse mode, one sweep per
    /// output, else by forward mode, one sweep per input. Which is cheaper depends on the
    /// kernel, not on its shape alone: the simplifying constructors fold each sweep
    /// differently, so the optimizer tries both.
    pub reverse_mode: bool,
    /// Which of the values a model offers as units ([`Expr::keep_where_cheaper`]) are kept
    /// whole, the others folded into their users: bit `k` for the `k`-th offer the build meets.
    /// Keeping a value whole saves where its users would each expand it, and costs where they
    /// would cancel parts of it, which only the count tells apart, so the optimizer chooses.
    pub kept_offers: u32,
}

impl Policy {
    pub const FLAT: Policy = Policy {
        expand_limit: 1,
        absorb_constants: false,
        share_reciprocals: true,
        distribute_offsets: false,
        reverse_mode: false,
        kept_offers: 0,
    };
}

impl Default for Policy {
    fn default() -> Self {
        Policy::FLAT
    }
}

/// The node arena with its memo table.
#[derive(Debug, Default)]
pub struct Arena {
    nodes: Vec<Node>,
    memo: HashMap<Node, NodeId>,
    policy: Policy,
    /// Set when a constant division by zero, a non-finite constant or a model error was met.
    invalid: Option<String>,
    /// Set when a Jacobian was taken ([`Graph::jacobian`]), so the policy's mode mattered.
    took_jacobian: bool,
    /// The offers met ([`Expr::keep_where_cheaper`]), in the order first met: bit `k` of
    /// [`Policy::kept_offers`] is the `k`-th.
    offers: Vec<&'static str>,
}

/// A linear form: terms with coefficients plus a constant.
pub type Linear = (BTreeMap<NodeId, f64>, f64);

impl Arena {
    pub fn new(policy: Policy) -> Self {
        Arena {
            policy,
            ..Arena::default()
        }
    }

    pub fn policy(&self) -> Policy {
        self.policy
    }

    /// Why the graph cannot be emitted, if it cannot: the first constant division by zero,
    /// non-finite constant or model error met while building it.
    pub fn invalid(&self) -> Option<&str> {
        self.invalid.as_deref()
    }

    /// Whether the graph took a Jacobian ([`Graph::jacobian`]): only then does
    /// [`Policy::reverse_mode`] change it.
    pub fn took_jacobian(&self) -> bool {
        self.took_jacobian
    }

    /// The offers the build met ([`Expr::keep_where_cheaper`]), in the order of the bits of
    /// [`Policy::kept_offers`].
    pub fn offers(&self) -> &[&'static str] {
        &self.offers
    }

    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id.0 as usize]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    fn intern(&mut self, node: Node) -> NodeId {
        if let Some(&id) = self.memo.get(&node) {
            return id;
        }
        let id = NodeId(self.nodes.len() as u32);
        debug_assert!(
            node.children().iter().all(|c| c.0 < id.0),
            "children precede their parents"
        );
        self.nodes.push(node.clone());
        self.memo.insert(node, id);
        id
    }

    pub fn constant(&mut self, value: f64) -> NodeId {
        if !value.is_finite() {
            self.invalid
                .get_or_insert_with(|| format!("non-finite constant {value}"));
            return self.intern(Node::Const(Real::new(0.0)));
        }
        self.intern(Node::Const(Real::new(value)))
    }

    pub fn input(&mut self, index: u32) -> NodeId {
        self.intern(Node::Input(index))
    }

    pub fn const_value(&self, id: NodeId) -> Option<f64> {
        match self.node(id) {
            Node::Const(c) => Some(c.get()),
            _ => None,
        }
    }

    /// The linear form of a node: its terms and constant.
    pub fn linear(&self, id: NodeId) -> Linear {
        match self.node(id) {
            Node::Const(c) => (BTreeMap::new(), c.get()),
            Node::Sum { terms, constant } => (
                terms.iter().map(|&(t, c)| (t, c.get())).collect(),
                constant.get(),
            ),
            _ => (BTreeMap::from([(id, 1.0)]), 0.0),
        }
    }

    /// Builds the canonical node of a linear form.
    pub fn make_sum(&mut self, terms: BTreeMap<NodeId, f64>, constant: f64) -> NodeId {
        let terms: Vec<(NodeId, Real)> = terms
            .into_iter()
            .filter(|&(_, c)| c != 0.0)
            .map(|(t, c)| (t, Real::new(c)))
            .collect();
        if terms.is_empty() {
            return self.constant(constant);
        }
        if terms.len() == 1 && terms[0].1.get() == 1.0 && constant == 0.0 {
            return terms[0].0;
        }
        if !constant.is_finite() || terms.iter().any(|(_, c)| !c.get().is_finite()) {
            self.invalid
                .get_or_insert_with(|| "non-finite coefficient".to_string());
        }
        self.intern(Node::Sum {
            terms,
            constant: Real::new(constant),
        })
    }

    pub fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.combine(a, 1.0, b, 1.0)
    }

    pub fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.combine(a, 1.0, b, -1.0)
    }

    /// `ka·a + kb·b`.
    pub fn combine(&mut self, a: NodeId, ka: f64, b: NodeId, kb: f64) -> NodeId {
        let (mut terms, ca) = self.linear(a);
        terms.values_mut().for_each(|c| *c *= ka);
        let (tb, cb) = self.linear(b);
        for (t, c) in tb {
            *terms.entry(t).or_insert(0.0) += kb * c;
        }
        self.make_sum(terms, ka * ca + kb * cb)
    }

    pub fn scale(&mut self, a: NodeId, k: f64) -> NodeId {
        let zero = self.constant(0.0);
        self.combine(a, k, zero, 0.0)
    }

    pub fn neg(&mut self, a: NodeId) -> NodeId {
        self.scale(a, -1.0)
    }

    /// Splits a node into `coefficient · monic`, where the monic part (if any) is a non-sum atom,
    /// a product, or a sum whose leading coefficient is positive.
    pub fn split_sign(&mut self, id: NodeId) -> (f64, Option<NodeId>) {
        match self.node(id).clone() {
            Node::Const(c) => (c.get(), None),
            Node::Sum { terms, constant } => {
                if terms.len() == 1 && constant.get() == 0.0 {
                    (terms[0].1.get(), Some(terms[0].0))
                } else if terms[0].1.get() < 0.0 {
                    (-1.0, Some(self.neg(id)))
                } else {
                    (1.0, Some(id))
                }
            }
            _ => (1.0, Some(id)),
        }
    }

    /// Factors of a monic node.
    pub fn factors(&self, id: NodeId) -> Vec<(NodeId, i32)> {
        match self.node(id) {
            Node::Product(f) => f.clone(),
            _ => vec![(id, 1)],
        }
    }

    /// Builds the canonical monic product of `factors`.
    pub fn make_product(&mut self, factors: impl IntoIterator<Item = (NodeId, i32)>) -> NodeId {
        let mut map: BTreeMap<NodeId, i32> = BTreeMap::new();
        for (base, exp) in factors {
            for (b, e) in self.factors(base) {
                *map.entry(b).or_insert(0) += e * exp;
            }
        }
        let factors: Vec<(NodeId, i32)> = map.into_iter().filter(|&(_, e)| e != 0).collect();
        match factors.as_slice() {
            [] => self.constant(1.0),
            [(b, 1)] => *b,
            _ => self.intern(Node::Product(factors)),
        }
    }

    /// `k · monic`, the inverse of [`Arena::split_sign`].
    fn scaled(&mut self, k: f64, monic: Option<NodeId>) -> NodeId {
        match monic {
            None => self.constant(k),
            Some(m) => self.scale(m, k),
        }
    }

    pub fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        let (ka, ma) = self.split_sign(a);
        let (kb, mb) = self.split_sign(b);
        let k = ka * kb;
        if k == 0.0 {
            return self.constant(0.0);
        }
        let (Some(ma), Some(mb)) = (ma, mb) else {
            return self.scaled(k, ma.or(mb));
        };
        let (la, lb) = (self.linear(ma), self.linear(mb));
        let width =
            (la.0.len() + usize::from(la.1 != 0.0)) * (lb.0.len() + usize::from(lb.1 != 0.0));
        let offset = |l: &Linear| l.0.len() == 1 && l.1 != 0.0;
        if (width > 1 && width <= self.policy.expand_limit)
            || (self.policy.distribute_offsets && (offset(&la) || offset(&lb)))
        {
            return self.expand(la, lb, k);
        }
        let p = self.make_product([(ma, 1), (mb, 1)]);
        self.scale(p, k)
    }

    /// Distributes `k · (Σa)(Σb)`.
    fn expand(&mut self, (ta, ca): Linear, (tb, cb): Linear, k: f64) -> NodeId {
        let mut terms: BTreeMap<NodeId, f64> = BTreeMap::new();
        let mut constant = k * ca * cb;
        let mut push = |arena: &mut Arena, node: NodeId, c: f64| {
            let (kk, m) = arena.split_sign(node);
            match m {
                None => constant += c * kk,
                Some(m) => {
                    let (lt, lc) = arena.linear(m);
                    constant += c * kk * lc;
                    for (t, tc) in lt {
                        *terms.entry(t).or_insert(0.0) += c * kk * tc;
                    }
                }
            }
        };
        for (&x, &cx) in &ta {
            for (&y, &cy) in &tb {
                let p = self.make_product([(x, 1), (y, 1)]);
                push(self, p, k * cx * cy);
            }
            if cb != 0.0 {
                push(self, x, k * cx * cb);
            }
        }
        if ca != 0.0 {
            for (&y, &cy) in &tb {
                push(self, y, k * ca * cy);
            }
        }
        self.make_sum(terms, constant)
    }

    pub fn recip(&mut self, a: NodeId) -> NodeId {
        let (k, m) = self.split_sign(a);
        if k == 0.0 {
            self.invalid
                .get_or_insert_with(|| "division by a constant zero".to_string());
            return self.constant(0.0);
        }
        match m {
            None => self.constant(1.0 / k),
            Some(m) => {
                let p = self.make_product([(m, -1)]);
                self.scale(p, 1.0 / k)
            }
        }
    }

    pub fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        let r = self.recip(b);
        self.mul(a, r)
    }

    pub fn call(&mut self, func: Func, a: NodeId) -> NodeId {
        if let Some(c) = self.const_value(a) {
            let v = match func {
                Func::Sin => c.sin(),
                Func::Cos => c.cos(),
                Func::Sqrt => c.sqrt(),
                Func::Sign => sign(c),
                Func::Atan => c.atan(),
                Func::Keep => c,
            };
            return self.constant(v);
        }
        // A value already kept is a unit already. (An input is too, but kept it stays a unit
        // when a substitution replaces it by an expression.)
        if func == Func::Keep && matches!(self.node(a), Node::Call(Func::Keep, _)) {
            return a;
        }
        let (k, m) = self.split_sign(a);
        match (func, k, m) {
            // sin is odd and cos even: keep the argument's sign outside the call.
            (Func::Sin, -1.0, Some(m)) => {
                let s = self.intern(Node::Call(Func::Sin, m));
                self.neg(s)
            }
            (Func::Cos, -1.0, Some(m)) => self.intern(Node::Call(Func::Cos, m)),
            // atan and the identity are odd too.
            (Func::Atan | Func::Keep, -1.0, Some(m)) => {
                let s = self.intern(Node::Call(func, m));
                self.neg(s)
            }
            _ => self.intern(Node::Call(func, a)),
        }
    }

    /// `id` with the inputs of `values` replaced by their nodes, rebuilt through the same
    /// simplifying constructors (so a product or sum that the replacement makes constant folds).
    /// `memo` holds the nodes already rebuilt for these `values`; pass the same map for several
    /// outputs.
    pub fn substitute(
        &mut self,
        id: NodeId,
        values: &HashMap<u32, NodeId>,
        memo: &mut HashMap<NodeId, NodeId>,
    ) -> NodeId {
        if let Some(&s) = memo.get(&id) {
            return s;
        }
        let s = match self.node(id).clone() {
            Node::Const(_) => id,
            Node::Input(i) => values.get(&i).copied().unwrap_or(id),
            Node::Sum { terms, constant } => {
                let mut form: BTreeMap<NodeId, f64> = BTreeMap::new();
                let mut total = constant.get();
                for (t, c) in terms {
                    let st = self.substitute(t, values, memo);
                    let (lt, lc) = self.linear(st);
                    total += c.get() * lc;
                    for (u, k) in lt {
                        *form.entry(u).or_insert(0.0) += c.get() * k;
                    }
                }
                self.make_sum(form, total)
            }
            Node::Product(factors) => {
                // Through `mul` and `recip`, so that a factor replaced by a sum or a constant
                // keeps the product canonical (coefficients out, constants folded).
                let mut product = self.constant(1.0);
                for (base, exp) in factors {
                    let b = self.substitute(base, values, memo);
                    let b = if exp < 0 { self.recip(b) } else { b };
                    for _ in 0..exp.unsigned_abs() {
                        product = self.mul(product, b);
                    }
                }
                product
            }
            Node::Call(f, a) => {
                let a = self.substitute(a, values, memo);
                self.call(f, a)
            }
        };
        memo.insert(id, s);
        s
    }

    /// `∂id/∂x_wrt`, the exact derivative with respect to the input `wrt`, built through the same
    /// simplifying constructors, so it shares every subexpression with the primal (and the
    /// lowering's CSE spans both). `memo` holds the derivatives already built for this `wrt`;
    /// pass the same map for several outputs.
    pub fn derivative(
        &mut self,
        id: NodeId,
        wrt: u32,
        memo: &mut HashMap<NodeId, NodeId>,
    ) -> NodeId {
        let one = self.constant(1.0);
        self.tangent(id, &HashMap::from_iter([(wrt, one)]), memo)
    }

    /// `Σₓ ∂id/∂x · rates[x]`, the exact derivative of `id` along the direction `rates` (forward
    /// mode, one pass): with `rates` the time derivatives of the inputs it names, the time
    /// derivative of `id`. Inputs `rates` does not name are held constant. `memo` holds the
    /// tangents already built for these `rates`.
    pub fn tangent(
        &mut self,
        id: NodeId,
        rates: &HashMap<u32, NodeId>,
        memo: &mut HashMap<NodeId, NodeId>,
    ) -> NodeId {
        if let Some(&d) = memo.get(&id) {
            return d;
        }
        let d = match self.node(id).clone() {
            Node::Const(_) => self.constant(0.0),
            Node::Input(i) => match rates.get(&i) {
                Some(&rate) => rate,
                None => self.constant(0.0),
            },
            Node::Sum { terms, .. } => {
                let mut form: BTreeMap<NodeId, f64> = BTreeMap::new();
                let mut constant = 0.0;
                for (t, c) in terms {
                    let dt = self.tangent(t, rates, memo);
                    let (lt, lc) = self.linear(dt);
                    constant += c.get() * lc;
                    for (u, k) in lt {
                        *form.entry(u).or_insert(0.0) += c.get() * k;
                    }
                }
                self.make_sum(form, constant)
            }
            Node::Product(factors) => {
                // Σ_k e_k b_k^(e_k - 1) Π_{j≠k} b_j^(e_j) ∂b_k.
                let mut sum = self.constant(0.0);
                for (k, &(base, exp)) in factors.iter().enumerate() {
                    let db = self.tangent(base, rates, memo);
                    if self.const_value(db) == Some(0.0) {
                        continue;
                    }
                    let rest = self.cofactor(&factors, k);
                    let term = self.mul(rest, db);
                    sum = self.combine(sum, 1.0, term, f64::from(exp));
                }
                sum
            }
            Node::Call(f, a) => {
                let da = self.tangent(a, rates, memo);
                if self.const_value(da) == Some(0.0) {
                    da
                } else {
                    let outer = self.call_derivative(f, a);
                    self.mul(outer, da)
                }
            }
        };
        memo.insert(id, d);
        d
    }

    /// `f'(a)`, the derivative of the call `f(a)` with respect to its argument.
    fn call_derivative(&mut self, f: Func, a: NodeId) -> NodeId {
        match f {
            Func::Sin => self.call(Func::Cos, a),
            Func::Cos => {
                let s = self.call(Func::Sin, a);
                self.neg(s)
            }
            Func::Sqrt => {
                let r = self.call(Func::Sqrt, a);
                let two_r = self.scale(r, 2.0);
                self.recip(two_r)
            }
            // Zero wherever it is defined.
            Func::Sign => self.constant(0.0),
            Func::Keep => self.constant(1.0),
            // 1 / (1 + a²).
            Func::Atan => {
                let square = self.mul(a, a);
                let one = self.constant(1.0);
                let denominator = self.add(one, square);
                self.recip(denominator)
            }
        }
    }

    /// `Π_{j≠k} b_j^(e_j) · b_k^(e_k - 1)`: the product's derivative with respect to its `k`-th
    /// base, but for the exponent `e_k` that scales it.
    fn cofactor(&mut self, factors: &[(NodeId, i32)], k: usize) -> NodeId {
        let rest = factors
            .iter()
            .enumerate()
            .map(|(j, &(b, e))| (b, if j == k { e - 1 } else { e }));
        self.make_product(rest)
    }

    /// `∂id/∂x` for each input `x` of `wrt`, by reverse mode: one sweep from `id` back through
    /// the nodes it is built from, each node's adjoint the sum of its users' adjoints times
    /// their local partial derivatives, built through the same simplifying constructors.
    pub fn gradient(&mut self, id: NodeId, wrt: &[u32]) -> Vec<NodeId> {
        let mut reached = std::collections::BTreeSet::new();
        let mut stack = vec![id];
        while let Some(n) = stack.pop() {
            if reached.insert(n) {
                stack.extend(self.node(n).children());
            }
        }
        let mut parts: HashMap<NodeId, Vec<NodeId>> = HashMap::default();
        let one = self.constant(1.0);
        parts.insert(id, vec![one]);
        let mut at_inputs: HashMap<u32, NodeId> = HashMap::default();
        for &n in reached.iter().rev() {
            let Some(contributions) = parts.remove(&n) else {
                continue;
            };
            let adjoint = contributions
                .into_iter()
                .reduce(|sum, c| self.add(sum, c))
                .expect("one contribution at least");
            match self.node(n).clone() {
                Node::Const(_) => {}
                Node::Input(i) => {
                    at_inputs.insert(i, adjoint);
                }
                Node::Sum { terms, .. } => {
                    for (t, c) in terms {
                        let d = self.scale(adjoint, c.get());
                        parts.entry(t).or_default().push(d);
                    }
                }
                Node::Product(factors) => {
                    for (k, &(base, exp)) in factors.iter().enumerate() {
                        let rest = self.cofactor(&factors, k);
                        let local = self.mul(rest, adjoint);
                        let d = self.scale(local, f64::from(exp));
                        parts.entry(base).or_default().push(d);
                    }
                }
                Node::Call(f, a) => {
                    let outer = self.call_derivative(f, a);
                    if self.const_value(outer) == Some(0.0) {
                        continue;
                    }
                    let d = self.mul(outer, adjoint);
                    parts.entry(a).or_default().push(d);
                }
            }
        }
        wrt.iter()
            .map(|i| match at_inputs.get(i) {
                Some(&d) => d,
                None => self.constant(0.0),
            })
            .collect()
    }

    /// Renders a node as an infix expression (for tests and diagnostics).
    pub fn render(&self, id: NodeId, names: &dyn Fn(u32) -> String) -> String {
        match self.node(id) {
            Node::Const(c) => format!("{}", c.get()),
            Node::Input(i) => names(*i),
            Node::Call(f, a) => format!("{}({})", f.name(), self.render(*a, names)),
            Node::Product(fs) => fs
                .iter()
                .map(|&(b, e)| {
                    let inner = match self.node(b) {
                        Node::Sum { .. } => format!("({})", self.render(b, names)),
                        _ => self.render(b, names),
                    };
                    if e == 1 {
                        inner
                    } else {
                        format!("{inner}^{e}")
                    }
                })
                .collect::<Vec<_>>()
                .join("*"),
            Node::Sum { terms, constant } => {
                let mut out = String::new();
                for (i, &(t, c)) in terms.iter().enumerate() {
                    let c = c.get();
                    let body = self.render(t, names);
                    let (sign, mag) = if c < 0.0 { ("-", -c) } else { ("+", c) };
                    if i == 0 {
                        if sign == "-" {
                            out.push('-');
                        }
                    } else {
                        out.push_str(&format!(" {sign} "));
                    }
                    if mag == 1.0 {
                        out.push_str(&body);
                    } else {
                        out.push_str(&format!("{mag}*{body}"));
                    }
                }
                let c = constant.get();
                if c > 0.0 {
                    out.push_str(&format!(" + {c}"));
                } else if c < 0.0 {
                    out.push_str(&format!(" - {}", -c));
                }
                out
            }
        }
    }
}

/// A graph shared by the [`Expr`] handles that build it.
#[derive(Debug)]
pub struct Graph {
    arena: RefCell<Arena>,
}

impl Graph {
    pub fn new(policy: Policy) -> Self {
        Graph {
            arena: RefCell::new(Arena::new(policy)),
        }
    }

    pub fn constant(&self, value: f64) -> Expr<'_> {
        let id = self.arena.borrow_mut().constant(value);
        Expr { id, graph: self }
    }

    pub fn zero(&self) -> Expr<'_> {
        self.constant(0.0)
    }

    pub fn one(&self) -> Expr<'_> {
        self.constant(1.0)
    }

    pub fn input(&self, index: u32) -> Expr<'_> {
        let id = self.arena.borrow_mut().input(index);
        Expr { id, graph: self }
    }

    pub fn wrap(&self, id: NodeId) -> Expr<'_> {
        Expr { id, graph: self }
    }

    /// Marks the graph as one that cannot be emitted (a model error), keeping the first reason.
    pub fn invalidate(&self, reason: String) {
        self.arena.borrow_mut().invalid.get_or_insert(reason);
    }

    pub fn arena(&self) -> std::cell::Ref<'_, Arena> {
        self.arena.borrow()
    }

    /// `exprs` with each input `x` of `values` replaced by its value, sharing the work between
    /// them.
    ///
    /// # Panics
    /// If a replaced `x` is not an input node (a bug in the model).
    pub fn substitute<'g>(
        &'g self,
        exprs: &[Expr<'g>],
        values: &[(Expr<'g>, Expr<'g>)],
    ) -> Vec<Expr<'g>> {
        let values: HashMap<u32, NodeId> = values
            .iter()
            .map(|(x, v)| match *self.arena().node(x.id) {
                Node::Input(i) => (i, v.id),
                _ => panic!("only inputs are substituted"),
            })
            .collect();
        let mut memo = HashMap::default();
        exprs
            .iter()
            .map(|e| {
                let id = self.with(|a| a.substitute(e.id, &values, &mut memo));
                self.wrap(id)
            })
            .collect()
    }

    /// `∂e/∂x` for each of `exprs`, `x` an input of the graph, sharing the work between them.
    ///
    /// # Panics
    /// If `x` is not an input node (a bug in the model).
    pub fn derivatives<'g>(&'g self, exprs: &[Expr<'g>], x: Expr<'g>) -> Vec<Expr<'g>> {
        let Node::Input(wrt) = *self.arena().node(x.id) else {
            panic!("derivatives are taken with respect to an input");
        };
        let mut memo = HashMap::default();
        exprs
            .iter()
            .map(|e| {
                let id = self.with(|a| a.derivative(e.id, wrt, &mut memo));
                self.wrap(id)
            })
            .collect()
    }

    /// `∂f/∂x` row-major (row `i` for `f[i]`, column `j` for `xs[j]`), by the mode the
    /// policy names ([`Policy::reverse_mode`]).
    ///
    /// # Panics
    /// If an `x` is not an input node (a bug in the model).
    pub fn jacobian<'g>(&'g self, f: &[Expr<'g>], xs: &[Expr<'g>]) -> Vec<Expr<'g>> {
        let reverse = {
            let mut arena = self.arena.borrow_mut();
            arena.took_jacobian = true;
            arena.policy.reverse_mode
        };
        if reverse {
            return self.gradients(f, xs);
        }
        let columns: Vec<Vec<Expr<'g>>> = xs.iter().map(|&x| self.derivatives(f, x)).collect();
        (0..f.len())
            .flat_map(|i| columns.iter().map(move |c| c[i]))
            .collect()
    }

    /// `∂e/∂x` row-major (row `i` for `exprs[i]`, column `j` for `xs[j]`), by reverse mode.
    ///
    /// # Panics
    /// If an `x` is not an input node (a bug in the model).
    pub fn gradients<'g>(&'g self, exprs: &[Expr<'g>], xs: &[Expr<'g>]) -> Vec<Expr<'g>> {
        let wrt: Vec<u32> = xs
            .iter()
            .map(|x| match *self.arena().node(x.id) {
                Node::Input(i) => i,
                _ => panic!("derivatives are taken with respect to an input"),
            })
            .collect();
        exprs
            .iter()
            .flat_map(|e| self.with(|a| a.gradient(e.id, &wrt)))
            .map(|id| self.wrap(id))
            .collect()
    }

    /// `Σₓ ∂e/∂x · rate(x)` for each of `exprs`: their exact derivatives along `rates`, pairs of
    /// an input `x` and its rate (for instance the time derivatives of the inputs, which makes
    /// these the time derivatives of `exprs`); the inputs not named are held constant.
    ///
    /// # Panics
    /// If a named `x` is not an input node (a bug in the model).
    pub fn tangents<'g>(
        &'g self,
        exprs: &[Expr<'g>],
        rates: &[(Expr<'g>, Expr<'g>)],
    ) -> Vec<Expr<'g>> {
        let rates: HashMap<u32, NodeId> = rates
            .iter()
            .map(|(x, v)| match *self.arena().node(x.id) {
                Node::Input(i) => (i, v.id),
                _ => panic!("tangents are taken along inputs"),
            })
            .collect();
        let mut memo = HashMap::default();
        exprs
            .iter()
            .map(|e| {
                let id = self.with(|a| a.tangent(e.id, &rates, &mut memo));
                self.wrap(id)
            })
            .collect()
    }

    pub fn into_arena(self) -> Arena {
        self.arena.into_inner()
    }

    fn with<R>(&self, f: impl FnOnce(&mut Arena) -> R) -> R {
        f(&mut self.arena.borrow_mut())
    }
}

/// A handle on a node, with arithmetic operators that build simplified nodes.
#[derive(Clone, Copy, Debug)]
pub struct Expr<'g> {
    pub id: NodeId,
    graph: &'g Graph,
}

impl<'g> Expr<'g> {
    pub fn graph(self) -> &'g Graph {
        self.graph
    }
    pub fn sin(self) -> Self {
        self.wrap(self.graph.with(|a| a.call(Func::Sin, self.id)))
    }
    pub fn cos(self) -> Self {
        self.wrap(self.graph.with(|a| a.call(Func::Cos, self.id)))
    }
    pub fn sqrt(self) -> Self {
        self.wrap(self.graph.with(|a| a.call(Func::Sqrt, self.id)))
    }
    pub fn sign(self) -> Self {
        self.wrap(self.graph.with(|a| a.call(Func::Sign, self.id)))
    }
    pub fn atan(self) -> Self {
        self.wrap(self.graph.with(|a| a.call(Func::Atan, self.id)))
    }
    /// The same value as a unit ([`Func::Keep`]): computed once, used whole.
    pub fn keep(self) -> Self {
        self.wrap(self.graph.with(|a| a.call(Func::Keep, self.id)))
    }
    /// The same value, kept as a unit ([`Expr::keep`]) where the policy keeps the `offer` it
    /// belongs to ([`Policy::kept_offers`]): for values whose keeping pays in some kernels and
    /// not in others. One offer names a group of values kept or folded together.
    pub fn keep_where_cheaper(self, offer: &'static str) -> Self {
        let keep = self.graph.with(|a| {
            let k = match a.offers.iter().position(|&o| o == offer) {
                Some(k) => k,
                None => {
                    a.offers.push(offer);
                    a.offers.len() - 1
                }
            };
            k < 32 && a.policy.kept_offers & (1 << k) != 0
        });
        if keep {
            self.keep()
        } else {
            self
        }
    }
    pub fn recip(self) -> Self {
        self.wrap(self.graph.with(|a| a.recip(self.id)))
    }
    pub fn as_const(self) -> Option<f64> {
        self.graph.arena().const_value(self.id)
    }
    fn wrap(self, id: NodeId) -> Self {
        Expr {
            id,
            graph: self.graph,
        }
    }
    fn lift(self, value: f64) -> Self {
        self.graph.constant(value)
    }
    /// Refuses to combine nodes of two graphs: their ids index different arenas, so mixing them
    /// would silently build a wrong expression.
    fn same_graph(self, other: Self) {
        assert!(
            std::ptr::eq(self.graph, other.graph),
            "an expression combines nodes of two different graphs (a bug in the model)"
        );
    }
}

macro_rules! binary_ops {
    ($($trait:ident $method:ident $arena:ident;)*) => {$(
        impl<'g> $trait for Expr<'g> {
            type Output = Expr<'g>;
            fn $method(self, rhs: Self) -> Self {
                self.same_graph(rhs);
                self.wrap(self.graph.with(|a| a.$arena(self.id, rhs.id)))
            }
        }
        impl<'g> $trait<f64> for Expr<'g> {
            type Output = Expr<'g>;
            fn $method(self, rhs: f64) -> Self {
                let rhs = self.lift(rhs);
                self.$method(rhs)
            }
        }
        impl<'g> $trait<Expr<'g>> for f64 {
            type Output = Expr<'g>;
            fn $method(self, rhs: Expr<'g>) -> Expr<'g> {
                rhs.lift(self).$method(rhs)
            }
        }
    )*};
}

binary_ops! {
    Add add add;
    Sub sub sub;
    Mul mul mul;
    Div div div;
}

impl<'g> Neg for Expr<'g> {
    type Output = Expr<'g>;
    fn neg(self) -> Self {
        self.wrap(self.graph.with(|a| a.neg(self.id)))
    }
}

impl<'g> std::iter::Sum for Expr<'g> {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.reduce(|a, b| a + b)
            .expect("sum of an empty iterator of expressions")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(i: u32) -> String {
        ["x", "y", "z", "L", "w"][i as usize].to_string()
    }

    /// One-line rule tests in the manner of egg's `test_fn!`.
    macro_rules! simplify_test {
        ($name:ident, $policy:expr, |$x:ident, $y:ident, $z:ident, $l:ident| $e:expr => $want:expr) => {
            #[test]
            fn $name() {
                let g = Graph::new($policy);
                let ($x, $y, $z, $l) = (g.input(0), g.input(1), g.input(2), g.input(3));
                let got = $e;
                assert_eq!(g.arena().render(got.id, &names), $want);
            }
        };
    }

    const FLAT: Policy = Policy::FLAT;
    const EXPAND: Policy = Policy {
        expand_limit: 64,
        ..Policy::FLAT
    };

    simplify_test!(x_times_one, FLAT, |x, _y, _z, _l| x * 1.0 => "x");
    simplify_test!(x_times_zero, FLAT, |x, _y, _z, _l| x * 0.0 => "0");
    simplify_test!(x_plus_zero, FLAT, |x, _y, _z, _l| x + 0.0 => "x");
    simplify_test!(constants_fold, FLAT, |_x, _y, _z, _l| {
        let g = _x.graph();
        g.constant(2.0) * g.constant(3.0) + 1.0
    } => "7");
    simplify_test!(chapter_cancellation, FLAT, |_x, y, _z, l| (y - l) - (y + l) => "-2*L");
    simplify_test!(x_minus_x, FLAT, |x, _y, _z, _l| x - x => "0");
    simplify_test!(product_commutes, FLAT, |x, y, _z, _l| x * y - y * x => "0");
    simplify_test!(quotient_cancels, FLAT, |x, y, _z, _l| x * y / y => "x");
    simplify_test!(sign_floats_up, FLAT, |x, y, _z, _l| (-x) * y + x * y => "0");
    simplify_test!(sum_sign_normalised, FLAT, |x, y, z, _l| (x - y) * z + (y - x) * z => "0");
    simplify_test!(reciprocal_sign, FLAT, |x, y, _z, _l| 1.0 / (x - y) + 1.0 / (y - x) => "0");
    simplify_test!(sin_is_odd, FLAT, |x, _y, _z, _l| (-x).sin() + x.sin() => "0");
    simplify_test!(cos_is_even, FLAT, |x, _y, _z, _l| (-x).cos() - x.cos() => "0");
    simplify_test!(atan_is_odd, FLAT, |x, _y, _z, _l| (-x).atan() + x.atan() => "0");
    simplify_test!(square, FLAT, |x, _y, _z, _l| x * x => "x^2");
    simplify_test!(no_expansion_when_flat, FLAT, |x, y, z, _l| (x + y) * z => "z*(x + y)");
    simplify_test!(expansion_cancels, EXPAND, |x, y, z, _l| (x + y) * z - x * z => "y*z");

    /// `∂f/∂x` rendered, for the one-line derivative tests.
    fn derivative_of(policy: Policy, f: impl for<'g> Fn(&[Expr<'g>]) -> Expr<'g>) -> String {
        let g = Graph::new(policy);
        let v = [g.input(0), g.input(1), g.input(2), g.input(3)];
        let e = f(&v);
        let d = g.derivatives(&[e], v[0])[0];
        let rendered = g.arena().render(d.id, &names);
        rendered
    }

    #[test]
    fn derivatives_of_polynomials_products_and_calls() {
        assert_eq!(
            derivative_of(EXPAND, |v| v[0] * v[0] * v[1] + v[0] * 3.0),
            "2*x*y + 3"
        );
        assert_eq!(derivative_of(FLAT, |v| v[1] * v[2] + 4.0), "0");
        assert_eq!(derivative_of(FLAT, |v| (v[0] * v[1]).sin()), "y*cos(x*y)");
        assert_eq!(derivative_of(FLAT, |v| v[0].cos()), "-sin(x)");
        assert_eq!(derivative_of(FLAT, |v| v[1] / v[0]), "-x^-2*y");
    }

    type Build = for<'g> fn(&[Expr<'g>]) -> Expr<'g>;

    /// Expressions of four inputs with every node kind and call the derivatives meet.
    const CASES: [Build; 7] = [
        |v| (v[0] / v[2]).atan() * v[1],
        |v| v[0] / (v[0] + v[1]),
        |v| (v[0] * v[1]).sin() * v[0].cos() + v[2] / (v[0] * v[0] + 1.0),
        |v| (v[0] * v[0] + v[1]).sqrt() * v[3],
        |v| (v[0] - v[1]) * (v[0] + v[2]) * (v[0] * 2.0 - v[3]),
        |v| (v[1] * v[0].sin() + v[0]).recip(),
        |v| (v[0] * v[1] + v[2]).keep() * (v[0] * v[1] + v[2]).keep() * v[3] + v[1].sign() * v[0],
    ];
    const POINT: [f64; 4] = [0.7, -0.4, 1.3, 0.25];

    /// `∂f/∂x_wrt` of `f` at [`POINT`] by central differences.
    fn central_difference(program: &crate::lower::Program, wrt: usize) -> f64 {
        let h = 1e-6;
        let (mut up, mut down) = (POINT, POINT);
        up[wrt] += h;
        down[wrt] -= h;
        (program.eval(&up)[0] - program.eval(&down)[0]) / (2.0 * h)
    }

    /// Reverse mode's gradient against forward mode's derivatives and central differences:
    /// one sweep from the output gives every input's derivative.
    #[test]
    fn gradients_match_forward_mode_and_finite_differences() {
        use crate::lower::{factor, lower};
        for (n, f) in CASES.into_iter().enumerate() {
            let g = Graph::new(FLAT);
            let ids: Vec<NodeId> = {
                let v = [g.input(0), g.input(1), g.input(2), g.input(3)];
                let e = f(&v);
                let forward = (0..4).map(|k| g.derivatives(&[e], v[k])[0]);
                let reverse = g.gradients(&[e], &v);
                [e].into_iter()
                    .chain(forward)
                    .chain(reverse)
                    .map(|x| x.id)
                    .collect()
            };
            let mut arena = g.into_arena();
            let outs = factor(&mut arena, &ids);
            let program = lower(&arena, &outs, true);
            let values = program.eval(&POINT);
            for wrt in 0..4 {
                let (forward, reverse) = (values[1 + wrt], values[5 + wrt]);
                let fd = central_difference(&program, wrt);
                assert!(
                    (forward - reverse).abs() <= 1e-14 * forward.abs().max(1.0),
                    "case {n}, ∂/∂x{wrt}: forward {forward} vs reverse {reverse}"
                );
                assert!(
                    (reverse - fd).abs() < 1e-8 * reverse.abs().max(1.0),
                    "case {n}, ∂/∂x{wrt}: {reverse} vs {fd}"
                );
            }
        }
    }

    /// An offer is kept whole where its bit is set, bits numbered in the order the offers are
    /// first met, and an offer met again is the same bit; the value is the same either way.
    #[test]
    fn offers_are_kept_where_their_bit_is_set() {
        for kept_offers in 0..4u32 {
            let g = Graph::new(Policy {
                kept_offers,
                ..FLAT
            });
            let (x, y) = (g.input(0), g.input(1));
            let a = (x + y).keep_where_cheaper("a");
            let b = (x * y).keep_where_cheaper("b");
            let a_again = (x - y).keep_where_cheaper("a");
            let kept = |e: Expr<'_>| matches!(g.arena().node(e.id), Node::Call(Func::Keep, _));
            assert_eq!(kept(a), kept_offers & 1 != 0);
            assert_eq!(kept(b), kept_offers & 2 != 0);
            assert_eq!(kept(a_again), kept_offers & 1 != 0);
            assert_eq!(g.arena().offers(), ["a", "b"]);
        }
    }

    /// Exact derivatives against central differences of the evaluated expression.
    #[test]
    fn derivatives_match_finite_differences() {
        use crate::lower::{factor, lower};
        for (n, f) in CASES.into_iter().enumerate() {
            for wrt in 0..4 {
                let g = Graph::new(FLAT);
                let ids = {
                    let v = [g.input(0), g.input(1), g.input(2), g.input(3)];
                    let e = f(&v);
                    let d = g.derivatives(&[e], v[wrt])[0];
                    [e.id, d.id]
                };
                let mut arena = g.into_arena();
                let outs = factor(&mut arena, &ids);
                let program = lower(&arena, &outs, true);
                let exact = program.eval(&POINT)[1];
                let fd = central_difference(&program, wrt);
                assert!(
                    (exact - fd).abs() < 1e-8 * exact.abs().max(1.0),
                    "case {n}, ∂/∂x{wrt}: {exact} vs {fd}"
                );
            }
        }
    }

    /// A tangent is the derivative along a line: `d/dt f(x + t r)` at `t = 0`, and twice
    /// applied, with the rates' own rates named, the second derivative along a curve.
    #[test]
    fn tangents_are_derivatives_along_a_direction() {
        use crate::lower::{factor, lower};
        let point = [0.7, -0.4, 1.3];
        let (rate, rate_of_rate) = ([0.3, 1.1, -0.8], [0.5, -0.2, 0.9]);
        let g = Graph::new(FLAT);
        let ids = {
            let x = [g.input(0), g.input(1), g.input(2)];
            let xd = [g.input(3), g.input(4), g.input(5)];
            let xdd = [g.input(6), g.input(7), g.input(8)];
            let f = (x[0] * x[1]).sin() * x[2].sqrt() + x[0] / (x[1] * x[1] + x[2]);
            let first: Vec<_> = (0..3).map(|k| (x[k], xd[k])).collect();
            let second: Vec<_> = (0..3)
                .flat_map(|k| [(x[k], xd[k]), (xd[k], xdd[k])])
                .collect();
            let fd = g.tangents(&[f], &first)[0];
            let fdd = g.tangents(&[fd], &second)[0];
            [f.id, fd.id, fdd.id]
        };
        let mut arena = g.into_arena();
        let outs = factor(&mut arena, &ids);
        let program = lower(&arena, &outs, true);
        // Along x(t) = x + t r + t²/2 r', f(x(t)) has the first and second derivatives above.
        let along = |t: f64| {
            let mut inputs = vec![0.0; 9];
            for k in 0..3 {
                inputs[k] = point[k] + t * rate[k] + 0.5 * t * t * rate_of_rate[k];
                inputs[3 + k] = rate[k];
                inputs[6 + k] = rate_of_rate[k];
            }
            program.eval(&inputs)
        };
        let h = 1e-4;
        let (up, mid, down) = (along(h)[0], along(0.0), along(-h)[0]);
        let first = (up - down) / (2.0 * h);
        let second = (up - 2.0 * mid[0] + down) / (h * h);
        assert!((mid[1] - first).abs() < 1e-7, "{} vs {first}", mid[1]);
        assert!((mid[2] - second).abs() < 1e-5, "{} vs {second}", mid[2]);
    }

    #[test]
    fn substitution_rebuilds_through_the_simplifier() {
        let g = Graph::new(EXPAND);
        let (x, y, z) = (g.input(0), g.input(1), g.input(2));
        let e = x * y + (x * 2.0).sin() / y;
        let [s] = g.substitute(&[e], &[(y, g.constant(2.0)), (x, z + 1.0)])[..] else {
            unreachable!()
        };
        assert_eq!(g.arena().render(s.id, &names), "2*z + 0.5*sin(2*z + 2) + 2");
        // Substituting an input by itself changes nothing.
        assert_eq!(g.substitute(&[e], &[(x, x)])[0].id, e.id);
    }

    #[test]
    fn a_derivative_shares_the_primal() {
        let g = Graph::new(FLAT);
        let (x, y) = (g.input(0), g.input(1));
        let inner = x * y + 1.0;
        let e = inner.sin();
        let before = g.arena().len();
        let d = g.derivatives(&[e], x)[0];
        // cos(xy + 1) and y are new or shared; x·y + 1 is not built again.
        assert!(g.arena().len() - before <= 3);
        assert_eq!(g.arena().render(d.id, &names), "y*cos(x*y + 1)");
    }

    #[test]
    fn hash_consing_is_cse() {
        let g = Graph::new(FLAT);
        let (x, y) = (g.input(0), g.input(1));
        let a = (x + y) * x;
        let b = x * (y + x);
        assert_eq!(a.id, b.id);
    }

    #[test]
    fn division_by_zero_constant_is_flagged() {
        let g = Graph::new(FLAT);
        let x = g.input(0);
        let _ = x / 0.0;
        assert!(g.arena().invalid().is_some());
    }
}
