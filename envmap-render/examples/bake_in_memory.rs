//! An engine's asset step, all in memory: an HDR file's bytes → the bake →
//! the KTX2 files Bevy loads (and the raw texels an engine uploads itself),
//! with nothing written to disk.
//!
//! ```text
//! cargo run --release -p envmap-render --example bake_in_memory [-- FILE.hdr|.exr [SIZE]]
//! ```
//!
//! With no file, the bytes of a Radiance file are made in memory from the
//! built-in sky (so the example runs anywhere); SIZE is the chain's level 0
//! (default 64: Bevy's own preset says 512).

use envmap_core::AnyMapping;
use envmap_render::bake::{Baker, Target};
use envmap_render::image::{
    load_from_memory, save_to_memory, LoadOptions, Representation, SaveOptions,
};
use envmap_render::scene::Builtin;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.get(1).map_or(Ok(64), |s| s.parse())?;
    // 1. The file's bytes, as an engine has them (from its asset pack).
    let (name, bytes) = match args.first() {
        Some(path) => (path.clone(), std::fs::read(path)?),
        None => ("sky.hdr".to_owned(), sky_hdr_bytes()?),
    };
    // 2. Decoded from memory: the mapping from the aspect ratio (a 2:1
    //    latlong here), the axes from the file's tags or envmap's default.
    let src = load_from_memory(&bytes, &name, &LoadOptions::default())?.image;
    // 3. Bevy's preset (E5B9G9R9 + zstd KTX2, linear roughness rule), at
    //    the size asked.
    let baked = Baker::for_target(Target::Bevy)
        .size(size)
        .input_name(name.as_str())
        .bake(&src)?;
    // 4. The files' bytes, exactly as `envmap bake --target bevy` writes
    //    them, and the raw texels for an engine's own upload.
    let files = baked.files("ibl")?;
    println!(
        "{name}: {}×{} → {} files in memory:",
        src.width(),
        src.height(),
        files.files.len()
    );
    for f in &files.files {
        println!("  {:<14} {:>8} bytes", f.path.display(), f.bytes.len());
    }
    let ktx2 = files.get("specular.ktx2").ok_or("no specular.ktx2")?;
    assert_eq!(&ktx2[..12], b"\xABKTX 20\xBB\r\n\x1A\n", "a KTX2 file");
    let up = baked.textures()?;
    if let Some(s) = &up.specular {
        println!(
            "specular upload: {} levels × 6 faces, {} (Vulkan {}, wgpu {}), level 0 {} bytes per face",
            s.levels.len(),
            s.format.name(),
            s.format.vk_name(),
            s.format.wgpu_name().unwrap_or("none"),
            s.levels[0].faces[0].len()
        );
    }
    Ok(())
}

/// The built-in sky as a 256 × 128 Radiance file, encoded in memory.
fn sky_hdr_bytes() -> envmap_render::Result<Vec<u8>> {
    let sky = Builtin::Sky.image(Representation::default_for(AnyMapping::LatLong), 256, 128)?;
    Ok(save_to_memory(&sky, "sky.hdr", &SaveOptions::default())?
        .into_iter()
        .next()
        .map(|f| f.bytes)
        .unwrap_or_default())
}
