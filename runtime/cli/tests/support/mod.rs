//! Running the `c5` program in tests.

use std::io::Write;
use std::process::{Command, Output, Stdio};

/// Runs `c5 ARGS` with `stdin`, fed from a thread (the program writes while it reads, and both
/// pipes are bounded); a program that exits before reading leaves a broken pipe, ignored here.
pub fn c5(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_c5"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("c5 runs");
    let mut pipe = child.stdin.take().unwrap();
    let input = stdin.to_string();
    let feeder = std::thread::spawn(move || {
        let _ = pipe.write_all(input.as_bytes());
    });
    let out = child.wait_with_output().unwrap();
    feeder.join().unwrap();
    out
}

/// [`c5`], asserting that it succeeds (its standard error in the message if not).
// Each test file compiles this module on its own, and not every one needs this.
#[allow(dead_code)]
pub fn c5_ok(args: &[&str], stdin: &str) -> Output {
    let out = c5(args, stdin);
    assert!(
        out.status.success(),
        "c5 {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}
