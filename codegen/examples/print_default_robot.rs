//! Prints the default robot as TOML, the format `--robot FILE.toml` reads.
fn main() {
    print!("{}", c5_codegen::Robot::default().to_toml());
}
