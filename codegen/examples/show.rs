fn main() {
    let name = std::env::args().nth(1).unwrap();
    let robot = c5_codegen::Robot::default();
    let mut specs = c5_codegen::model::chapter_kernels();
    specs.extend(c5_codegen::model::pose_kernels(
        &robot,
        &c5_codegen::ParameterSet::None,
        "",
    ));
    let s = specs.iter().find(|s| s.name == name).unwrap();
    let c = s.compile().unwrap();
    println!(
        "{}",
        c5_codegen::emit::emit_file("", &[(s, &c)], c5_codegen::Scalar::F64).unwrap()
    );
}
