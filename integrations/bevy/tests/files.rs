//! The files `envmap bake --target bevy` writes, read by Bevy's own KTX2
//! loader (`bevy::image::ktx2_buffer_to_image`, what its `AssetServer`
//! runs for a `.ktx2`), give the very `Image`s envmap-bevy makes in memory:
//! the same cube view, format, layer and mip count, and bytes. No GPU.

use bevy::image::{ktx2_buffer_to_image, CompressedImageFormats, Image};
use bevy::render::render_resource::{TextureDataOrder, TextureFormat, TextureViewDimension};
use envmap_bevy::{bake_image, bevy_preset, EnvironmentImages};
use envmap_core::AnyMapping;
use envmap_render::bake::Baker;
use envmap_render::image::{Representation, TexelFormat};
use envmap_render::scene::Builtin;

fn same(ours: &Image, bevys: &Image, what: &str) {
    let (a, b) = (&ours.texture_descriptor, &bevys.texture_descriptor);
    assert_eq!(a.format, b.format, "{what}: format");
    assert_eq!(a.size, b.size, "{what}: size and layers");
    assert_eq!(a.mip_level_count, b.mip_level_count, "{what}: mips");
    assert_eq!(a.dimension, b.dimension, "{what}: dimension");
    assert_eq!(bevys.data_order, TextureDataOrder::MipMajor, "{what}");
    assert_eq!(ours.data_order, bevys.data_order, "{what}: data order");
    let view = |i: &Image| i.texture_view_descriptor.as_ref().and_then(|v| v.dimension);
    assert_eq!(
        view(bevys),
        Some(TextureViewDimension::Cube),
        "{what}: Bevy's view"
    );
    assert_eq!(view(ours), view(bevys), "{what}: view");
    assert!(ours.data == bevys.data, "{what}: texel bytes differ");
}

#[test]
fn bevys_loader_reads_the_preset_files_as_the_images_made_in_memory() {
    let repr = Representation::default_for(AnyMapping::LatLong);
    let sky = Builtin::Sky.image(repr, 256, 128).expect("sky");
    let baked = bake_image(&sky, 64).expect("bake");
    for (format, zstd, wgpu) in [
        (TexelFormat::E5b9g9r9, Some(3), TextureFormat::Rgb9e5Ufloat),
        (TexelFormat::Rgba16f, Some(3), TextureFormat::Rgba16Float),
        (TexelFormat::Rgba16f, None, TextureFormat::Rgba16Float),
    ] {
        let mut preset = bevy_preset(64);
        preset.texture.format = format;
        preset.texture.zstd = zstd;
        let files = Baker::with_preset(preset)
            .input_name("sky")
            .bake(&sky)
            .expect("bake")
            .files("ibl")
            .expect("files");
        let ours = EnvironmentImages::from_bake(&baked, format).expect("images");
        for (name, mine, levels) in [
            ("specular.ktx2", &ours.specular, 6),
            ("diffuse.ktx2", &ours.diffuse, 1),
        ] {
            let what = format!("{name} ({}, zstd {zstd:?})", format.name());
            let bytes = files.get(name).expect(name);
            let bevys = ktx2_buffer_to_image(bytes, CompressedImageFormats::NONE, false)
                .unwrap_or_else(|e| panic!("{what}: Bevy refuses it: {e:?}"));
            assert_eq!(bevys.texture_descriptor.format, wgpu, "{what}");
            assert_eq!(
                bevys.texture_descriptor.size.depth_or_array_layers, 6,
                "{what}"
            );
            assert_eq!(bevys.texture_descriptor.mip_level_count, levels, "{what}");
            eprintln!(
                "{what}: Bevy reads {:?}, {}×{}×{} layers, {} mips, view {:?}",
                bevys.texture_descriptor.format,
                bevys.texture_descriptor.size.width,
                bevys.texture_descriptor.size.height,
                bevys.texture_descriptor.size.depth_or_array_layers,
                bevys.texture_descriptor.mip_level_count,
                bevys
                    .texture_view_descriptor
                    .as_ref()
                    .and_then(|v| v.dimension)
            );
            same(mine, &bevys, &what);
        }
    }
}
