//! How long each kernel takes to compile, and what it costs (a development aid):
//! `cargo run --release -p c5-codegen --example compile_times [-- gough-stewart]`.
fn main() {
    use c5_codegen::{model::kernels, Mechanism, Model, ParameterSet, Robot};
    let mechanisms: Vec<Mechanism> = match std::env::args().nth(1).as_deref() {
        Some("gough-stewart") => vec![Mechanism::gough_stewart(&c5_robot::GoughStewart::example())],
        _ => Model::ALL
            .into_iter()
            .map(|m| Mechanism::c5(&Robot::default(), m))
            .collect(),
    };
    for mechanism in &mechanisms {
        for params in [ParameterSet::None, ParameterSet::All] {
            for entry in kernels::specs(mechanism, &params, "").unwrap() {
                let spec = entry.spec;
                let t = std::time::Instant::now();
                let c = spec.compile().unwrap();
                println!(
                    "{:<14} {:<28} {:<5} {:>8.1} ms  {}",
                    mechanism.name(),
                    spec.name,
                    params != ParameterSet::None,
                    t.elapsed().as_secs_f64() * 1e3,
                    c.count
                );
            }
        }
    }
}
