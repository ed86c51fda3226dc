//! `c5` follows the conventions of a command-line tool: `--help` and `--version` everywhere,
//! unknown arguments and bad values refused with the choices, a closed stdout ends the run
//! quietly, and `simulate`'s sampling stays within bounds and ends on the end of the motion.

use crate::support;

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use support::{c5, c5_ok};

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-conventions-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn help_and_version_everywhere() {
    for args in [
        &["--help"][..],
        &["--version"],
        &["simulate", "--help"],
        &["eval", "--help"],
        &["audit", "--help"],
    ] {
        let out = c5(args, "");
        assert!(out.status.success(), "{args:?}");
        assert!(!out.stdout.is_empty(), "{args:?}");
    }
    let out = c5(&["simulate", "--frobnicate"], "");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--frobnicate"));
}

#[test]
fn audit_lists_the_models_it_is_asked_for() {
    let all = String::from_utf8(c5(&["audit"], "").stdout).unwrap();
    assert!(all.contains("consistent ") && all.contains("paper "));
    let paper = String::from_utf8(c5(&["audit", "--model", "paper"], "").stdout).unwrap();
    assert!(paper.contains("step6_factored") && !paper.contains("consistent "));
}

#[test]
fn simulate_refuses_a_rate_it_cannot_honour() {
    let dir = scratch("rate");
    let out_dir = dir.join("out");
    let out = c5(
        &[
            "simulate",
            "--rate",
            "1e9",
            "--out",
            out_dir.to_str().unwrap(),
        ],
        "",
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("1000000002 samples"),
        "{err}"
    );
    assert!(!out_dir.exists());
    for rate in ["0", "-5", "nan"] {
        let out = c5(
            &[
                "simulate",
                "--rate",
                rate,
                "--out",
                out_dir.to_str().unwrap(),
            ],
            "",
        );
        assert!(!out.status.success(), "{rate}");
    }
    // A trajectory file has its own times: --rate with it is refused, not ignored.
    let out = c5(&["simulate", "--rate", "100", "--trajectory", "x.csv"], "");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("--trajectory"),
        "{err}"
    );
}

#[test]
fn simulate_ends_on_the_end_of_the_motion_whatever_the_rate() {
    let dir = scratch("end");
    c5_ok(
        &["simulate", "--rate", "1.5", "--out", dir.to_str().unwrap()],
        "",
    );
    let mut rows = csv::Reader::from_path(dir.join("section9.csv")).unwrap();
    let t: Vec<f64> = rows
        .records()
        .map(|r| r.unwrap()[0].parse().unwrap())
        .collect();
    assert_eq!(t.len(), 3);
    assert_eq!((t[0], t[2]), (0.0, 1.0));
    assert!((t[1] - 1.0 / 1.5).abs() < 1e-12);
}

#[test]
fn a_closed_stdout_ends_eval_quietly_and_successfully() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_c5"))
        .arg("eval")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    // Far more output than a pipe holds, so the writer meets the closed end.
    let feeder = std::thread::spawn(move || {
        for _ in 0..20_000 {
            if stdin
                .write_all(b"{\"pose\": [0.1, 0.2, 0.3, 0.01, 0.02, 0.03]}\n")
                .is_err()
            {
                break;
            }
        }
    });
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.contains("\"gamma\""));
    // The reader is gone: like `c5 eval | head -1`.
    let out = child.wait_with_output().unwrap();
    feeder.join().unwrap();
    assert!(out.status.success(), "exit status {:?}", out.status);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The commands that report in a few lines after their work (`plan`, `calibrate --plan`) end
/// quietly and successfully when the reader is already gone, like `c5 plan | head -0`: the
/// report is written, and the closed pipe is not a panic.
#[test]
fn a_closed_stdout_ends_the_short_reports_quietly() {
    let dir = scratch("closed-report");
    let delta = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/delta.toml");
    let hexapod = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/hexapod.toml");
    let (plan_out, poses) = (dir.join("plan"), dir.join("poses.csv"));
    let commands: [&[&str]; 2] = [
        &[
            "plan",
            "--robot",
            delta,
            "--duration",
            "0.5",
            "--out",
            plan_out.to_str().unwrap(),
        ],
        &[
            "calibrate",
            "--plan",
            "12",
            "--robot",
            hexapod,
            "--out",
            poses.to_str().unwrap(),
        ],
    ];
    for args in commands {
        let mut child = Command::new(env!("CARGO_BIN_EXE_c5"))
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // The read end closed before the program reports.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "c5 {}: {err}", args.join(" "));
        assert!(err.is_empty(), "c5 {}: {err}", args.join(" "));
    }
    assert!(plan_out.join("plan.csv").exists() && poses.exists());
}
