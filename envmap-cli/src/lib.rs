//! The `envmap` command: convert environment maps between representations,
//! inspect them, map directions to texture coordinates and back, render and
//! demonstrate. `src/main.rs` (the binary) calls [`main`].
//!
//! One file per subcommand (`convert.rs`, `info.rs`, `map.rs` for `map` and
//! `unmap`, `render.rs`, `demo.rs`), the argument parsers and helpers they
//! share in `args.rs`, and [`text`], the line formats of `map` and `unmap`.
//!
//! Exit codes: 0 success; 1 a runtime error (a file that cannot be read,
//! decoded or written, an image above the size limit or fitting no layout,
//! a bad input line); 2 a usage error (unknown command, flag or value,
//! reported by the argument parser); 130 and 143 interrupted by SIGINT and
//! SIGTERM (see `signals.rs`). `--help` prints them.
//!
//! The command is a thin shell over the library `envmap-render`: flags,
//! progress bars, printed tables, the demo and its report, interrupts and
//! exit codes live here; every computation is the library's.

#![forbid(unsafe_code)]

use std::process::ExitCode;

use signals::Signals;

use clap::{Parser, Subcommand};

/// A line on standard error, as `eprintln!` writes it, but a standard error
/// that cannot be written (closed: `envmap bake … 2>&1 | head -1`) is no
/// reason to stop: the outputs were made; the line is dropped.
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod args;
mod bake;
mod convert;
mod demo;
mod info;
mod map;
mod render;
mod signals;
pub mod text;

/// Why a subcommand stopped: the library's error, or one of the command's
/// own (a flag's value refused before any work, standard output closed).
/// [`main`] turns each into its one line on standard error and its exit
/// status, here and nowhere else.
#[derive(Debug)]
pub(crate) enum Failure {
    /// An error of the library: a file that cannot be read, decoded or
    /// written, a value it refuses, a bad input line (its message names the
    /// file).
    Library(envmap_render::Error),
    /// The command's own: a flag's value out of range, two flags that
    /// disagree, standard input or output that cannot be used.
    Command(String),
}

impl Failure {
    /// The process's exit status for this failure (see [`EXIT_STATUS`]).
    fn exit_status(&self) -> u8 {
        match self {
            Failure::Library(_) | Failure::Command(_) => 1,
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Library(e) => e.fmt(f),
            Failure::Command(m) => f.write_str(m),
        }
    }
}

impl From<envmap_render::Error> for Failure {
    fn from(e: envmap_render::Error) -> Self {
        Failure::Library(e)
    }
}

impl From<String> for Failure {
    fn from(m: String) -> Self {
        Failure::Command(m)
    }
}

impl From<&str> for Failure {
    fn from(m: &str) -> Self {
        Failure::Command(m.to_owned())
    }
}

/// The exit codes, as `--help` prints them.
const EXIT_STATUS: &str = "Exit status: 0 success; 1 an error while running (a file that \
cannot be read, decoded or written, an image above the size limit or fitting no layout, a bad \
input line); 2 a usage error (an unknown command, flag or value); 130 interrupted by SIGINT \
(Ctrl-C), 143 by SIGTERM, with every temporary file removed and nothing written. Errors are one \
line on standard error, naming the file and the problem.";

#[derive(Parser)]
#[command(
    name = "envmap",
    version,
    about = "Environment maps: convert between every representation, inspect, map directions.",
    long_about = None,
    after_help = EXIT_STATUS
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Convert an environment map into another representation.
    ///
    /// Example: envmap convert studio.hdr studio_cube.exr --to cube --layout cross --size 1024
    Convert(convert::ConvertArgs),
    /// Describe an environment map file: size, format, representation, radiance.
    Info(info::InfoArgs),
    /// Map directions (one `x y z` or `x,y,z` per line) to `chart,u,v` (CSV).
    Map(map::MapArgs),
    /// Map `chart,u,v` lines (as `map` prints them) back to unit directions `x,y,z`.
    Unmap(map::UnmapArgs),
    /// Every representation of the built-in sky, a mirror teapot in each, error maps and a report.
    ///
    /// Example: envmap demo --out envmap-demo
    Demo(demo::DemoArgs),
    /// Bake image-based lighting: a GGX-prefiltered specular chain, irradiance, SH9 and the DFG table.
    ///
    /// Example: envmap bake studio.hdr --out studio-ibl
    Bake(bake::BakeArgs),
    /// Render a mirror object (teapot, sphere, torus) in an environment.
    ///
    /// Example: envmap render teapot.png --env sky --mapping latlong --mode per-vertex
    Render(render::RenderArgs),
}

/// Runs the `envmap` command on the process's arguments: parses them
/// (printing usage and exiting 2 on a usage error), runs the subcommand, and
/// prints an error as one line on standard error (exit status 1). SIGINT
/// and SIGTERM stop the work at its next safe point with nothing left
/// behind (exit status 130 and 143; see `docs/cli.md`).
#[must_use]
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let signals = Signals::install();
    let stop = signals.flag();
    let result = match cli.command {
        Command::Convert(a) => convert::run(&a, stop),
        Command::Info(a) => info::run(&a, stop),
        Command::Map(a) => map::run_map(&a, stop),
        Command::Unmap(a) => map::run_unmap(&a, stop),
        Command::Render(a) => render::run(&a, stop),
        Command::Bake(a) => bake::run(&a, stop),
        Command::Demo(a) => demo::run(&a, stop),
    };
    if let Some(status) = signals.exit_status() {
        match result {
            Ok(()) => {
                note!("envmap: interrupted after the work had finished: every output was written")
            }
            Err(_) => note!("envmap: interrupted: nothing written"),
        }
        return ExitCode::from(status);
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            note!("envmap: error: {e}");
            ExitCode::from(e.exit_status())
        }
    }
}
