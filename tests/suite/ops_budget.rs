//! The budgets hold. The operation budget (`benches/ops-budget.txt`): no generated kernel costs
//! more than its line allows, and every kernel of every model has a line. The size budget
//! (`benches/size-budget.txt`): no generated file has more lines than its line allows (compile
//! time grows with them), every generated file has a line, and all of them stay within the
//! total.

use c5_generated::manifest::KERNELS;
use std::collections::BTreeMap;

fn budget() -> BTreeMap<(String, String), [u32; 5]> {
    let text = include_str!("../../benches/ops-budget.txt");
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

#[test]
fn no_generated_file_exceeds_its_size_budget() {
    let text = include_str!("../../benches/size-budget.txt");
    let budget: BTreeMap<&str, usize> = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let mut f = l.split_whitespace();
            let name = f.next().unwrap();
            (name, f.next().unwrap().parse().expect("a line count"))
        })
        .collect();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/src");
    let (mut over, mut total) = (Vec::new(), 0);
    for dir in ["f64", "f32"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            let name = format!("{dir}/{}", path.file_name().unwrap().to_string_lossy());
            let lines = std::fs::read_to_string(&path).unwrap().lines().count();
            total += lines;
            let limit = *budget.get(name.as_str()).unwrap_or_else(|| {
                panic!("generated/src/{name} has no line in benches/size-budget.txt")
            });
            if lines > limit {
                over.push(format!("{name}: {lines} lines > budget {limit}"));
            }
        }
    }
    println!(
        "generated kernel files: {total} lines (budget {})",
        budget["total"]
    );
    assert!(
        total <= budget["total"],
        "{total} lines > total budget {}",
        budget["total"]
    );
    assert!(
        over.is_empty(),
        "generated code over its budget (raise the line in benches/size-budget.txt in the \
         change that grows it, and say why): {over:#?}"
    );
}
