//! The specular bake on real HDRIs, measured against the oracle of the input
//! itself ([`Oracle`]: the map as loaded, piecewise constant over its own
//! texels): the four committed CC0 HDRIs (`test-data/hdri`, 512 × 256 DWAB
//! half EXR, suns and the negative ringing lossy compression leaves around
//! them) baked at a CI size and at 64² meet the project's targets (relative
//! RMS ≤ 1 %, |bias| ≤ 0.2 % at every level above 0), their energy adds up
//! (input = base cube + split texels), a made-up sun ringing as DWAB rings is
//! baked without bias with its ring split out; and the ignored test
//! `full_set_within_target`: every `*.exr` in a directory meets the same
//! targets at 128² and 512² (`ENVMAP_REAL_HDRIS=DIR`, default `target/hdri`,
//! where `scripts/fetch-hdris.sh` puts the 18; a missing or empty directory
//! fails it). CI runs it on the four committed ones.
//!
//! ```text
//! cargo test --release -p envmap-render --test real_hdri -- --nocapture
//! scripts/fetch-hdris.sh && cargo test --release -p envmap-render --test real_hdri -- --ignored --nocapture
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;
use envmap_render::filter::bake::{
    bake, measure_irradiance, measure_level, specular_chain, BakeOptions, SpecularChain,
};
use envmap_render::filter::sh::IrradianceScale;
use envmap_render::filter::weights::TexelWeights;
use envmap_render::image::{load, LoadOptions, NonFinite};
use envmap_render::image::{EnvImage, Representation};
use envmap_render::instruments::Oracle;
use envmap_render::scene::fill;

/// The project's target for every level above 0: relative RMS error
/// against the oracle.
const MAX_RMS: f64 = 0.01;
/// The project's target for every level above 0: |bias| against the oracle.
const MAX_BIAS: f64 = 0.002;
/// The committed HDRIs, by name.
const COMMITTED: [&str; 4] = ["sky", "park", "studio", "venice"];

/// The path of the committed HDRI `name`.
fn committed_path(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../test-data/hdri")).join(format!("{name}.exr"))
}

/// Loads `path` as the bake's command does (NaN and infinite texels black).
fn load_hdri(path: &Path) -> EnvImage {
    load(path, &{
        let mut o = LoadOptions::default();
        o.non_finite = NonFinite::Zero;
        o
    })
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The specular chain of `src` at level-0 face `size`, the other options
/// the defaults.
fn chain(src: &EnvImage, size: u32) -> SpecularChain {
    specular_chain(
        src,
        &{
            let mut o = BakeOptions::default();
            o.size = size;
            o
        },
        &|_, _| {},
    )
    .unwrap_or_else(|e| panic!("bake at {size}: {e}"))
}

/// One level measured against the oracle.
#[derive(Clone, Debug)]
struct Row {
    name: String,
    size0: u32,
    level: usize,
    face: u32,
    roughness: f32,
    method: &'static str,
    samples: u32,
    rms: f64,
    bias: f64,
    oracle_s: f64,
}

impl Row {
    /// Whether the level meets the targets.
    fn ok(&self) -> bool {
        self.rms <= MAX_RMS && self.bias.abs() <= MAX_BIAS
    }
}

/// Bakes `src` at `size`, measures every level above 0 against `oracle` on
/// `texels` texels (seed: the level's index), prints a table and returns
/// its rows.
fn measure_chain(name: &str, src: &EnvImage, oracle: &Oracle, size: u32, texels: u32) -> Vec<Row> {
    let t = Instant::now();
    let c = chain(src, size);
    let bake_s = t.elapsed().as_secs_f64();
    let sizes: Vec<u32> = c.reports.iter().map(|r| r.size).collect();
    use std::fmt::Write;
    // One print per chain, so that tests running at once do not interleave.
    let mut out = String::new();
    writeln!(
        out,
        "{name} at {size}: chain {sizes:?}, base {}², {} bright texels ({:.2} % of the energy), gap {:.2e}, bake {bake_s:.2} s",
        c.base_size,
        c.bright.texels,
        100.0 * c.bright.energy_share,
        c.energy.gap(),
    )
    .unwrap();
    writeln!(out, "| file | size | level | face | roughness | method | samples | rel. RMS | bias | oracle (s) | |").unwrap();
    writeln!(
        out,
        "| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | --- |"
    )
    .unwrap();
    let mut rows = Vec::new();
    for (k, (img, rep)) in c.levels.iter().zip(&c.reports).enumerate() {
        if rep.roughness <= 0.0 {
            continue;
        }
        let m = measure_level(oracle, rep.roughness, img, texels, k as u32)
            .unwrap_or_else(|e| panic!("{name} {size} level {k}: {e}"));
        let row = Row {
            name: name.to_owned(),
            size0: size,
            level: k,
            face: rep.size,
            roughness: rep.roughness,
            method: rep.method,
            samples: rep.samples,
            rms: m.relative_rms,
            bias: m.bias,
            oracle_s: m.seconds,
        };
        writeln!(
            out,
            "| {name} | {size} | {k} | {} | {:.3} | {} | {} | {:.3} % | {:+.3} % | {:.2} | {} |",
            row.face,
            row.roughness,
            row.method,
            row.samples,
            100.0 * row.rms,
            100.0 * row.bias,
            row.oracle_s,
            if row.ok() { "" } else { "MISS" },
        )
        .unwrap();
        rows.push(row);
    }
    print!("{out}");
    rows
}

/// Panics listing every row that misses the targets.
fn assert_within_target(rows: &[Row]) {
    let misses: Vec<String> = rows
        .iter()
        .filter(|r| !r.ok())
        .map(|r| {
            format!(
                "{} at {}: level {} ({}², roughness {:.3}, {}): {:.3} % RMS, {:+.3} % bias",
                r.name,
                r.size0,
                r.level,
                r.face,
                r.roughness,
                r.method,
                100.0 * r.rms,
                100.0 * r.bias
            )
        })
        .collect();
    assert!(
        misses.is_empty(),
        "{} of {} levels miss the target ({} % RMS, {} % bias):\n{}",
        misses.len(),
        rows.len(),
        100.0 * MAX_RMS,
        100.0 * MAX_BIAS,
        misses.join("\n")
    );
}

#[test]
fn committed_real_hdris_bake_within_target() {
    let t = Instant::now();
    let mut rows = Vec::new();
    for name in COMMITTED {
        let src = load_hdri(&committed_path(name));
        let oracle = Oracle::new(&src);
        for size in [32, 64] {
            rows.extend(measure_chain(name, &src, &oracle, size, 256));
        }
    }
    println!(
        "committed HDRIs: {} levels measured in {:.1} s",
        rows.len(),
        t.elapsed().as_secs_f64()
    );
    assert_within_target(&rows);
}

#[test]
fn energy_adds_up() {
    for name in COMMITTED {
        let src = load_hdri(&committed_path(name));
        let c = chain(&src, 64);
        let e = &c.energy;
        let share = e.negative_share();
        println!(
            "{name}: input {:?}, base {:?}, split {:?}, gap {:.2e} (footprint {}×{}); negative share R {:.4} % G {:.4} % B {:.4} %; {} bright texels (threshold {})",
            e.input,
            e.base,
            e.split,
            e.gap(),
            e.footprint_samples,
            e.footprint_samples,
            100.0 * share[0],
            100.0 * share[1],
            100.0 * share[2],
            c.bright.texels,
            c.bright.threshold,
        );
        assert!(e.gap() <= 1e-3, "{name}: gap {:.3e}", e.gap());
        if name == "park" {
            assert!(share[2] > 0.0, "park: blue negative share {}", share[2]);
        }
        if matches!(name, "sky" | "park") {
            assert!(c.bright.texels > 0, "{name}: no bright texels split");
        }
    }
}

/// What each texel of [`ringing_sun`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    Sky,
    Sun,
    /// Just outside the sun: negative blue.
    Trough,
    /// Outside the trough: positive blue overshoot.
    Overshoot,
}

/// The sun's direction in [`ringing_sun`].
fn sun_dir() -> Vec3 {
    Vec3::new(0.3, -0.5, 0.8).normalize()
}

/// The part of the ringing sun at direction `d`: the sun within 1°, the
/// trough out to 1.8°, the overshoot out to 2.6°.
fn part(d: Vec3) -> Part {
    let a = d
        .normalize()
        .dot(sun_dir())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    match a {
        a if a <= 1.0 => Part::Sun,
        a if a <= 1.8 => Part::Trough,
        a if a <= 2.6 => Part::Overshoot,
        _ => Part::Sky,
    }
}

/// The smooth sky under the sun: 0.5 + 0.3·z per channel.
fn sky(d: Vec3) -> [f32; 3] {
    [0.5 + 0.3 * d.z; 3]
}

/// Blue in the trough (as DWAB rings).
const TROUGH: f32 = -800.0;
/// The sun's radiance (added to the sky).
const SUN: f32 = 5000.0;

/// A 512 × 256 latlong of a smooth sky with a 1° sun of radiance 5000 and,
/// around it, a ring of negative blue (−800) and then of positive blue
/// chosen so that the ring integrates to zero in blue over the texels'
/// exact solid angles. Returns the map, each texel's part (row by row) and
/// the overshoot's blue.
fn ringing_sun() -> (EnvImage, Vec<Part>, f32) {
    let repr = Representation::default_for(AnyMapping::LatLong);
    let (w, h) = (512, 256);
    // First the parts, then the overshoot that cancels the trough.
    let code = |p: Part| p as u8 as f32;
    let parts: Vec<Part> = fill(repr, w, h, |d| [code(part(d)); 3])
        .unwrap()
        .pixels()
        .iter()
        .map(|p| match p[0] as u8 {
            1 => Part::Sun,
            2 => Part::Trough,
            3 => Part::Overshoot,
            _ => Part::Sky,
        })
        .collect();
    let weights = TexelWeights::new(AnyMapping::LatLong, w, h);
    let omega = |want: Part| -> f64 {
        parts
            .iter()
            .enumerate()
            .filter(|(_, &p)| p == want)
            .map(|(k, _)| weights.get(0, k as u32 % w, k as u32 / w))
            .sum()
    };
    let overshoot = (-f64::from(TROUGH) * omega(Part::Trough) / omega(Part::Overshoot)) as f32;
    let img = fill(repr, w, h, |d| {
        let s = sky(d);
        match part(d) {
            Part::Sky => s,
            Part::Sun => s.map(|v| v + SUN),
            Part::Trough => [s[0], s[1], TROUGH],
            Part::Overshoot => [s[0], s[1], overshoot],
        }
    })
    .unwrap();
    (img, parts, overshoot)
}

#[test]
fn a_ringing_sun_is_baked_without_bias() {
    let (src, parts, overshoot) = ringing_sun();
    let count = |want: Part| parts.iter().filter(|&&p| p == want).count() as u64;
    let (sun, trough, over) = (
        count(Part::Sun),
        count(Part::Trough),
        count(Part::Overshoot),
    );
    // Σ Ω·L per channel over the sun's texels and over the whole ring's.
    let w = TexelWeights::new(AnyMapping::LatLong, src.width(), src.height());
    let mut sun_energy = [0.0f64; 3];
    let mut ring_energy = [0.0f64; 3];
    for (k, (p, l)) in parts.iter().zip(src.pixels()).enumerate() {
        let o = w.get(0, k as u32 % src.width(), k as u32 / src.width());
        let acc = match p {
            Part::Sun => &mut sun_energy,
            Part::Trough | Part::Overshoot => &mut ring_energy,
            Part::Sky => continue,
        };
        for c in 0..3 {
            acc[c] += o * f64::from(l[c]);
        }
    }
    println!(
        "ringing sun: {sun} sun texels, {trough} trough texels (blue {TROUGH}), {over} overshoot texels (blue {overshoot:.1}); sun energy {sun_energy:?}, ring energy {ring_energy:?}"
    );
    assert!(
        ring_energy[2].abs() < 1e-6 * sun_energy[2],
        "the ring does not cancel: {ring_energy:?}"
    );

    let oracle = Oracle::new(&src);
    let rows = measure_chain("ringing sun", &src, &oracle, 64, 256);

    // The split took the sun and the whole ring, negative texels included,
    // and nothing else: the ring cancels in the split as in the data.
    let c = chain(&src, 64);
    let b = &c.bright;
    println!(
        "split: {} texels ({} points), threshold {}, energy {:?} (sun + ring {:?})",
        b.texels,
        b.points,
        b.threshold,
        b.energy,
        core::array::from_fn::<f64, 3, _>(|k| sun_energy[k] + ring_energy[k]),
    );
    assert!(
        b.texels > sun,
        "split {} texels, the sun alone {sun}",
        b.texels
    );
    assert!(
        b.threshold < -TROUGH,
        "threshold {} above the trough",
        b.threshold
    );
    assert_eq!(
        b.texels,
        sun + trough + over,
        "the split is not the sun and its ring"
    );
    for k in 0..3 {
        let want = sun_energy[k] + ring_energy[k];
        assert!(
            (b.energy[k] - want).abs() <= 1e-4 * sun_energy[k],
            "channel {k}: split energy {} against {want}",
            b.energy[k]
        );
    }
    assert!(c.energy.gap() <= 1e-3, "gap {:.3e}", c.energy.gap());
    assert_within_target(&rows);
}

#[test]
#[ignore = "needs the 18 fetched HDRIs (scripts/fetch-hdris.sh, npm) or ENVMAP_REAL_HDRIS=DIR; about 10 minutes; run with cargo test --release -p envmap-render --test real_hdri -- --ignored"]
fn full_set_within_target() {
    // Tests run in the package's directory: a relative DIR is taken from
    // the repository root, where the script's default, target/hdri, is.
    // (An absolute DIR is kept as it is.)
    let dir = std::env::var("ENVMAP_REAL_HDRIS").unwrap_or_else(|_| "target/hdri".into());
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(dir);
    let fetch = "scripts/fetch-hdris.sh fetches the 18 into target/hdri; \
                 ENVMAP_REAL_HDRIS=DIR reads another directory";
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e} ({fetch})", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "exr"))
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "{}: no .exr files ({fetch})",
        dir.display()
    );
    let t = Instant::now();
    let mut rows = Vec::new();
    for path in &files {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let src = load_hdri(path);
        let oracle = Oracle::new(&src);
        for size in [128, 512] {
            rows.extend(measure_chain(&name, &src, &oracle, size, 512));
        }
    }
    println!(
        "{} files, {} levels measured in {:.1} s",
        files.len(),
        rows.len(),
        t.elapsed().as_secs_f64()
    );
    assert_within_target(&rows);
}

/// The irradiance map against the oracle's E/π on the committed HDRIs with
/// suns: from SH9 it cannot hold the sun (over 1 %: the band limit, not a
/// bug; this is the gap `--exact-irradiance` closes), by the exact cosine
/// convolution within 0.05 %.
#[test]
fn exact_irradiance_holds_a_sun() {
    for name in ["sky", "park"] {
        let src = load_hdri(&committed_path(name));
        let oracle = Oracle::new(&src);
        let mut errors = Vec::new();
        for exact_irradiance in [false, true] {
            let b = bake(
                &src,
                &{
                    let mut o = BakeOptions::default();
                    o.size = 16;
                    o.irradiance_size = 8;
                    o.dfg_size = 0;
                    o.exact_irradiance = exact_irradiance;
                    o
                },
                &|_, _| {},
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
            let irr = b.irradiance.expect("an irradiance map");
            assert_eq!(irr.method, if exact_irradiance { "exact" } else { "sh9" });
            let m = measure_irradiance(&oracle, &irr.image, IrradianceScale::EOverPi, 256, 7);
            println!(
                "{name}: irradiance ({}) {:.4} % RMS, bias {:+.4} %",
                irr.method,
                100.0 * m.relative_rms,
                100.0 * m.bias
            );
            errors.push(m.relative_rms);
        }
        assert!(
            errors[0] > 0.01,
            "{name}: SH9 within 1 % of a sun's E? {errors:?}"
        );
        assert!(errors[1] < 5e-4, "{name}: exact irradiance {errors:?}");
    }
}
