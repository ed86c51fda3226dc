fn main() {
    let robot = c5_codegen::Robot::default();
    let mut specs = c5_codegen::model::chapter_kernels();
    specs.extend(c5_codegen::model::pose_kernels(
        &robot,
        &c5_codegen::ParameterSet::None,
        "",
    ));
    specs.extend(c5_codegen::model::pose_kernels(
        &robot,
        &c5_codegen::ParameterSet::All,
        "_params",
    ));
    for s in &specs {
        let t = std::time::Instant::now();
        let c = s.compile().unwrap();
        println!(
            "{:32} {:?} {} [{:?}]",
            s.name,
            c.policy.expand_limit,
            c.count,
            t.elapsed()
        );
    }
}
