//! Arbitrary bytes as a GPU texture file: the same bytes through the KTX2,
//! the DDS, the Babylon.js `.env` and the glTF image-based-light reader
//! (`envmap_render::image::texture::decode`). Reading may fail (with an error naming the file);
//! nothing may panic, a texture read must agree with what its file info
//! says and stay within the texel limit, and a texture of finite texels
//! must read back the same after writing it again in its own container.
#![no_main]

use std::path::Path;

use envmap_render::image::texture::{
    self, level_bytes, level_size, TextureFile, TextureKind, TextureOptions,
};
use envmap_render::image::TexelFormat;
use libfuzzer_sys::fuzz_target;

/// Small enough that the fuzzer cannot ask for gigabytes (a zstd level
/// may inflate to 16 bytes a texel).
const MAX_TEXELS: u64 = 1 << 18;

/// The writable format holding a format's texels exactly: itself, its
/// RGBA counterpart for the read-only RGB ones, RGBA32F for BC6H and
/// RGBD (lossy: their decoded texels are not what encoding them again
/// gives).
fn writable(format: TexelFormat) -> TexelFormat {
    match format {
        TexelFormat::Rgb16f => TexelFormat::Rgba16f,
        TexelFormat::Rgb32f | TexelFormat::Bc6h | TexelFormat::Rgbd8 => TexelFormat::Rgba32f,
        f => f,
    }
}

/// What every texture read must satisfy; returns its texel count.
fn check_consistent(file: &TextureFile, container: &str) -> u64 {
    let (tex, info) = (&file.texture, &file.info);
    assert_eq!(info.container, container);
    assert_eq!(info.kind, tex.kind());
    assert_eq!(info.size, tex.size());
    assert_eq!(info.levels, tex.level_count());
    assert!(info.levels >= 1);
    assert_eq!(info.level_bytes.len(), info.levels);
    let (w, h) = info.size;
    if info.kind == TextureKind::Cube {
        assert_eq!(w, h, "cube faces are square");
    }
    let mut texels = 0u64;
    for (p, level) in tex.levels().iter().enumerate() {
        assert_eq!(level.len(), info.kind.faces(), "level {p}: faces");
        let (lw, lh) = level_size(w, h, p);
        for img in level {
            assert_eq!((img.width, img.height), (lw, lh), "level {p}: size");
            assert_eq!(img.pixels.len(), lw as usize * lh as usize);
            texels += img.pixels.len() as u64;
        }
        // A .env or glTF level's bytes are its PNGs'.
        if info.supercompression.is_none() && container != ENV && container != GLTF {
            assert_eq!(
                Some(info.level_bytes[p]),
                level_bytes(info.kind, w, h, p, info.format),
                "level {p}: bytes in the file"
            );
        }
    }
    assert!(texels <= MAX_TEXELS, "{texels} texels read");
    let _ = info.summary();
    texels
}

/// The container name of `.env` files.
const ENV: &str = "Babylon.js .env";

/// The container name of glTF image-based lights.
const GLTF: &str = "glTF (EXT_lights_image_based)";

/// A texture of finite texels written again in its own container (in a
/// format that holds its texels exactly; a `.env`'s or glTF's in KTX2) must read back
/// the same.
fn check_round_trip(file: &TextureFile, container: &str) {
    let tex = &file.texture;
    let finite = tex
        .levels()
        .iter()
        .flatten()
        .all(|img| img.pixels.iter().flatten().all(|v| v.is_finite()));
    if !finite {
        return;
    }
    let format = writable(file.info.format);
    let path = Path::new(if container == "DDS" {
        "again.dds"
    } else {
        "again.ktx2"
    });
    // DDS has no supercompression.
    let zstd = file
        .info
        .supercompression
        .filter(|_| container == "KTX2")
        .map(|_| 1);
    let (bytes, clamped) = texture::encode(tex, path, {
        let mut o = TextureOptions::default();
        o.format = format;
        o.zstd = zstd;
        o
    })
    .expect("a texture read is written again");
    assert!(
        clamped.is_empty(),
        "{clamped:?} clamped writing texels read"
    );
    let again = texture::decode(path, &bytes, MAX_TEXELS).expect("a texture written reads back");
    assert!(again.texture == *tex, "{container}: the texels changed");
    assert_eq!(again.info.format, format);
}

fuzz_target!(|data: &[u8]| {
    if let Ok(file) = texture::decode(Path::new("input.ktx2"), data, MAX_TEXELS) {
        check_consistent(&file, "KTX2");
        check_round_trip(&file, "KTX2");
    }
    if let Ok(file) = texture::decode(Path::new("input.dds"), data, MAX_TEXELS) {
        check_consistent(&file, "DDS");
        check_round_trip(&file, "DDS");
    }
    if let Ok(file) = texture::decode(Path::new("input.env"), data, MAX_TEXELS) {
        check_consistent(&file, ENV);
        check_round_trip(&file, ENV);
    }
    if let Ok(file) = texture::decode(Path::new("input.gltf"), data, MAX_TEXELS) {
        check_consistent(&file, GLTF);
        check_round_trip(&file, GLTF);
    }
});
