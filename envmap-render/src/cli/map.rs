//! `envmap map` and `envmap unmap`: directions to chart points and back,
//! one line each (see [`crate::cli::text`]).

use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use envmap_core::{AnyMapping, Frame, Mapping};

use crate::cli::args::{output_size, parse_frame, parse_layout, parse_mapping, CliResult};
use crate::cli::text::{MapLines, UnmapLines};
use crate::image::layout::Layout;
use crate::image::Representation;

#[derive(Args)]
pub(crate) struct MapArgs {
    /// The mapping.
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) mapping: AnyMapping,
    /// Axis convention of the input directions.
    #[arg(long, value_parser = parse_frame, default_value = "z-up")]
    pub(crate) frame: Frame,
    /// Also print the texel x,y in an atlas of this size (cube: face edge; others: width).
    #[arg(long)]
    pub(crate) size: Option<u32>,
    /// Atlas layout for --size (default: the mapping's own).
    #[arg(long, value_parser = parse_layout)]
    pub(crate) layout: Option<Layout>,
    /// Read from this file instead of standard input.
    pub(crate) input: Option<PathBuf>,
}

#[derive(Args)]
pub(crate) struct UnmapArgs {
    /// The mapping.
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) mapping: AnyMapping,
    /// Axis convention of the output directions.
    #[arg(long, value_parser = parse_frame, default_value = "z-up")]
    pub(crate) frame: Frame,
    /// Read from this file instead of standard input.
    pub(crate) input: Option<PathBuf>,
}

/// Lines of the input (a file or standard input), with its display name.
fn read_lines(input: Option<&Path>) -> Result<(String, Vec<String>), String> {
    match input {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("{}: cannot read: {e}", p.display()))?;
            Ok((
                p.display().to_string(),
                text.lines().map(str::to_owned).collect(),
            ))
        }
        None => {
            let mut lines = Vec::new();
            for l in std::io::stdin().lock().lines() {
                lines.push(l.map_err(|e| format!("<stdin>: cannot read: {e}"))?);
            }
            Ok(("<stdin>".to_owned(), lines))
        }
    }
}

pub(crate) fn run_map(a: &MapArgs) -> CliResult {
    let (name, lines) = read_lines(a.input.as_deref())?;
    let atlas = match a.layout {
        Some(l) if !Layout::for_mapping(a.mapping).contains(&l) || l.is_six_files() => {
            return Err(format!(
                "--layout {}: not a single-image layout of {}",
                l.name(),
                a.mapping
            ));
        }
        Some(l) => l.atlas(),
        None => a.mapping.atlas(),
    };
    let size = match a.size {
        Some(n) => {
            let repr = Representation::new(a.mapping, atlas, a.frame).map_err(|e| e.to_string())?;
            Some(output_size(&repr, n)?)
        }
        None => None,
    };
    let parser = MapLines::new(a.mapping, a.frame, atlas, size);
    write_rows(&name, &lines, parser.header(), |l| parser.line(l))
}

pub(crate) fn run_unmap(a: &UnmapArgs) -> CliResult {
    let (name, lines) = read_lines(a.input.as_deref())?;
    let parser = UnmapLines::new(a.mapping, a.frame);
    write_rows(&name, &lines, parser.header(), |l| parser.line(l))
}

/// Prints `header`, then the row of each line that gives one; stops at the
/// first bad line with an error naming it (`<name>:<line>: ...`).
fn write_rows(
    name: &str,
    lines: &[String],
    header: &str,
    row: impl Fn(&str) -> crate::Result<Option<String>>,
) -> CliResult {
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let io = |e: std::io::Error| format!("<stdout>: {e}");
    writeln!(out, "{header}").map_err(io)?;
    for (k, line) in lines.iter().enumerate() {
        match row(line) {
            Ok(Some(r)) => writeln!(out, "{r}").map_err(io)?,
            Ok(None) => {}
            Err(e) => return Err(format!("{name}:{}: {e}", k + 1)),
        }
    }
    out.flush().map_err(io)
}
