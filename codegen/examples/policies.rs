//! Every rewriting policy's count for one kernel, and the cheapest in each differentiation mode
//! (a development aid; docs/derivatives.md's table of modes comes from it):
//! `cargo run --release -p c5-codegen --example policies -- paper inverse_dynamics`,
//! `… -- gough-stewart inverse_dynamics_derivatives_params`. The mechanism is `paper`,
//! `consistent` (the C5's models), `gough-stewart`, `rus-hexapod` or `delta`, each its
//! checked-in example; a `_params` kernel takes every parameter as an input.
use c5_codegen::{model::kernels, Mechanism, Model, ParameterSet, Robot};

fn mechanism(name: &str) -> Mechanism {
    match name {
        "gough-stewart" => Mechanism::gough_stewart(&c5_robot::GoughStewart::example()),
        "rus-hexapod" => Mechanism::rus_hexapod(&c5_robot::RusHexapod::example()),
        "delta" => Mechanism::delta(&c5_robot::Delta::example()),
        model => Mechanism::c5(&Robot::default(), model.parse::<Model>().unwrap()),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mechanism = mechanism(args.get(1).map_or("paper", String::as_str));
    let name = args.get(2).map_or("inverse_dynamics", String::as_str);
    let (parameters, suffix) = match name.strip_suffix("_params") {
        Some(_) => (ParameterSet::All, "_params"),
        None => (ParameterSet::None, ""),
    };
    let mut specs = kernels::specs(&mechanism, &parameters, suffix).unwrap();
    specs.extend(kernels::derivative_specs(&mechanism, &parameters, suffix).unwrap());
    let spec = specs
        .into_iter()
        .find(|e| e.spec.name == name)
        .expect("a kernel of that name")
        .spec;
    let costs = spec.costs_by_policy().unwrap();
    for (policy, count) in &costs {
        println!("{policy:?}: {count}");
    }
    for reverse_mode in [false, true] {
        let best = costs
            .iter()
            .filter(|(policy, _)| policy.reverse_mode == reverse_mode)
            .min_by(|a, b| a.1.weight().total_cmp(&b.1.weight()));
        if let Some((policy, count)) = best {
            let mode = if reverse_mode { "reverse" } else { "forward" };
            println!("cheapest in {mode} mode: {count} ({policy:?})");
        }
    }
}
