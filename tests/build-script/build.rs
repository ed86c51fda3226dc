//! Generates kernels for the robot in `robot.toml` (not the default one): the consistent model
//! (the default) and the paper model with the robot folded in as constants, plus a set that
//! keeps gravity as a runtime input, named in an order of this crate's choosing.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let robot = c5_codegen::Robot::from_toml_file(std::path::Path::new("robot.toml"))?;
    c5_codegen::Config::new().robot(robot).generate()?;
    c5_codegen::Config::new()
        .robot(robot)
        .model(c5_codegen::Model::Paper)
        .file_name("paper.rs")
        .generate()?;
    c5_codegen::Config::new()
        .robot(robot)
        .runtime_parameters(c5_codegen::ParameterSet::Named(vec![
            "gravity_z".into(),
            "gravity_x".into(),
            "gravity_y".into(),
        ]))
        .file_name("gravity_input.rs")
        .generate()?;
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=robot.toml");
    Ok(())
}
