//! Split-sum renders of any chain against the exact split sum, per
//! roughness: the scene and measure of `tests/split_sum.rs` (a white metal
//! sphere, 96² pixels, relative RMS and bias over the sphere), for chains
//! given on the command line.
//!
//! ```text
//! cargo run --release -p envmap-render --example split_sum -- MAPS ROUGHNESS CHAIN...
//! ```
//!
//! * MAPS: comma-separated files or built-ins (`sky`, stored as a cube of
//!   `ENV_SIZE`², default 512).
//! * ROUGHNESS: comma-separated values, or `all` (0 to 1 in steps of 0.05).
//! * CHAIN: `RULE/MIN/BLEND/DFG`, level 0 at `SIZE`² (default 256):
//!   RULE `linear`, `filament`, `unity` with MIN the smallest face (`nK`:
//!   K levels), or `lobe` with MIN `first,step,texels,min[,max]`
//!   ([`lobe_chain`]), or `list` with MIN `r0,r1,…;s0,s1,…`; BLEND `r`
//!   (linear in roughness), `eng` (the rule's lod), `iw` (envmap's, linear
//!   in 1/α), `iwF` (with floor F); DFG `cN` (N² at texel centres) or
//!   `eN` (edges grid); a fifth part `src` reads the input itself at
//!   roughness 0 ([`LitEnvironment::with_source`], as envmap's renders do).
//!   The exact split sum reads the input bilinearly ([`Oracle::bilinear`]).
//!
//! Environment: `PX` (image size, 96), `SIZE`, `ENV_SIZE`, `CACHE=DIR`
//! (keep the exact renders there: each is slow), `VERBOSE=1` (each
//! level's method and time).
use std::path::Path;
use std::time::Instant;

use envmap_render::filter::bake::{bake, lobe_chain, BakeOptions};
use envmap_render::filter::dfg::{DfgGrid, DfgTable};
use envmap_render::filter::sh::IrradianceScale;
use envmap_render::filter::specular::RoughnessRule;
use envmap_render::image::RgbImage;
use envmap_render::image::{load, LoadOptions, NonFinite};
use envmap_render::image::{EnvImage, FileAxes};
use envmap_render::instruments::Oracle;
use envmap_render::scene::Builtin;
use envmap_render::scene::{LevelBlend, LitEnvironment};

#[path = "../tests/sphere_scene/mod.rs"]
mod sphere_scene;
use sphere_scene::{builtin_sky, mask, measure, split};

/// A file, or `sky` (the built-in sky as a cube of `env_size`²).
fn load_map(name: &str, env_size: u32) -> EnvImage {
    if matches!(name.parse::<Builtin>(), Ok(Builtin::Sky)) {
        return builtin_sky(env_size);
    }
    load(Path::new(name), &{
        let mut o = LoadOptions::default();
        o.non_finite = NonFinite::Zero;
        o
    })
    .unwrap()
}

/// The exact split sum at `r`, from `CACHE` when it holds it.
fn exact(env: &EnvImage, oracle: &Oracle, key: &str, r: f32, px: u32) -> RgbImage {
    let cache = std::env::var("CACHE").ok();
    let path = cache
        .as_ref()
        .map(|d| format!("{d}/{key}_bilinear_{r:.3}_{px}.bin"));
    if let Some(b) = path.as_ref().and_then(|p| std::fs::read(p).ok()) {
        let f: Vec<f32> = b
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        return RgbImage {
            width: px,
            height: px,
            pixels: f.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
        };
    }
    let t = Instant::now();
    let img = sphere_scene::exact(env, oracle, r, px);
    eprintln!("exact {key} r {r}: {:.1} s", t.elapsed().as_secs_f64());
    if let (Some(dir), Some(path)) = (&cache, &path) {
        std::fs::create_dir_all(dir).unwrap();
        let mut b = Vec::new();
        for p in &img.pixels {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        std::fs::write(path, b).unwrap();
    }
    img
}

/// A chain named as the module docs say, and its description.
fn lit_for(env: &EnvImage, spec: &str, size: u32) -> (LitEnvironment, String) {
    // rule/min/blend/dfg
    let parts: Vec<&str> = spec.split('/').collect();
    let mut o = BakeOptions::default();
    o.size = size;
    o.axes = FileAxes::Frame(env.representation().frame);
    o.irradiance_size = 8;
    o.dfg_size = 0;
    let rule_name = parts[0];
    let mut engine_rule = RoughnessRule::Linear;
    if rule_name == "lobe" {
        let p: Vec<f64> = parts[1].split(',').map(|x| x.parse().unwrap()).collect();
        let max = p.get(4).map_or(size, |&m| m as u32);
        let shape = lobe_chain(size, max, p[0] as f32, p[1], p[2], p[3] as u32);
        o = shape.apply(o);
    } else if rule_name == "list" {
        // list/r0,r1,..;s0,s1,..
        let (rs, ss) = parts[1].split_once(';').unwrap();
        let r: Vec<f32> = rs.split(',').map(|x| x.parse().unwrap()).collect();
        let s: Vec<u32> = ss.split(',').map(|x| x.parse().unwrap()).collect();
        o.rule = RoughnessRule::Custom(r);
        o.sizes = Some(s);
    } else {
        engine_rule = rule_name.parse().unwrap();
        o.rule = engine_rule.clone();
        let m = parts[1];
        if let Some(n) = m.strip_prefix('n') {
            o.levels = Some(n.parse().unwrap());
        } else {
            o.min_size = Some(m.parse().unwrap());
        }
    }
    let t = Instant::now();
    let b = bake(env, &o, &|_, _| {}).unwrap();
    let secs = t.elapsed().as_secs_f64();
    let chain = b.chain.unwrap();
    if std::env::var("VERBOSE").is_ok() {
        for r in &chain.reports {
            eprintln!(
                "  {} r {:.3} {} samples {} src {:?} {:.3} s",
                r.size, r.roughness, r.method, r.samples, r.source_level, r.seconds
            );
        }
        eprintln!("  stages {:?}", chain.stages);
    }
    let roughness: Vec<f32> = chain.reports.iter().map(|r| r.roughness).collect();
    let sizes: Vec<u32> = chain.reports.iter().map(|r| r.size).collect();
    let dfg = match parts.get(3).copied().unwrap_or("e128") {
        d if d.starts_with('c') => {
            DfgTable::on_grid(d[1..].parse().unwrap(), DfgGrid::TexelCentres, None).unwrap()
        }
        d => DfgTable::on_grid(d[1..].parse().unwrap(), DfgGrid::Edges, None).unwrap(),
    };
    let lit = LitEnvironment::new(
        chain.levels,
        roughness.clone(),
        b.irradiance.unwrap().image,
        IrradianceScale::EOverPi,
        dfg,
    )
    .unwrap();
    // A fifth part `src`: the input read at roughness 0 in place of level 0.
    let lit = if parts.get(4) == Some(&"src") {
        lit.with_source(env.clone()).unwrap()
    } else {
        lit
    };
    let blend = match parts.get(2).copied().unwrap_or("iw") {
        "r" => LevelBlend::Roughness,
        "eng" => LevelBlend::engine(&engine_rule),
        "iw" => lit.blend(),
        b => LevelBlend::InverseWidth {
            floor: b[2..].parse().unwrap(),
        },
    };
    let texels: u64 = sizes.iter().map(|&s| 6 * u64::from(s) * u64::from(s)).sum();
    let desc = format!(
        "{spec}: {} levels {:?} sizes {:?}, {:.2} Mtexels, bake {secs:.2} s, blend {blend:?}",
        roughness.len(),
        roughness
            .iter()
            .map(|r| (r * 1000.0).round() / 1000.0)
            .collect::<Vec<_>>(),
        sizes,
        texels as f64 / 1e6
    );
    (lit.with_blend(blend), desc)
}

/// Every map, every chain, every roughness: the table.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let maps: Vec<&str> = args[1].split(',').collect();
    let rs: Vec<f32> = if args[2] == "all" {
        (0..=20).map(|k| k as f32 * 0.05).collect()
    } else {
        args[2].split(',').map(|x| x.parse().unwrap()).collect()
    };
    let specs = &args[3..];
    let px: u32 = std::env::var("PX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(96);
    let size: u32 = std::env::var("SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(256);
    let env_size: u32 = std::env::var("ENV_SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(512);
    for map in maps {
        let env = load_map(map, env_size);
        let key = format!(
            "{}_{}",
            Path::new(map).file_stem().unwrap().to_string_lossy(),
            env.width()
        );
        let t = Instant::now();
        let oracle = Oracle::bilinear(&env);
        eprintln!("oracle {key}: {:.2} s", t.elapsed().as_secs_f64());
        let mask = mask(px);
        let exacts: Vec<RgbImage> = rs
            .iter()
            .map(|&r| exact(&env, &oracle, &key, r, px))
            .collect();
        println!("## {map}");
        let mut table = vec![String::new(); rs.len()];
        for (si, spec) in specs.iter().enumerate() {
            let (lit, desc) = lit_for(&env, spec, size);
            println!("[{si}] {desc}");
            for (k, &r) in rs.iter().enumerate() {
                let img = split(&env, &lit, r, px);
                let (rms, bias) = measure(&img, &exacts[k], &mask);
                table[k] += &format!(" | {:6.2} {:+7.3}", rms * 100.0, bias * 100.0);
            }
        }
        for (k, &r) in rs.iter().enumerate() {
            println!("{r:.2}{}", table[k]);
        }
    }
}
