//! Fused multiply-add: which products of a program fold into the sums and differences that
//! read them, for the kernels' FMA twins (Rust `mul_add`, C `fma`).
//!
//! A product folds when its one reader is a sum or difference (an output is a reader that is
//! not) with no other product folded in: the reader becomes one fused operation and the
//! product disappears, one instruction and one rounding fewer. Where both terms of a sum could
//! fold, the earlier product does. The plan is made on the lowered program; the C emitter
//! carries it through its scheduled order ([`Fusion::permuted`]), so the Rust and C FMA twins
//! fuse the same products and compute the same bits, as their separate-rounding forms do.

use crate::lower::{Instr, Operand, Program};

/// A product folded into the instruction that reads it: `a·b + c`, `a·b − c` or `c − a·b`,
/// each with one rounding (`c` and `a` negated exactly where needed).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Fused {
    /// `a·b + c`.
    MulAdd(Operand, Operand, Operand),
    /// `a·b − c`, i.e. `fma(a, b, −c)`.
    MulSub(Operand, Operand, Operand),
    /// `c − a·b`, i.e. `fma(−a, b, c)`.
    NegMulAdd(Operand, Operand, Operand),
}

impl Fused {
    fn map_operands(self, f: impl Fn(Operand) -> Operand) -> Fused {
        match self {
            Fused::MulAdd(a, b, c) => Fused::MulAdd(f(a), f(b), f(c)),
            Fused::MulSub(a, b, c) => Fused::MulSub(f(a), f(b), f(c)),
            Fused::NegMulAdd(a, b, c) => Fused::NegMulAdd(f(a), f(b), f(c)),
        }
    }
}

/// The fusion plan of a program: per instruction, the fused operation it becomes, and whether
/// it is a product folded into its readers (then not emitted at all).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fusion {
    pub fused: Vec<Option<Fused>>,
    pub absorbed: Vec<bool>,
}

impl Fusion {
    /// The number of fused operations.
    #[cfg(test)]
    pub fn count(&self) -> usize {
        self.fused.iter().flatten().count()
    }

    /// The number of products folded away (the instructions the FMA twin saves).
    #[cfg(test)]
    pub fn saved(&self) -> usize {
        self.absorbed.iter().filter(|&&a| a).count()
    }

    /// The same plan for the program reordered as `order` says (`order[new] = old`, as
    /// [`crate::schedule::schedule_order`] gives it), its temporaries renumbered alike.
    pub fn permuted(&self, order: &[usize]) -> Fusion {
        let map = crate::schedule::renumbering(order);
        Fusion {
            fused: order
                .iter()
                .map(|&old| self.fused[old].map(|f| f.map_operands(&map)))
                .collect(),
            absorbed: order.iter().map(|&old| self.absorbed[old]).collect(),
        }
    }
}

/// The most readers a product may have and still fold (into each of them). Folding a product
/// read by two sums also saves an instruction, but turns both sums into multiplier-pipe work,
/// and the kernels are bound by those pipes on cores with two multiply and two add pipes:
/// measured on Zen 4, the paper model's inverse dynamics took 55.7 ns with one reader, 56.3 ns
/// with two and 57.2 ns with any number.
const MAX_READERS: usize = 1;

/// The plan for `program`.
pub fn plan(program: &Program) -> Fusion {
    let instrs = &program.instrs;
    let n = instrs.len();
    // Each temporary's readers, one entry per operand read (so in program order, a sum that
    // reads it twice twice), and whether an output reads it.
    let mut readers: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, instr) in instrs.iter().enumerate() {
        for o in instr.operands() {
            if let Operand::Temp(t) = o {
                readers[t as usize].push(i);
            }
        }
    }
    let mut is_output = vec![false; n];
    for o in &program.outputs {
        if let Operand::Temp(t) = *o {
            is_output[t as usize] = true;
        }
    }
    let mut fusion = Fusion {
        fused: vec![None; n],
        absorbed: vec![false; n],
    };
    for (t, instr) in instrs.iter().enumerate() {
        let Instr::Mul(a, b) = *instr else { continue };
        let reads = &readers[t];
        let foldable = |r: usize| {
            matches!(instrs[r], Instr::Add(..) | Instr::Sub(..)) && fusion.fused[r].is_none()
        };
        if is_output[t]
            || reads.is_empty()
            || reads.len() > MAX_READERS
            || reads.windows(2).any(|w| w[0] == w[1])
            || !reads.iter().all(|&r| foldable(r))
        {
            continue;
        }
        let product = Operand::Temp(t as u32);
        for &r in reads {
            fusion.fused[r] = Some(match instrs[r] {
                Instr::Add(x, y) => Fused::MulAdd(a, b, if x == product { y } else { x }),
                Instr::Sub(x, y) if x == product => Fused::MulSub(a, b, y),
                Instr::Sub(x, _) => Fused::NegMulAdd(a, b, x),
                _ => unreachable!("only sums and differences fold a product"),
            });
        }
        fusion.absorbed[t] = true;
    }
    fusion
}

#[cfg(test)]
/// Evaluates `program` on `inputs` with the plan's fused operations (for the tests: how far
/// the FMA twin is from the separate roundings).
pub fn eval_fused(program: &Program, fusion: &Fusion, inputs: &[f64]) -> Vec<f64> {
    let mut t: Vec<f64> = Vec::with_capacity(program.instrs.len());
    let val = |t: &[f64], o: Operand| match o {
        Operand::Temp(i) => t[i as usize],
        Operand::Input(i) => inputs[i as usize],
        Operand::Const(c) => c.get(),
    };
    for (i, instr) in program.instrs.iter().enumerate() {
        let v = match fusion.fused[i] {
            Some(Fused::MulAdd(a, b, c)) => val(&t, a).mul_add(val(&t, b), val(&t, c)),
            Some(Fused::MulSub(a, b, c)) => val(&t, a).mul_add(val(&t, b), -val(&t, c)),
            Some(Fused::NegMulAdd(a, b, c)) => (-val(&t, a)).mul_add(val(&t, b), val(&t, c)),
            // An absorbed product is never read; its slot keeps the numbering.
            None if fusion.absorbed[i] => f64::NAN,
            None => eval_one(*instr, &t, inputs),
        };
        t.push(v);
    }
    program.outputs.iter().map(|&o| val(&t, o)).collect()
}

#[cfg(test)]
/// One unfused instruction, as [`Program::eval`] computes it (the temporaries read as inputs
/// after the program's own).
fn eval_one(instr: Instr, t: &[f64], inputs: &[f64]) -> f64 {
    if let Instr::PairedCos(a) = instr {
        return eval_one(Instr::Call(crate::dag::Func::Cos, a), t, inputs);
    }
    let program = Program {
        instrs: vec![instr.map_operands(|o| match o {
            Operand::Temp(k) => Operand::Input(inputs.len() as u32 + k),
            other => other,
        })],
        outputs: vec![Operand::Temp(0)],
    };
    let mut all = inputs.to_vec();
    all.extend_from_slice(t);
    program.eval(&all)[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::kernels::specs;
    use crate::model::ParameterSet;
    use c5_robot::{Model, Robot};

    fn temp(t: u32) -> Operand {
        Operand::Temp(t)
    }

    #[test]
    fn a_product_read_once_by_a_sum_folds_into_it() {
        let (x, y, z) = (Operand::Input(0), Operand::Input(1), Operand::Input(2));
        let program = Program {
            instrs: vec![
                Instr::Mul(x, y),             // t0, read once: folds into t1
                Instr::Add(z, temp(0)),       // t1 = z + x·y
                Instr::Mul(x, z),             // t2, read by two sums: stays (MAX_READERS)
                Instr::Sub(temp(2), y),       // t3
                Instr::Sub(temp(1), temp(2)), // t4
                Instr::Mul(y, z),             // t5, read once: folds into t6
                Instr::Sub(temp(3), temp(5)), // t6 = t3 − y·z
                Instr::Mul(temp(3), x),       // t7, an output: stays
                Instr::Mul(x, x),             // t8, read twice by one sum: stays
                Instr::Add(temp(8), temp(8)), // t9
            ],
            outputs: vec![temp(4), temp(6), temp(7), temp(9)],
        };
        let fusion = plan(&program);
        assert_eq!(
            fusion.absorbed,
            [true, false, false, false, false, true, false, false, false, false]
        );
        assert_eq!(fusion.fused[1], Some(Fused::MulAdd(x, y, z)));
        assert_eq!(fusion.fused[6], Some(Fused::NegMulAdd(y, z, temp(3))));
        assert_eq!((fusion.count(), fusion.saved()), (2, 2));
        let inputs = [0.1, 0.7, -1.3];
        let (fused, separate) = (
            eval_fused(&program, &fusion, &inputs),
            program.eval(&inputs),
        );
        for (f, s) in fused.iter().zip(&separate) {
            assert!((f - s).abs() <= 1e-15, "{f} vs {s}");
        }
    }

    #[test]
    fn the_plan_follows_a_reordering() {
        let (x, y) = (Operand::Input(0), Operand::Input(1));
        let program = Program {
            instrs: vec![
                Instr::Mul(x, y),       // t0
                Instr::Add(x, y),       // t1
                Instr::Add(temp(0), y), // t2 = x·y + y
                Instr::Mul(temp(1), temp(2)),
            ],
            outputs: vec![temp(3)],
        };
        let order = [1, 0, 2, 3];
        let reordered = crate::schedule::schedule(&program);
        let fusion = plan(&program).permuted(&order);
        assert_eq!(fusion.absorbed, [false, true, false, false]);
        assert_eq!(fusion.fused[2], Some(Fused::MulAdd(x, y, y)));
        // The scheduler's own order gives the same fused values as the original order.
        let schedule = crate::schedule::schedule_order(&program);
        let moved = plan(&program).permuted(&schedule);
        let inputs = [0.3, -1.7];
        assert_eq!(
            eval_fused(&reordered, &moved, &inputs),
            eval_fused(&program, &plan(&program), &inputs)
        );
    }

    #[test]
    fn a_product_minus_a_value_is_one_fused_operation() {
        let (x, y, z) = (Operand::Input(0), Operand::Input(1), Operand::Input(2));
        let program = Program {
            instrs: vec![Instr::Mul(x, y), Instr::Sub(temp(0), z)],
            outputs: vec![temp(1)],
        };
        let fusion = plan(&program);
        assert_eq!(fusion.fused[1], Some(Fused::MulSub(x, y, z)));
        // 1/3·3 − 1 is exactly representable fused (the product's rounding error), zero apart.
        let third = 1.0 / 3.0;
        let fused = eval_fused(&program, &fusion, &[third, 3.0, 1.0])[0];
        assert_eq!(fused, third.mul_add(3.0, -1.0));
        assert_ne!(fused, program.eval(&[third, 3.0, 1.0])[0]);
    }

    /// The inverse dynamics of both models: about half the products fold into a sum, and the
    /// fused evaluation stays within a few units in the last place of the separate one.
    #[test]
    fn the_inverse_dynamics_fuses_about_half_its_products() {
        for model in Model::ALL {
            let entries = specs(
                &crate::Mechanism::c5(&Robot::default(), model),
                &ParameterSet::None,
                "",
            )
            .unwrap();
            let entry = entries
                .iter()
                .find(|e| e.spec.name == "inverse_dynamics")
                .unwrap();
            let compiled = entry.spec.compile().unwrap();
            let fusion = plan(&compiled.program);
            assert!(
                fusion.count() * 5 > compiled.count.mul as usize * 2,
                "{model}: {} of {} products fused",
                fusion.count(),
                compiled.count.mul
            );
            let inputs = [
                0.17, 0.26, 0.35, 0.01, -0.02, 0.03, 0.3, -0.2, 0.1, 0.05, 0.02, -0.01, 1.0, -2.0,
                0.5, 0.3, 0.2, -0.4,
            ];
            let separate = compiled.program.eval(&inputs);
            let fused = eval_fused(&compiled.program, &fusion, &inputs);
            let scale = separate.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
            for (f, s) in fused.iter().zip(&separate) {
                assert!((f - s).abs() <= 1e-13 * scale, "{model}: {f} vs {s}");
            }
        }
    }
}
