//! `envmap-report --quick --json` runs and its output is complete: every
//! function, mapping and tier, the conversion and the render. No timing is
//! judged.

use std::process::Command;

use envmap_bench::report::check_json_lines;

/// Runs `envmap-report` with `args`; its standard output.
fn report(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_envmap-report"))
        .args(args)
        .output()
        .expect("envmap-report runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

#[test]
fn quick_json_report_is_complete() {
    let text = report(&["--quick", "--json"]);
    let rows = check_json_lines(&text).expect("complete report");
    assert!(rows > 100, "{rows} rows");

    // The checker notices a missing row and a broken line.
    let without_fast_cube: String = text
        .lines()
        .filter(|l| !(l.contains("\"name\":\"cube\"") && l.contains("\"tier\":\"fast\"")))
        .map(|l| format!("{l}\n"))
        .collect();
    let err = check_json_lines(&without_fast_cube).unwrap_err();
    assert!(err.contains("cube"), "{err}");
    assert!(check_json_lines(&format!("{text}{{\"kind\": \"function\"\n")).is_err());
}

#[test]
fn tune_prints_a_degree() {
    let text = report(&["--quick", "--tune", "atan2", "--degrees", "5..9"]);
    let degrees: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("| ")?.split(' ').next())
        .filter(|d| d.parse::<u32>().is_ok())
        .collect();
    assert_eq!(degrees, ["5", "7", "9"], "{text}");
    assert!(
        text.contains("atan2 to 0.015625 texel at 8192 wide: degree"),
        "{text}"
    );
}
