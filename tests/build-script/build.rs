//! Generates kernels for a robot that is not the default, folded in as constants, plus a set
//! that keeps gravity as a runtime input.

fn robot() -> c5_codegen::Robot {
    let mut robot = c5_codegen::Robot {
        half_spacing: 0.25,
        gravity: [0.5, -0.3, -9.7],
        ..Default::default()
    };
    robot.platform.mass = 12.5;
    robot.platform.com = [0.01, -0.02, 0.005];
    robot.segments[3].joint.mass = 2.1;
    robot
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    c5_codegen::Config::new().robot(robot()).generate()?;
    c5_codegen::Config::new()
        .robot(robot())
        .runtime_parameters(c5_codegen::ParameterSet::Named(vec![
            "gravity_x".into(),
            "gravity_y".into(),
            "gravity_z".into(),
        ]))
        .file_name("gravity_input.rs")
        .generate()?;
    println!("cargo:rerun-if-changed=build.rs");
    Ok(())
}
