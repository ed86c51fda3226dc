//! Generates kernels for the robot in `robot.toml` (not the default one), folded in as
//! constants, plus a set that keeps gravity as a runtime input.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let robot = c5_codegen::Robot::from_toml_file(std::path::Path::new("robot.toml"))?;
    c5_codegen::Config::new().robot(robot).generate()?;
    c5_codegen::Config::new()
        .robot(robot)
        .runtime_parameters(c5_codegen::ParameterSet::Named(vec![
            "gravity_x".into(),
            "gravity_y".into(),
            "gravity_z".into(),
        ]))
        .file_name("gravity_input.rs")
        .generate()?;
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=robot.toml");
    Ok(())
}
