//! envmap against ffmpeg's `v360` filter on one job, side by side: a
//! 4096 × 2048 float equirect (a smooth sky and a sun 0.5° wide, peak
//! 50 000) converted to the equi-angular cube map with 1024 × 1024 faces,
//! in v360's `eac` file (3076 × 2056 texels, float OpenEXR, uncompressed).
//! Each route runs as a whole process (reading the file, converting,
//! writing), the routes alternating, `--rounds` times:
//!
//! * **envmap**: `envmap convert IN OUT --to eac --size 1024` (its defaults:
//!   bilinear, sub-samples chosen from the size ratio, every core);
//! * **ffmpeg PQ**: v360 with Lanczos between `zscale` conversions to PQ in
//!   16 bits and back (v360 takes integer pixels only; PQ keeps a range of
//!   linear values up to `10 000 / npl` in them); `npl = 10 000 / (2 ·
//!   peak)` puts the input's peak at half of PQ's range, room for the
//!   Lanczos kernel's overshoot;
//! * **ffmpeg naive**: v360 with Lanczos on the float input as ffmpeg
//!   converts it by itself (to 16-bit integers: everything above 1.0 is
//!   clipped).
//!
//! For each: the median wall time of a whole process, its peak resident
//! memory (from GNU time's `-v`; `n/a` where `/usr/bin/time` is missing),
//! the largest value written, and the energy kept: each output read by
//! envmap and integrated over the sphere (luminance × each texel's exact
//! solid angle), against the input's integral, over the whole sphere and
//! for the sun alone (the texels within 5° of the sun, less the analytic
//! sky at each). The result is a Markdown table, with the machine's cores,
//! CPU and load average beside it: the times depend on the machine and on
//! what else it runs.
//!
//! ```text
//! cargo build --release -p envmap-cli
//! cargo run --release -p envmap-bench --bin envmap-v360 [-- --rounds N --envmap PATH --dir DIR --keep]
//! ```
//!
//! The `envmap` binary is the one beside this program (both built with
//! `--release` and default features: `target/release/envmap`) unless
//! `--envmap` names another. ffmpeg must be on `PATH` and have `zscale`
//! (built with libzimg, as Debian's is: `apt-get install ffmpeg`).
#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use clap::Parser;
use envmap_bench::timing::median;
use envmap_core::glam::Vec3;
use envmap_core::texel::texel_center;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_render::image::{
    load, luminance, save, EnvImage, Layout, LoadOptions, Representation, SaveOptions,
};
use envmap_render::scene::{direction_from_angles, fill};

/// Convert one 4096 × 2048 HDR equirect to EAC 1024 with envmap and with
/// ffmpeg's v360 (two ways): time, peak memory and energy kept, as a
/// Markdown table.
///
/// Build both in release with default features first: `cargo build
/// --release -p envmap-cli`; then `cargo run --release -p envmap-bench
/// --bin envmap-v360`. The times are this machine's, under whatever else it
/// runs: the table is printed with its core count, CPU and load average.
#[derive(Parser, Debug)]
#[command(name = "envmap-v360", version)]
struct Args {
    /// Rounds: each runs the three routes once, one after another.
    #[arg(long, default_value_t = 3)]
    rounds: usize,
    /// The `envmap` command to time (default: `envmap` beside this program).
    #[arg(long, value_name = "PATH")]
    envmap: Option<PathBuf>,
    /// Working directory for the input and outputs (default: a new directory
    /// in the system's temporary directory, removed at the end).
    #[arg(long, value_name = "DIR")]
    dir: Option<PathBuf>,
    /// Keep the working directory's files.
    #[arg(long)]
    keep: bool,
}

/// Input size (equirect) and output face edge.
const IN_W: u32 = 4096;
const IN_H: u32 = 2048;
const FACE: u32 = 1024;
/// v360's `eac` file for FACE × FACE faces: 3N + 4 by 2N + 8.
const OUT_W: u32 = 3 * FACE + 4;
const OUT_H: u32 = 2 * FACE + 8;
/// The sun: peak radiance, full width at half maximum (degrees) of its
/// Gaussian profile, and its direction (elevation, azimuth in degrees,
/// well inside one cube face).
const SUN_PEAK: f32 = 50_000.0;
const SUN_FWHM_DEG: f32 = 0.5;
const SUN_ELEVATION_DEG: f32 = 20.0;
const SUN_AZIMUTH_DEG: f32 = 25.0;
/// The sun's energy is counted within this angle of its direction.
const SUN_RING_DEG: f32 = 5.0;

fn sun_direction() -> Vec3 {
    direction_from_angles(SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG).normalize()
}

/// The smooth sky along `d` (canonical axes, z up; no sun): a gradient from
/// the ground through a bright horizon to a blue zenith, brighter towards
/// the sun; between about 0.3 and 3, so the naive route clips part of it.
fn sky(d: Vec3) -> [f32; 3] {
    let d = d.normalize();
    let z = d.z;
    let horizon = (-(z / 0.3) * (z / 0.3)).exp();
    let towards_sun = 0.5 + 0.5 * d.dot(sun_direction());
    let base = [0.5 - 0.2 * z, 0.7 - 0.1 * z, 1.1 + 0.4 * z];
    let glow = [1.2, 1.0, 0.8];
    let side = [0.9, 0.7, 0.4];
    std::array::from_fn(|c| base[c] + glow[c] * horizon + side[c] * towards_sun * towards_sun)
}

/// The sun alone along `d`: a Gaussian of the angle to its direction.
fn sun(d: Vec3) -> f32 {
    let sigma = SUN_FWHM_DEG.to_radians() / (2.0 * (2.0 * 2f32.ln()).sqrt());
    let cos = d.normalize().dot(sun_direction()).clamp(-1.0, 1.0);
    // 1 − cos = 2 sin²(θ/2): an angle accurate near 0.
    let theta = 2.0 * ((0.5 * (1.0 - cos)).sqrt()).asin();
    SUN_PEAK * (-0.5 * (theta / sigma) * (theta / sigma)).exp()
}

fn radiance(d: Vec3) -> [f32; 3] {
    let s = sun(d);
    sky(d).map(|c| c + s)
}

/// One texel's true direction (canonical axes).
fn direction(img: &EnvImage, chart: u32, i: u32, j: u32) -> Vec3 {
    let (w, h) = img.cell_size();
    let repr = img.representation();
    let c = ChartUv::new(chart, texel_center(i, w), texel_center(j, h));
    repr.frame
        .to_canonical(repr.mapping.inverse(c).unwrap_or(Vec3::Z))
        .normalize()
}

/// The luminance integrated over the sphere (each texel × its exact solid
/// angle), and the sun's part: over the texels within [`SUN_RING_DEG`] of
/// the sun, the luminance less the analytic sky's.
fn energy(img: &EnvImage) -> (f64, f64) {
    let m = img.mapping();
    let (w, h) = img.cell_size();
    let ring = SUN_RING_DEG.to_radians().cos();
    let s = sun_direction();
    let (mut total, mut sun) = (0.0f64, 0.0f64);
    for chart in 0..m.chart_count() {
        for j in 0..h {
            for i in 0..w {
                let omega = m.texel_solid_angle(chart, i, j, w, h);
                let y = f64::from(luminance(img.chart_texel(chart, i, j).unwrap_or_default()));
                total += omega * y;
                let d = direction(img, chart, i, j);
                if d.dot(s) >= ring {
                    sun += omega * (y - f64::from(luminance(sky(d))));
                }
            }
        }
    }
    (total, sun)
}

/// One route: its name and the command it runs.
struct Route {
    name: &'static str,
    output: &'static str,
    program: PathBuf,
    args: Vec<String>,
    /// How the output is read: v360's files need the mapping and layout
    /// named; envmap's say them.
    named: bool,
}

/// One run's wall time (s) and peak resident memory (kB), if measured.
fn run(route: &Route, dir: &Path, gnu_time: bool) -> Result<(f64, Option<u64>), String> {
    let report = dir.join("time.txt");
    let mut cmd = if gnu_time {
        let mut c = Command::new("/usr/bin/time");
        c.arg("-v").arg("-o").arg(&report).arg(&route.program);
        c
    } else {
        Command::new(&route.program)
    };
    cmd.args(&route.args).current_dir(dir);
    let start = Instant::now();
    let out = cmd
        .output()
        .map_err(|e| format!("{}: {e}", route.program.display()))?;
    let wall = start.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(format!(
            "{} failed ({}): {}",
            route.name,
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let rss = if gnu_time {
        let text = std::fs::read_to_string(&report).map_err(|e| e.to_string())?;
        let kb = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("Maximum resident set size (kbytes):"))
            .and_then(|v| v.trim().parse().ok())
            .ok_or("no maximum resident set size in GNU time's report")?;
        Some(kb)
    } else {
        None
    };
    Ok((wall, rss))
}

/// A line about the machine: cores, CPU, load average.
fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines().find_map(|l| {
                l.strip_prefix("model name")
                    .map(|m| m.trim_start_matches([' ', '\t', ':']).to_string())
            })
        })
        .unwrap_or_else(|| "unknown CPU".into());
    format!("{cores} cores, {cpu}, load average {}", load_average())
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn main() -> ExitCode {
    match real_main() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("envmap-v360: {e}");
            ExitCode::FAILURE
        }
    }
}

fn real_main() -> Result<(), String> {
    let args = Args::parse();
    if args.rounds == 0 {
        return Err("--rounds must be at least 1".into());
    }
    let envmap = match args.envmap {
        Some(p) => p,
        None => std::env::current_exe()
            .map_err(|e| e.to_string())?
            .with_file_name(format!("envmap{}", std::env::consts::EXE_SUFFIX)),
    };
    if !envmap.is_file() {
        return Err(format!(
            "no envmap command at {}: build it with `cargo build --release -p envmap-cli`, or name one with --envmap",
            envmap.display()
        ));
    }
    let ffmpeg_version = Command::new("ffmpeg")
        .arg("-version")
        .output()
        .map_err(|e| format!("ffmpeg is not on PATH ({e}): apt-get install ffmpeg"))?;
    let ffmpeg_version = String::from_utf8_lossy(&ffmpeg_version.stdout)
        .lines()
        .next()
        .unwrap_or("ffmpeg")
        .to_string();
    let gnu_time = Path::new("/usr/bin/time").is_file();
    let (dir, made_dir) = match args.dir {
        Some(d) => (d, false),
        None => (
            std::env::temp_dir().join(format!("envmap-v360-{}", std::process::id())),
            true,
        ),
    };
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;

    println!("machine: {}", machine());
    println!("envmap: {}", envmap.display());
    println!("{ffmpeg_version}");
    eprintln!("making the {IN_W}×{IN_H} input ...");
    let latlong = Representation::for_file(AnyMapping::LatLong, Default::default());
    let input = fill(latlong, IN_W, IN_H, radiance).map_err(|e| e.to_string())?;
    save(&input, dir.join("in.exr"), &SaveOptions::default()).map_err(|e| e.to_string())?;
    let peak = input.stats().max.into_iter().fold(0.0f32, f32::max);
    let (in_total, in_sun) = energy(&input);
    // PQ's top, 10 000 nits, stands for linear 10 000 / npl: twice the peak.
    let npl = 10_000.0 / (2.0 * f64::from(peak));
    println!(
        "input: {IN_W}×{IN_H} float equirect, peak {peak:.0}; integral of luminance {in_total:.4}, \
         the sun's part (within {SUN_RING_DEG}° of it, less the sky) {in_sun:.4}; npl = {npl:.6}"
    );
    drop(input);

    let v360 = format!("v360=input=e:output=eac:interp=lanczos:w={OUT_W}:h={OUT_H}");
    let pq = format!(
        "zscale=tin=linear:t=smpte2084:npl={npl:.6}:d=none,format=gbrp16le,{v360},\
         zscale=tin=smpte2084:t=linear:npl={npl:.6}:d=none,format=gbrpf32le"
    );
    let ffmpeg_args = |filter: &str, output: &str| -> Vec<String> {
        [
            "-hide_banner",
            "-loglevel",
            "error",
            "-y",
            "-i",
            "in.exr",
            "-vf",
            filter,
            "-frames:v",
            "1",
            "-c:v",
            "exr",
            "-format",
            "float",
            "-compression",
            "none",
            output,
        ]
        .map(String::from)
        .to_vec()
    };
    let routes = [
        Route {
            name: "envmap convert --to eac --size 1024",
            output: "envmap.exr",
            program: envmap,
            args: [
                "convert",
                "in.exr",
                "envmap.exr",
                "--to",
                "eac",
                "--size",
                "1024",
                "-q",
            ]
            .map(String::from)
            .to_vec(),
            named: false,
        },
        Route {
            name: "ffmpeg v360 lanczos, PQ through zscale",
            output: "pq.exr",
            program: "ffmpeg".into(),
            args: ffmpeg_args(&pq, "pq.exr"),
            named: true,
        },
        Route {
            name: "ffmpeg v360 lanczos, naive",
            output: "naive.exr",
            program: "ffmpeg".into(),
            args: ffmpeg_args(&v360, "naive.exr"),
            named: true,
        },
    ];
    for r in &routes {
        println!("{}: {} {}", r.name, r.program.display(), r.args.join(" "));
    }

    let mut walls = vec![Vec::new(); routes.len()];
    let mut rss = vec![None; routes.len()];
    for round in 1..=args.rounds {
        for (k, r) in routes.iter().enumerate() {
            let (wall, kb) = run(r, &dir, gnu_time)?;
            eprintln!(
                "round {round}: {}: {wall:.2} s{} (load average {})",
                r.name,
                kb.map_or(String::new(), |kb| format!(", {} MB", kb / 1024)),
                load_average()
            );
            walls[k].push(wall);
            rss[k] = rss[k].max(kb);
        }
    }

    println!();
    println!(
        "| route | median wall (s) of {} | peak RSS (MB) | largest value | energy kept | sun's energy kept |",
        args.rounds
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (k, r) in routes.iter().enumerate() {
        let mut opts = LoadOptions::default();
        if r.named {
            opts.mapping = Some(AnyMapping::Eac);
            opts.layout = Some(Layout::V360);
        }
        let out = load(dir.join(r.output), &opts).map_err(|e| e.to_string())?;
        if out.mapping() != AnyMapping::Eac || out.cell_size() != (FACE, FACE) {
            return Err(format!(
                "{}: read as {} with {:?} faces, not EAC {FACE}",
                r.output,
                out.mapping(),
                out.cell_size()
            ));
        }
        let largest = out.stats().max.into_iter().fold(0.0f32, f32::max);
        let (total, sun) = energy(&out);
        println!(
            "| {} | {:.2} | {} | {largest:.1} | {:.2} % | {:.2} % |",
            r.name,
            median(&mut walls[k]),
            rss[k].map_or("n/a".into(), |kb| format!("{}", kb / 1024)),
            100.0 * total / in_total,
            100.0 * sun / in_sun
        );
    }
    println!();
    println!(
        "{} round(s), routes alternating, each a whole process (read {IN_W}×{IN_H} EXR, convert, \
         write {OUT_W}×{OUT_H} EXR); machine: {}",
        args.rounds,
        machine()
    );
    if made_dir && !args.keep {
        std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    } else {
        println!("files kept in {}", dir.display());
    }
    Ok(())
}
