//! `c5`: the program; its commands are the library's (`src/lib.rs`).

fn main() -> std::process::ExitCode {
    c5_cli::main()
}
