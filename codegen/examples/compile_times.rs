//! How long each kernel takes to compile, per policy (a development aid).
fn main() {
    use c5_codegen::{model::kernels, Mechanism, Model, ParameterSet, Robot};
    let robot = Robot::default();
    for model in Model::ALL {
        let mechanism = Mechanism::c5(&robot, model);
        for params in [ParameterSet::None, ParameterSet::All] {
            for entry in kernels::specs(&mechanism, &params, "").unwrap() {
                let spec = entry.spec;
                let t = std::time::Instant::now();
                let c = spec.compile().unwrap();
                println!(
                    "{model:<10} {:<28} {:?} {:>8.1} ms  {}",
                    spec.name,
                    params != ParameterSet::None,
                    t.elapsed().as_secs_f64() * 1e3,
                    c.count
                );
            }
        }
    }
}
