//! The operation budget (`benches/ops-budget.txt`) holds: no generated kernel costs more than
//! its line allows, and every kernel of every model has a line.

use c5_generated::manifest::KERNELS;
use std::collections::BTreeMap;

fn budget() -> BTreeMap<(String, String), [u32; 5]> {
    let text = include_str!("../benches/ops-budget.txt");
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let mut f = l.split_whitespace();
            let model = f.next().unwrap().to_string();
            let name = f.next().unwrap().to_string();
            let n: Vec<u32> = f.map(|x| x.parse().expect("a count")).collect();
            ((model, name), n.try_into().expect("mul div add neg calls"))
        })
        .collect()
}

#[test]
fn no_kernel_exceeds_its_budget() {
    let budget = budget();
    let mut over = Vec::new();
    for k in KERNELS {
        let key = (k.model.to_string(), k.name.to_string());
        let limit = budget.get(&key).unwrap_or_else(|| {
            panic!(
                "kernel `{}` of the {} model has no line in benches/ops-budget.txt",
                k.name, k.model
            )
        });
        let c = &k.count;
        let calls = c.calls.iter().map(|(_, n)| n).sum();
        let got = [c.mul, c.div, c.add, c.neg, calls];
        if got.iter().zip(limit).any(|(g, l)| g > l) {
            over.push(format!(
                "{} {}: {got:?} > budget {limit:?}",
                k.model, k.name
            ));
        }
    }
    assert!(
        over.is_empty(),
        "over budget (mul div add neg calls): {over:#?}"
    );
}
