//! `c5-codegen`: regenerates the checked-in `generated/` crate and prints the audit.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../generated");
    match args.first().map(String::as_str) {
        Some("generate") => match c5_codegen::write_generated_crate(&dir) {
            Ok(stale) => {
                for p in &stale {
                    println!("wrote generated/{}", p.display());
                }
                if stale.is_empty() {
                    println!("generated/ is up to date");
                }
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        _ => {
            eprintln!("usage: c5-codegen generate");
            ExitCode::from(2)
        }
    }
}
