//! Helpers shared by the integration tests (each test file uses some).
#![allow(dead_code, unused_imports)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `envmap` command in `dir`.
pub(crate) fn envmap(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_envmap"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run envmap")
}

/// Runs the `envmap` command in `dir` with `input` on standard input.
pub(crate) fn envmap_stdin(args: &[&str], dir: &Path, input: &str) -> Output {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_envmap"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run envmap");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write stdin");
    child.wait_with_output().expect("wait")
}

pub(crate) use envmap_tests::{entries, text};
