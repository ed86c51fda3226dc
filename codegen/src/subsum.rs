//! Common sub-sums: the pairs of terms several sums share, computed once.
//!
//! Sums are canonical flat maps in the DAG, so `a + b + c` and `a + b - d` share no node although
//! both need `a + b`. Before lowering, this pass repeatedly takes the pair of items (terms, or
//! sub-sums already extracted) that the most sums hold with coefficients of equal magnitude,
//! `k·a ± k·b`, makes it one sub-sum `a ± b`, and puts that in their place. Each extraction of a
//! pair held by `n` sums saves `n - 1` additions and costs nothing else, so the pass never makes
//! a program dearer.

use crate::dag::{Arena, Node, NodeId};
use rustc_hash::FxHashMap as HashMap;
use std::cmp::Reverse;
use std::collections::{BTreeMap, BTreeSet, BinaryHeap};

/// Sums wider than this offer no pairs (a sum of `n` items holds `n²/2` of them); they still
/// use the sub-sums narrower sums make.
const WIDEST: usize = 96;

/// An addend of a planned sum.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Item {
    /// A term of the DAG's sum.
    Term(NodeId),
    /// The extracted sub-sum with this index in [`Plan::subsums`].
    Sub(usize),
}

/// `first + second` (or `first - second` when `negative`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubSum {
    pub first: Item,
    pub second: Item,
    pub negative: bool,
}

/// How to add up every sum: its items with their coefficients, and the sub-sums they use.
#[derive(Clone, Debug, Default)]
pub struct Plan {
    pub sums: HashMap<NodeId, Vec<(Item, f64)>>,
    pub subsums: Vec<SubSum>,
}

/// A pair of items with coefficients of equal magnitude, and whether they have opposite signs.
type Key = (Item, Item, bool);

fn pairs(items: &[(Item, f64)]) -> Vec<Key> {
    let mut out = Vec::new();
    if items.len() > WIDEST {
        return out;
    }
    for (i, &(a, ca)) in items.iter().enumerate() {
        for &(b, cb) in &items[i + 1..] {
            if ca.abs().to_bits() == cb.abs().to_bits() {
                let (x, y) = if a < b { (a, b) } else { (b, a) };
                out.push((x, y, (ca < 0.0) != (cb < 0.0)));
            }
        }
    }
    out
}

/// The plan that shares nothing: every sum adds its own terms.
pub fn unshared<'a>(arena: &Arena, nodes: impl IntoIterator<Item = &'a NodeId>) -> Plan {
    let sums = nodes
        .into_iter()
        .filter_map(|&id| match arena.node(id) {
            Node::Sum { terms, .. } => Some((
                id,
                terms
                    .iter()
                    .map(|&(t, c)| (Item::Term(t), c.get()))
                    .collect(),
            )),
            _ => None,
        })
        .collect();
    Plan {
        sums,
        subsums: Vec::new(),
    }
}

/// Plans the sums among `nodes` (the nodes a program needs).
pub fn plan<'a>(arena: &Arena, nodes: impl IntoIterator<Item = &'a NodeId>) -> Plan {
    let mut ids: Vec<NodeId> = nodes
        .into_iter()
        .copied()
        .filter(|&id| matches!(arena.node(id), Node::Sum { .. }))
        .collect();
    ids.sort();
    let mut items: Vec<Vec<(Item, f64)>> = ids
        .iter()
        .map(|&id| match arena.node(id) {
            Node::Sum { terms, .. } => terms
                .iter()
                .map(|&(t, c)| (Item::Term(t), c.get()))
                .collect(),
            _ => unreachable!("filtered to sums"),
        })
        .collect();
    // Which sums hold each pair.
    let mut holders: HashMap<Key, BTreeSet<usize>> = HashMap::default();
    for (s, list) in items.iter().enumerate() {
        for key in pairs(list) {
            holders.entry(key).or_default().insert(s);
        }
    }
    // The pairs by how many sums hold them, largest first, ties to the smallest key (a
    // deterministic plan); an entry whose count has changed since is skipped when it surfaces.
    let mut queue: BinaryHeap<(usize, Reverse<Key>)> = holders
        .iter()
        .filter(|(_, h)| h.len() >= 2)
        .map(|(&k, h)| (h.len(), Reverse(k)))
        .collect();
    let mut subsums = Vec::new();
    while let Some((count, Reverse(key))) = queue.pop() {
        let current = holders.get(&key).map_or(0, BTreeSet::len);
        if current != count {
            if current >= 2 {
                queue.push((current, Reverse(key)));
            }
            continue;
        }
        let (mut a, mut b, negative) = key;
        let sums = holders[&key].clone();
        // A difference is oriented as most of its sums use it (`b - a` if most hold `-a + b`),
        // so that a sum left holding it alone needs no negation.
        if negative {
            let coefficient = |s: usize, item: Item| {
                items[s]
                    .iter()
                    .find(|(i, _)| *i == item)
                    .map_or(0.0, |&(_, c)| c)
            };
            let flipped = sums.iter().filter(|&&s| coefficient(s, a) < 0.0).count();
            if 2 * flipped > sums.len() {
                std::mem::swap(&mut a, &mut b);
            }
        }
        let sub = Item::Sub(subsums.len());
        subsums.push(SubSum {
            first: a,
            second: b,
            negative,
        });
        for s in sums {
            for key in pairs(&items[s]) {
                if let Some(h) = holders.get_mut(&key) {
                    h.remove(&s);
                    if h.is_empty() {
                        holders.remove(&key);
                    }
                }
            }
            let list = &mut items[s];
            let ca = list
                .iter()
                .find(|(i, _)| *i == a)
                .map(|&(_, c)| c)
                .expect("a holder");
            list.retain(|(i, _)| *i != a && *i != b);
            // `ca·a + cb·b = ca·(a ± b)`.
            list.push((sub, ca));
            for key in pairs(list) {
                let h = holders.entry(key).or_default();
                h.insert(s);
                if h.len() >= 2 {
                    queue.push((h.len(), Reverse(key)));
                }
            }
        }
    }
    let sums = ids.into_iter().zip(items).collect::<BTreeMap<_, _>>();
    Plan {
        sums: sums.into_iter().collect(),
        subsums,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dag::{Graph, Policy};

    #[test]
    fn a_pair_two_sums_share_is_extracted_once() {
        let g = Graph::new(Policy::default());
        let (a, b, c, d) = (g.input(0), g.input(1), g.input(2), g.input(3));
        let s1 = a + b + c;
        let s2 = a + b - d;
        let s3 = a - b + d;
        let ids = [s1.id, s2.id, s3.id];
        let arena = g.into_arena();
        let p = plan(&arena, &ids);
        assert_eq!(p.subsums.len(), 1, "{:?}", p.subsums);
        let sub = p.subsums[0];
        assert!(!sub.negative, "a + b, shared by the first two");
        assert_eq!(p.sums[&ids[0]].len(), 2);
        assert_eq!(p.sums[&ids[2]].len(), 3, "a - b is another pair");
    }
}
