//! `envmap map` and `envmap unmap`: directions to chart points and back,
//! one line each (see [`crate::text`]).

use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::mpsc;
use std::time::Duration;

use clap::Args;
use envmap_core::{AnyMapping, Frame, Mapping};

use crate::args::{
    output_size, parse_convention, parse_fov, parse_layout, parse_lens, parse_mapping, parse_world,
    with_lens, CliResult,
};
use crate::text::{MapLines, UnmapLines};
use envmap_render::cancel;
use envmap_render::image::Layout;
use envmap_render::image::Representation;
use envmap_render::image::{Convention, World};
use envmap_render::Error;

#[derive(Args)]
pub(crate) struct MapArgs {
    /// The mapping.
    #[arg(long, value_parser = parse_mapping)]
    pub(crate) mapping: AnyMapping,
    /// Field of view of each lens of a fisheye, in degrees (default 180).
    #[arg(long, value_parser = parse_fov)]
    pub(crate) fov: Option<f64>,
    /// Lens law of a fisheye: equidistant (the default) or equisolid.
    #[arg(long, value_parser = parse_lens)]
    pub(crate) lens: Option<envmap_core::Lens>,
    /// The world of the directions read: y-up (the GL world: the mapping as its files use it, so GL's vectors give GL's cube face), y-up-lh, or z-up (envmap's canonical frame: the mapping's formula on the directions as given).
    #[arg(long, value_parser = parse_world, default_value = "y-up")]
    pub(crate) frame: World,
    /// File conventions of the mapping (see `envmap convert --help`).
    #[arg(long, value_parser = parse_convention, default_value = "envmap")]
    pub(crate) convention: Convention,
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
    /// Field of view of each lens of a fisheye, in degrees (default 180).
    #[arg(long, value_parser = parse_fov)]
    pub(crate) fov: Option<f64>,
    /// Lens law of a fisheye: equidistant (the default) or equisolid.
    #[arg(long, value_parser = parse_lens)]
    pub(crate) lens: Option<envmap_core::Lens>,
    /// The world of the directions printed (as `map --frame`).
    #[arg(long, value_parser = parse_world, default_value = "y-up")]
    pub(crate) frame: World,
    /// File conventions of the mapping (see `envmap convert --help`).
    #[arg(long, value_parser = parse_convention, default_value = "envmap")]
    pub(crate) convention: Convention,
    /// Read from this file instead of standard input.
    pub(crate) input: Option<PathBuf>,
}

/// The directions' axes (`world`) → the axes `mapping`'s formula is
/// applied in, as its files in `convention` use it.
fn directions_frame(mapping: AnyMapping, convention: Convention, world: World) -> Frame {
    let file = convention.frame(mapping, world);
    world.frame().then(file.inverse())
}

/// Lines of the input (a file or standard input), with its display name.
/// Standard input is read on a thread of its own, so that a signal stops
/// the command even while it waits for input (`stop` is polled).
fn read_lines(
    input: Option<&Path>,
    stop: &AtomicBool,
) -> Result<(String, Vec<String>), crate::Failure> {
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
            let (tx, rx) = mpsc::channel();
            std::thread::spawn(move || {
                let read: Result<Vec<String>, String> = std::io::stdin()
                    .lock()
                    .lines()
                    .map(|l| l.map_err(|e| format!("<stdin>: cannot read: {e}")))
                    .collect();
                let _ = tx.send(read);
            });
            loop {
                if cancel::is_set(Some(stop)) {
                    return Err(Error::Cancelled.into());
                }
                match rx.recv_timeout(Duration::from_millis(20)) {
                    Ok(lines) => return Ok(("<stdin>".to_owned(), lines?)),
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        return Err("<stdin>: cannot read: the reader stopped".into())
                    }
                }
            }
        }
    }
}

pub(crate) fn run_map(a: &MapArgs, stop: &AtomicBool) -> CliResult {
    let mapping = with_lens(a.mapping, a.lens, a.fov, "--fov and --lens")?;
    let (name, lines) = read_lines(a.input.as_deref(), stop)?;
    let atlas = match a.layout {
        Some(l) if !Layout::for_mapping(mapping).contains(&l) || l.is_six_files() => {
            return Err(format!(
                "--layout {}: not a single-image layout of {}",
                l.name(),
                mapping
            )
            .into());
        }
        Some(l) => l.atlas(),
        None => mapping.atlas(),
    };
    let size = match a.size {
        Some(n) => {
            let repr = Representation::new(mapping, atlas, Frame::IDENTITY)?;
            Some(output_size(&repr, n)?)
        }
        None => None,
    };
    let parser = MapLines::new(
        mapping,
        directions_frame(mapping, a.convention, a.frame),
        atlas,
        size,
    );
    write_rows(&name, &lines, parser.header(), |l| parser.line(l), stop)
}

pub(crate) fn run_unmap(a: &UnmapArgs, stop: &AtomicBool) -> CliResult {
    let mapping = with_lens(a.mapping, a.lens, a.fov, "--fov and --lens")?;
    let (name, lines) = read_lines(a.input.as_deref(), stop)?;
    let parser = UnmapLines::new(mapping, directions_frame(mapping, a.convention, a.frame));
    write_rows(&name, &lines, parser.header(), |l| parser.line(l), stop)
}

/// Prints `header`, then the row of each line that gives one; stops at the
/// first bad line with an error naming it (`<name>:<line>: ...`). The rows
/// are printed once all are made, so that an error or a signal (`stop`,
/// polled every 4096 lines) leaves standard output empty.
fn write_rows(
    name: &str,
    lines: &[String],
    header: &str,
    row: impl Fn(&str) -> envmap_render::Result<Option<String>>,
    stop: &AtomicBool,
) -> CliResult {
    let mut text = String::with_capacity(32 * lines.len() + header.len() + 1);
    text.push_str(header);
    text.push('\n');
    for (k, line) in lines.iter().enumerate() {
        if k % 4096 == 0 && cancel::is_set(Some(stop)) {
            return Err(Error::Cancelled.into());
        }
        match row(line) {
            Ok(Some(r)) => {
                text.push_str(&r);
                text.push('\n');
            }
            Ok(None) => {}
            Err(e) => return Err(format!("{name}:{}: {e}", k + 1).into()),
        }
    }
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let io = |e: std::io::Error| format!("<stdout>: {e}");
    out.write_all(text.as_bytes()).map_err(io)?;
    Ok(out.flush().map_err(io)?)
}
