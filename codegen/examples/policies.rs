//! Every rewriting policy's count for one kernel (a development aid):
//! `cargo run --release -p c5-codegen --example policies -- paper inverse_dynamics`.
fn main() {
    use c5_codegen::{model::kernels, Mechanism, Model, ParameterSet, Robot};
    let args: Vec<String> = std::env::args().collect();
    let model: Model = args.get(1).map_or("paper", String::as_str).parse().unwrap();
    let name = args.get(2).map_or("inverse_dynamics", String::as_str);
    let spec = kernels::specs(
        &Mechanism::c5(&Robot::default(), model),
        &ParameterSet::None,
        "",
    )
    .unwrap()
    .into_iter()
    .find(|e| e.spec.name == name)
    .expect("a kernel of that name")
    .spec;
    for (policy, count) in spec.costs_by_policy().unwrap() {
        println!("{policy:?}: {count}");
    }
}
