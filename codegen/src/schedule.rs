//! Orders a program's instructions for compilers that keep the order they are given: the same
//! instructions, each computing the same value (so the outputs are equal to the bit), in an
//! order that starts the long dependency chains first.
//!
//! Lowering emits a value where the walk from the outputs first needs it, so the chain that
//! bounds a kernel's time (the sine-cosine pairs, the rotation, the divisions, the forces) is
//! spread over the whole program and reaches the core's instruction window late. LLVM
//! reschedules before register allocation and gains nothing from this (the Rust kernels keep
//! the lowering's order); GCC on x86 does not (its first scheduling pass is off there), so the
//! order of a C kernel is the order it runs in. [`schedule`] is a list scheduler on a model of
//! an out-of-order core: each cycle it issues up to [`ISSUE_WIDTH`] instructions whose
//! operands are ready, the one with the longest latency path to an output first, and while
//! [`LIVE_LIMIT`] values are alive it prefers instructions that end lives.

use crate::dag::Func;
use crate::lower::{Instr, Operand, Program};

/// Instructions issued per modelled cycle: the floating-point pipes of a recent x86 or Arm core
/// (two for multiplications, two for additions) less the one that loads and stores share.
pub const ISSUE_WIDTH: usize = 3;

/// The most values the scheduler keeps alive before it prefers ending lives to the critical
/// path: the 16 vector registers of x86-64 less two for the compiler's own temporaries.
pub const LIVE_LIMIT: usize = 14;

/// Latencies in cycles (Zen 3, Zen 4, Golden Cove within a cycle or two); only their
/// proportions matter.
fn latency(instr: &Instr) -> u32 {
    match instr {
        Instr::Add(..) | Instr::Sub(..) | Instr::Mul(..) => 3,
        Instr::Neg(..) => 1,
        Instr::Div(..) => 13,
        Instr::Call(Func::Sign, _) => 2,
        Instr::Call(Func::Sqrt, _) => 20,
        // Inline polynomials: about ten dependent multiplications and additions.
        Instr::Call(..) | Instr::SinCos(_) => 30,
        Instr::PairedCos(_) => 0,
    }
}

/// The temporaries an instruction reads, each once. A [`Instr::PairedCos`] reads none: its
/// [`Instr::SinCos`] computes it and it is scheduled with that one.
fn temps_read(instr: &Instr) -> Vec<usize> {
    if let Instr::PairedCos(_) = instr {
        return Vec::new();
    }
    let mut temps: Vec<usize> = instr
        .operands()
        .into_iter()
        .filter_map(|o| match o {
            Operand::Temp(t) => Some(t as usize),
            _ => None,
        })
        .collect();
    temps.sort_unstable();
    temps.dedup();
    temps
}

/// The program with its instructions reordered (and renumbered) by [`schedule_order`].
pub fn schedule(program: &Program) -> Program {
    let order = schedule_order(program);
    let map = renumbering(&order);
    let instrs = order
        .iter()
        .map(|&old| program.instrs[old].map_operands(&map))
        .collect();
    let scheduled = Program {
        instrs,
        outputs: program.outputs.iter().map(|&o| map(o)).collect(),
    };
    debug_assert_eq!(
        scheduled.verify(),
        Ok(()),
        "the scheduler breaks an invariant"
    );
    scheduled
}

/// The operands of a program reordered as `order` says (`order[new] = old`): each temporary
/// takes its new number, inputs and constants stay.
pub fn renumbering(order: &[usize]) -> impl Fn(Operand) -> Operand {
    let mut new_of = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        new_of[old] = new as u32;
    }
    move |o| match o {
        Operand::Temp(t) => Operand::Temp(new_of[t as usize]),
        other => other,
    }
}

/// The order (old indices) in which [`schedule`] puts the instructions: a topological order in
/// which every [`Instr::PairedCos`] still follows its [`Instr::SinCos`].
pub fn schedule_order(program: &Program) -> Vec<usize> {
    let instrs = &program.instrs;
    let n = instrs.len();
    let reads: Vec<Vec<usize>> = instrs.iter().map(temps_read).collect();
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, temps) in reads.iter().enumerate() {
        for &t in temps {
            users[t].push(i);
        }
    }
    // Uses not yet scheduled; an output is read at the very end, so it lives until then.
    let mut uses_left: Vec<usize> = users.iter().map(Vec::len).collect();
    for &o in &program.outputs {
        if let Operand::Temp(t) = o {
            uses_left[t as usize] += 1;
        }
    }
    // The lowering's order is topological: heights come out of one sweep backwards.
    let mut height = vec![0u32; n];
    for i in (0..n).rev() {
        let mut below = users[i].iter().map(|&u| height[u]).max().unwrap_or(0);
        if matches!(instrs[i], Instr::SinCos(_)) {
            below = below.max(height[i + 1]);
        }
        height[i] = latency(&instrs[i]) + below;
    }
    let is_paired_cos = |i: usize| matches!(instrs[i], Instr::PairedCos(_));
    let mut operands_left: Vec<usize> = reads.iter().map(Vec::len).collect();
    let mut ready: Vec<usize> = (0..n)
        .filter(|&i| operands_left[i] == 0 && !is_paired_cos(i))
        .collect();
    let mut done_at = vec![0u32; n];
    let mut order = Vec::with_capacity(n);
    let (mut live, mut cycle, mut issued) = (0usize, 0u32, 0usize);
    while !ready.is_empty() {
        let operands_done = |i: usize| reads[i].iter().map(|&t| done_at[t]).max().unwrap_or(0);
        if issued == ISSUE_WIDTH {
            cycle += 1;
            issued = 0;
        }
        let soonest = ready.iter().map(|&i| operands_done(i)).min().unwrap_or(0);
        if soonest > cycle {
            cycle = soonest;
            issued = 0;
        }
        let crowded = live >= LIVE_LIMIT;
        // Net change in live values: the lives it ends, less the one it starts.
        let ends = |i: usize| reads[i].iter().filter(|&&t| uses_left[t] == 1).count() as i64 - 1;
        let (k, &i) = ready
            .iter()
            .enumerate()
            .filter(|&(_, &i)| crowded || operands_done(i) <= cycle)
            .max_by_key(|&(_, &i)| {
                let (h, e, first) = (i64::from(height[i]), ends(i), -(i as i64));
                if crowded {
                    (e, h, first)
                } else {
                    (h, e, first)
                }
            })
            .expect("an instruction is ready by the soonest cycle");
        ready.swap_remove(k);
        issued += 1;
        done_at[i] = cycle.max(operands_done(i)) + latency(&instrs[i]);
        let mut scheduled = vec![i];
        if matches!(instrs[i], Instr::SinCos(_)) {
            done_at[i + 1] = done_at[i];
            scheduled.push(i + 1);
        }
        for &s in &scheduled {
            order.push(s);
            for &t in &reads[s] {
                uses_left[t] -= 1;
                if uses_left[t] == 0 {
                    live -= 1;
                }
            }
            if uses_left[s] > 0 {
                live += 1;
            }
            for &u in &users[s] {
                operands_left[u] -= 1;
                if operands_left[u] == 0 {
                    ready.push(u);
                }
            }
        }
    }
    debug_assert_eq!(order.len(), n, "every instruction is scheduled once");
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dag::{Graph, Policy};
    use crate::lower::{factor, lower};

    fn program(build: impl for<'g> Fn(&'g Graph) -> Vec<crate::dag::NodeId>) -> Program {
        let g = Graph::new(Policy::FLAT);
        let outs = build(&g);
        let mut arena = g.into_arena();
        let outs = factor(&mut arena, &outs);
        lower(&arena, &outs, true)
    }

    /// Every operand is computed before it is read, each `PairedCos` right after its `SinCos`.
    fn assert_topological(p: &Program) {
        for (i, instr) in p.instrs.iter().enumerate() {
            for o in instr.operands() {
                if let Operand::Temp(t) = o {
                    assert!((t as usize) < i, "t{i} reads t{t} before it is computed");
                }
            }
            if let Instr::PairedCos(a) = instr {
                assert_eq!(p.instrs[i - 1], Instr::SinCos(*a), "t{i}'s pair");
            }
        }
    }

    #[test]
    fn same_instructions_same_outputs_to_the_bit() {
        let p = program(|g| {
            let v: Vec<_> = (0..4).map(|i| g.input(i)).collect();
            let (s, c) = (v[0].sin(), v[0].cos());
            let d = (v[1] * c - v[2] * s) / (v[3] * v[3] + 1.0);
            vec![
                (d * s + v[1]).id,
                (d * c - v[2] * v[3]).id,
                (v[1] * v[2] + v[3]).id,
            ]
        });
        let mut order = schedule_order(&p);
        assert_ne!(
            order,
            (0..p.instrs.len()).collect::<Vec<_>>(),
            "the order changed"
        );
        order.sort_unstable();
        assert_eq!(
            order,
            (0..p.instrs.len()).collect::<Vec<_>>(),
            "a permutation"
        );
        let scheduled = schedule(&p);
        assert_topological(&scheduled);
        assert_eq!(scheduled.count(), p.count());
        for x in [[0.3, -1.2, 2.5, 0.7], [1.1, 0.0, -3.0, 4.0]] {
            let (e, f) = (p.eval(&x), scheduled.eval(&x));
            assert!(e.iter().zip(&f).all(|(e, f)| e.to_bits() == f.to_bits()));
        }
    }

    #[test]
    fn the_long_chain_starts_first() {
        // out0 = x / y (a division, the longest latency), out1 = a chain of additions that
        // lowering reaches first.
        let p = program(|g| {
            let v: Vec<_> = (0..4).map(|i| g.input(i)).collect();
            vec![(v[2] * v[3] + v[2]).id, ((v[0] + 1.0) / (v[1] + 2.0)).id]
        });
        let scheduled = schedule(&p);
        let first_div = scheduled
            .instrs
            .iter()
            .position(|i| matches!(i, Instr::Div(..)))
            .unwrap();
        let before = p
            .instrs
            .iter()
            .position(|i| matches!(i, Instr::Div(..)))
            .unwrap();
        assert!(
            first_div < before,
            "the division moved up: {first_div} < {before}"
        );
    }
}
