//! Interrupted runs leave nothing behind: SIGINT and SIGTERM sent to the
//! `envmap` command while it loads, converts or saves leave the output
//! directory exactly as it was, with the documented exit status; the
//! library's cancel flag stops work within a band of rows.
//!
//! Run as a user runs the command: a child process and a real signal (sent
//! with `kill`), timed against the stage lines `--verbose` prints as each
//! stage begins. The latency from signal to exit is printed (`--nocapture`).
#![cfg(unix)]

use std::fs;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{mpsc, OnceLock};
use std::time::{Duration, Instant};

use envmap_core::AnyMapping;
use envmap_render::image::{Outputs, SaveOptions};
use envmap_render::scene::Builtin;
use envmap_render::scene::{fill, smooth};
use envmap_render::scene::{Camera, EnvSource, RenderOptions, Renderer};
use envmap_render::{
    filter::{convert, ConvertOptions},
    image::{save, Representation},
    Error,
};

mod common;
use common::entries;

/// A 4096 × 2048 latlong EXR (100 MB of f32), made once for every test.
fn big_input() -> &'static Path {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    let dir = DIR.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let img = fill(
            Representation::default_for(AnyMapping::LatLong),
            4096,
            2048,
            smooth,
        )
        .unwrap();
        save(&img, dir.path().join("big.exr"), &SaveOptions::default()).unwrap();
        dir
    });
    // Leaked on purpose: the directory lives as long as the test binary.
    Box::leak(dir.path().join("big.exr").into_boxed_path())
}

/// Every file in `dir` with its bytes, sorted by name.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    entries(dir)
        .into_iter()
        .map(|n| {
            let bytes = fs::read(dir.join(&n)).unwrap_or_default();
            (n, bytes)
        })
        .collect()
}

/// The command's standard error, line by line, as it comes.
fn stderr_lines(child: &mut Child) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    let err = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// Waits for a line containing `what`; the lines seen so far.
fn wait_for(rx: &mpsc::Receiver<String>, what: &str, seen: &mut Vec<String>) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while Instant::now() < deadline {
        if let Ok(l) = rx.recv_timeout(Duration::from_millis(50)) {
            let hit = l.contains(what);
            seen.push(l);
            if hit {
                return;
            }
        }
    }
    panic!("no line with {what:?} on standard error; saw {seen:?}");
}

fn kill(child: &Child, signal: &str) {
    let ok = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill -{signal}");
}

/// Waits for the child to exit (at most a minute); its status code and the
/// time it took from now.
fn finish(child: &mut Child) -> (Option<i32>, Duration) {
    let t = Instant::now();
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return (s.code(), t.elapsed());
        }
        if t.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("envmap did not exit within a minute of the signal");
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Runs `envmap convert big.exr <out> ...` in `dir`, sends `signal` once the
/// stage line containing `stage` appears (and, with `temps`, once that many
/// temporary files exist), and checks what it leaves.
fn interrupt(dir: &Path, out: &str, extra: &[&str], stage: &str, temps: usize, signal: &str) {
    let before = snapshot(dir);
    let mut child = Command::new(env!("CARGO_BIN_EXE_envmap"))
        .arg("convert")
        .arg(big_input())
        .arg(out)
        .args(["--to", "cube", "-v"])
        .args(extra)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let rx = stderr_lines(&mut child);
    let mut seen = Vec::new();
    wait_for(&rx, stage, &mut seen);
    if temps > 0 {
        let t = Instant::now();
        while entries(dir).iter().filter(|n| n.ends_with(".tmp")).count() < temps {
            assert!(t.elapsed() < Duration::from_secs(60), "no temporary files");
            std::thread::sleep(Duration::from_millis(1));
        }
    }
    kill(&child, signal);
    let (code, latency) = finish(&mut child);
    // Every line the process wrote: the reader thread ends when the pipe
    // closes, which may be after the exit is seen (a loaded machine).
    while let Ok(l) = rx.recv_timeout(Duration::from_secs(10)) {
        seen.push(l);
    }
    let want = if signal == "INT" { 130 } else { 143 };
    assert_eq!(code, Some(want), "{out} {stage} {signal}: {seen:?}");
    assert!(
        seen.iter()
            .any(|l| l == "envmap: interrupted: nothing written"),
        "{seen:?}"
    );
    assert!(!seen.iter().any(|l| l.contains("panicked")), "{seen:?}");
    // Exactly as before: no temporary file, every old file byte for byte.
    assert_eq!(snapshot(dir), before, "{out} {stage} {signal}");
    println!(
        "SIG{signal} while {stage:<10} {out:<18}: exit {want} after {:.1} ms",
        latency.as_secs_f64() * 1e3
    );
}

#[test]
fn signals_while_loading_converting_and_saving_leave_the_directory_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("cube.exr"), b"the previous output").unwrap();
    fs::write(dir.path().join("notes.txt"), b"a file of the user's").unwrap();
    // 16 sub-samples per texel make the conversion long enough to be hit.
    let convert_long = ["--size", "1024", "--layout", "strip", "--samples", "4"];
    let save_long = ["--size", "2048", "--layout", "strip", "--samples", "1"];
    for signal in ["INT", "TERM"] {
        interrupt(dir.path(), "cube.exr", &convert_long, "loading", 0, signal);
        interrupt(
            dir.path(),
            "cube.exr",
            &convert_long,
            "converting",
            0,
            signal,
        );
        interrupt(dir.path(), "cube.exr", &save_long, "saving", 1, signal);
    }
}

#[test]
fn a_six_file_cube_interrupted_midway_leaves_none_of_the_new_faces() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["+x", "-x", "+y", "-y", "+z", "-z"] {
        fs::write(dir.path().join(format!("sky_{f}.exr")), format!("old {f}")).unwrap();
    }
    // Signal once two faces are written to temporary files and a third is
    // under way: none of the new faces may replace an old one.
    for signal in ["INT", "TERM"] {
        interrupt(
            dir.path(),
            "sky_{face}.exr",
            &["--size", "1024", "--samples", "1"],
            "saving",
            3,
            signal,
        );
    }
}

#[test]
fn a_second_signal_exits_at_once_and_never_leaves_a_partial_target() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("cube.exr"), b"the previous output").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_envmap"))
        .arg("convert")
        .arg(big_input())
        .args([
            "cube.exr", "--to", "cube", "-v", "--size", "2048", "--layout", "strip",
        ])
        .current_dir(dir.path())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let rx = stderr_lines(&mut child);
    wait_for(&rx, "saving", &mut Vec::new());
    kill(&child, "INT");
    kill(&child, "INT");
    let (code, _) = finish(&mut child);
    assert_eq!(code, Some(130));
    // The target is the old file (a temporary file may remain when the
    // second signal came before the first was handled: it is never the
    // target's name).
    assert_eq!(
        fs::read(dir.path().join("cube.exr")).unwrap(),
        b"the previous output"
    );
    for n in entries(dir.path()) {
        assert!(
            n == "cube.exr" || (n.starts_with(".cube.exr.") && n.ends_with(".tmp")),
            "{n}"
        );
    }
}

#[test]
fn map_waiting_for_input_stops_on_a_signal() {
    for (signal, want) in [("INT", 130), ("TERM", 143)] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_envmap"))
            .args(["map", "--mapping", "cube"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Standard input stays open: the command is waiting for lines.
        std::thread::sleep(Duration::from_millis(200));
        kill(&child, signal);
        let (code, latency) = finish(&mut child);
        let out = child.wait_with_output().unwrap();
        assert_eq!(code, Some(want));
        assert!(out.stdout.is_empty());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("interrupted: nothing written"), "{err}");
        println!(
            "SIG{signal} while map waits for input: exit {want} after {:.1} ms",
            latency.as_secs_f64() * 1e3
        );
    }
}

/// The library's cancel flag, set from the progress callback as the first
/// band finishes: the conversion stops within a band per thread and says so.
#[test]
fn the_cancel_flag_stops_a_conversion_within_one_band() {
    let src = fill(
        Representation::default_for(AnyMapping::LatLong),
        1024,
        512,
        smooth,
    )
    .unwrap();
    let cube = Representation::new(
        AnyMapping::Cube,
        envmap_core::Atlas::CUBE_HORIZONTAL_STRIP,
        envmap_core::Frame::IDENTITY,
    )
    .unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let stop = AtomicBool::new(false);
    let rows = AtomicU32::new(0);
    let progress = |k: u32| {
        rows.fetch_add(k, Ordering::SeqCst);
        stop.store(true, Ordering::SeqCst);
    };
    let opts = {
        let mut o = ConvertOptions::default();
        o.samples = Some(1);
        o.cancel = Some(&stop);
        o
    };
    // 1024 rows on two threads: bands of 1024 / 8 = 128 rows.
    let r = pool.install(|| convert(&src, cube, 6 * 1024, 1024, &opts, Some(&progress)));
    assert!(matches!(r, Err(Error::Cancelled)), "{r:?}");
    let done = rows.load(Ordering::SeqCst);
    // The band that set the flag, and at most one more already under way on
    // the other thread.
    assert!(
        (128..=256).contains(&done),
        "{done} rows converted after the flag"
    );
    // Without the flag the same conversion finishes every row.
    stop.store(false, Ordering::SeqCst);
    let all = AtomicU32::new(0);
    let count = |k: u32| {
        all.fetch_add(k, Ordering::SeqCst);
    };
    let no_stop = {
        let mut o = opts;
        o.cancel = None;
        o
    };
    pool.install(|| convert(&src, cube, 6 * 1024, 1024, &no_stop, Some(&count)))
        .unwrap();
    assert_eq!(all.load(Ordering::SeqCst), 1024);
}

#[test]
fn the_cancel_flag_stops_a_render_and_a_load() {
    let env = Builtin::Sky
        .image(
            Representation::default_for(AnyMapping::Cube),
            64 * 4,
            64 * 3,
        )
        .unwrap();
    let stop = AtomicBool::new(true);
    let opts = {
        let mut o = RenderOptions::default();
        o.width = 64;
        o.height = 48;
        o.cancel = Some(&stop);
        o
    };
    let mesh = envmap_render::scene::Mesh::sphere(1.0, 16, 8);
    let r = Renderer::new().render(&mesh, EnvSource::Map(&env), &Camera::default(), &opts);
    assert!(matches!(r, Err(Error::Cancelled)));
    let l = envmap_render::image::load(big_input(), &{
        let mut o = envmap_render::image::LoadOptions::default();
        o.cancel = Some(&stop);
        o
    });
    assert!(matches!(l, Err(Error::Cancelled)), "{l:?}");
}

/// A run of several outputs whose third rename fails (its target became a
/// directory after staging): the two already renamed are put back, the
/// error says so, and no temporary file stays.
#[test]
fn a_rename_failing_midway_puts_the_earlier_targets_back() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| -> PathBuf { dir.path().join(n) };
    fs::write(p("a.txt"), b"old a").unwrap();
    fs::write(p("b.txt"), b"old b").unwrap();
    let mut run = Outputs::new(&SaveOptions::default());
    run.stage_bytes(p("a.txt"), b"new a").unwrap();
    run.stage_bytes(p("new.txt"), b"new").unwrap();
    run.stage_bytes(p("c.txt"), b"new c").unwrap();
    run.stage_bytes(p("b.txt"), b"new b").unwrap();
    fs::create_dir(p("c.txt")).unwrap();
    fs::write(p("c.txt").join("inside"), b"x").unwrap();
    let e = run.commit().unwrap_err().to_string();
    assert!(
        e.contains("c.txt") && e.contains("none of the 4 outputs"),
        "{e}"
    );
    assert_eq!(fs::read(p("a.txt")).unwrap(), b"old a");
    assert_eq!(fs::read(p("b.txt")).unwrap(), b"old b");
    assert!(!p("new.txt").exists());
    assert_eq!(entries(dir.path()), ["a.txt", "b.txt", "c.txt"]);
    // A cancel before the renames: nothing renamed, nothing left.
    let stop = AtomicBool::new(false);
    let opts = {
        let mut o = SaveOptions::default();
        o.cancel = Some(&stop);
        o
    };
    let mut run = Outputs::new(&opts);
    run.stage_bytes(p("a.txt"), b"newer a").unwrap();
    run.stage_bytes(p("b.txt"), b"newer b").unwrap();
    stop.store(true, Ordering::SeqCst);
    assert!(matches!(run.commit(), Err(Error::Cancelled)));
    assert_eq!(fs::read(p("a.txt")).unwrap(), b"old a");
    assert_eq!(entries(dir.path()), ["a.txt", "b.txt", "c.txt"]);
    // Staged twice in one run: refused.
    let mut run = Outputs::new(&SaveOptions::default());
    run.stage_bytes(p("d.txt"), b"1").unwrap();
    let e = run.stage_bytes(p("d.txt"), b"2").unwrap_err().to_string();
    assert!(e.contains("named twice"), "{e}");
}
