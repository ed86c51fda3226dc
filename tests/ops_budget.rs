//! The operation budget (`benches/ops-budget.txt`) holds: no generated kernel costs more than
//! its line allows, and every kernel has a line.

use std::collections::BTreeMap;

fn budget() -> BTreeMap<String, [u64; 5]> {
    let text = include_str!("../benches/ops-budget.txt");
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let mut f = l.split_whitespace();
            let name = f.next().unwrap().to_string();
            let n: Vec<u64> = f.map(|x| x.parse().expect("a count")).collect();
            (name, n.try_into().expect("mul div add neg calls"))
        })
        .collect()
}

#[test]
fn no_kernel_exceeds_its_budget() {
    let budget = budget();
    let m: serde_json::Value = serde_json::from_str(c5_generated::OPS_JSON).unwrap();
    let mut over = Vec::new();
    for k in m["kernels"].as_array().unwrap() {
        let name = k["name"].as_str().unwrap();
        let limit = budget
            .get(name)
            .unwrap_or_else(|| panic!("kernel `{name}` has no line in benches/ops-budget.txt"));
        let calls: u64 = k["calls"]
            .as_object()
            .unwrap()
            .values()
            .map(|v| v.as_u64().unwrap())
            .sum();
        let got = [
            k["mul"].as_u64().unwrap(),
            k["div"].as_u64().unwrap(),
            k["add"].as_u64().unwrap(),
            k["neg"].as_u64().unwrap(),
            calls,
        ];
        if got.iter().zip(limit).any(|(g, l)| g > l) {
            over.push(format!("{name}: {got:?} > budget {limit:?}"));
        }
    }
    assert!(
        over.is_empty(),
        "over budget (mul div add neg calls): {over:#?}"
    );
}
