//! Loading and saving environment maps: round trips through every format,
//! six-file cubes, layout detection, and every error a user can run into.

use std::fs;
use std::path::{Path, PathBuf};

use envmap_core::{AnyMapping, Atlas, CubeFace, Frame};
use envmap_render::image::FileFormat;
use envmap_render::image::{detect, resolve};
use envmap_render::image::{
    face_paths, linear_to_srgb8, load_detailed, read_rgb, srgb_to_linear, write_rgb, ExrPrecision,
};
use envmap_render::{
    filter::{convert, ConvertOptions},
    image::{load, save, EnvImage, Layout, LoadOptions, Representation, RgbImage, SaveOptions},
    Error,
};

mod common;
use common::entries;

/// A small latlong with distinct, smoothly varying values in `[lo, hi]`.
fn latlong(w: u32, lo: f32, hi: f32) -> EnvImage {
    let h = w / 2;
    let repr = Representation::default_for(AnyMapping::LatLong);
    let mut img = EnvImage::new(w, h, repr).unwrap();
    for y in 0..h {
        for x in 0..w {
            let t = (x + y * w) as f32 / (w * h - 1) as f32;
            let v = lo + (hi - lo) * t;
            img.set(x, y, [v, v * 0.5 + lo * 0.5, hi - v + lo]);
        }
    }
    img
}

/// A cube in `atlas` whose every texel encodes (face, i, j).
fn cube(atlas: Atlas, face: u32) -> EnvImage {
    let repr = Representation::new(AnyMapping::Cube, atlas, Frame::IDENTITY).unwrap();
    let (w, h) = atlas.image_size_for_cell_width(face).unwrap();
    let mut img = EnvImage::new(w, h, repr).unwrap();
    for f in 0..6 {
        for j in 0..face {
            for i in 0..face {
                let v = [f as f32 + 1.0, i as f32 * 10.0, j as f32 * 100.0 + 0.5];
                assert!(img.set_chart_texel(f, i, j, v));
            }
        }
    }
    img
}

fn message(e: &Error) -> String {
    e.to_string()
}

// ---------------------------------------------------------------------------
// Round trips

#[test]
fn exr_f32_round_trip_is_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sky.exr");
    let mut img = latlong(16, 0.0, 100.0);
    img.set(3, 2, [5000.0, 1e-20, -3.5]);
    img.set(4, 2, [f32::MAX, f32::MIN_POSITIVE, 0.0]);
    assert_eq!(
        save(&img, &path, &SaveOptions::default()).unwrap(),
        vec![path.clone()]
    );
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.image.representation(), img.representation());
    for (a, b) in loaded.image.pixels().iter().zip(img.pixels()) {
        assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
    }
    assert_eq!(loaded.image.get(3, 2)[0], 5000.0);
    assert_eq!(loaded.source.format, FileFormat::Exr);
    assert_eq!(loaded.source.pixel_format, "f32 RGB");
    assert_eq!(loaded.files, vec![path]);
}

#[test]
fn exr_f16_round_trip_within_half_precision() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sky.EXR");
    let img = latlong(16, 0.01, 5000.0);
    let opts = {
        let mut o = SaveOptions::default();
        o.exr_precision = ExrPrecision::F16;
        o
    };
    save(&img, &path, &opts).unwrap();
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.source.pixel_format, "f16 RGB");
    for (a, b) in loaded.image.pixels().iter().zip(img.pixels()) {
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= b[c].abs() / 1024.0 + 1e-7,
                "{a:?} {b:?}"
            );
        }
    }
}

#[test]
fn exr_rgba_f16_is_read_and_alpha_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rgba.exr");
    exr::prelude::write_rgba_file(&path, 8, 4, |x, y| {
        let v = exr::prelude::f16::from_f32(x as f32 + 8.0 * y as f32);
        (
            v,
            v,
            exr::prelude::f16::from_f32(5000.0),
            exr::prelude::f16::ONE,
        )
    })
    .unwrap();
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.source.pixel_format, "f16 RGBA (alpha dropped)");
    assert_eq!(loaded.image.get(5, 3), [29.0, 29.0, 5000.0]);
}

#[test]
fn hdr_round_trip_within_rgbe_precision() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sky.hdr");
    let mut img = latlong(16, 0.5, 200.0);
    img.set(0, 0, [5000.0, 5000.0, 5000.0]);
    img.set(1, 0, [5000.0, 2500.0, 4000.0]);
    save(&img, &path, &SaveOptions::default()).unwrap();
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.source.format, FileFormat::Hdr);
    assert_eq!(loaded.image.width(), 16);
    for (a, b) in loaded.image.pixels().iter().zip(img.pixels()) {
        let max = b.iter().fold(0.0f32, |m, v| m.max(*v));
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() <= 0.01 * max, "{a:?} {b:?}");
        }
    }
    let v = loaded.image.get(0, 0)[0];
    assert!((v - 5000.0).abs() <= 50.0, "{v}");
}

#[test]
fn png_round_trip_quantises_to_the_nearest_srgb_code() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sky.png");
    let img = latlong(16, 0.0, 1.0);
    save(&img, &path, &SaveOptions::default()).unwrap();
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.source.pixel_format, "8-bit sRGB RGB");
    for (a, b) in loaded.image.pixels().iter().zip(img.pixels()) {
        for c in 0..3 {
            let code = linear_to_srgb8(b[c]);
            assert_eq!(a[c], srgb_to_linear(f32::from(code) / 255.0));
        }
    }
    // Loading and saving an 8-bit image again changes nothing.
    let again = dir.path().join("again.png");
    save(&loaded.image, &again, &SaveOptions::default()).unwrap();
    assert_eq!(load(&again, &LoadOptions::default()).unwrap(), loaded.image);
}

#[test]
fn png_exposure_scales_by_powers_of_two_and_clamps() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("exposed.png");
    let mut img = latlong(4, 0.0, 0.0);
    img.set(0, 0, [0.1, 0.2, 5000.0]);
    img.set(1, 0, [f32::NAN, -1.0, f32::INFINITY]);
    let opts = {
        let mut o = SaveOptions::default();
        o.exposure = 2.0;
        o
    };
    save(&img, &path, &opts).unwrap();
    let back = image::open(&path).unwrap().into_rgb8();
    assert_eq!(
        back.get_pixel(0, 0).0,
        [linear_to_srgb8(0.4), linear_to_srgb8(0.8), 255]
    );
    assert_eq!(back.get_pixel(1, 0).0, [0, 0, 255]);
}

#[test]
fn jpeg_round_trip_is_close() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sky.JPG");
    let repr = Representation::default_for(AnyMapping::LatLong);
    let img = EnvImage::from_pixels(16, 8, vec![[0.2, 0.5, 0.05]; 128], repr).unwrap();
    save(&img, &path, &SaveOptions::default()).unwrap();
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.source.format, FileFormat::Jpeg);
    for p in loaded.image.pixels() {
        for (a, b) in p.iter().zip([0.2, 0.5, 0.05]) {
            assert!((a - b).abs() < 0.02, "{p:?}");
        }
    }
}

#[test]
fn eight_and_sixteen_bit_inputs_are_linearised() {
    let dir = tempfile::tempdir().unwrap();
    // 8-bit grey: replicated to RGB.
    let grey = dir.path().join("grey.png");
    image::GrayImage::from_pixel(4, 2, image::Luma([128]))
        .save(&grey)
        .unwrap();
    let l = load_detailed(&grey, &LoadOptions::default()).unwrap();
    assert_eq!(l.source.pixel_format, "8-bit sRGB grey");
    let v = l.image.get(1, 1);
    assert!((v[0] - 0.215_860_5).abs() < 1e-7, "{v:?}");
    assert_eq!(v[0], v[1]);
    assert_eq!(v[1], v[2]);

    // 8-bit RGBA: alpha dropped.
    let rgba = dir.path().join("rgba.png");
    image::RgbaImage::from_pixel(4, 2, image::Rgba([0, 128, 255, 7]))
        .save(&rgba)
        .unwrap();
    let l = load_detailed(&rgba, &LoadOptions::default()).unwrap();
    assert_eq!(l.source.pixel_format, "8-bit sRGB RGBA (alpha dropped)");
    assert_eq!(l.image.get(0, 0), [0.0, srgb_to_linear(128.0 / 255.0), 1.0]);

    // 16-bit RGB.
    let deep = dir.path().join("deep.png");
    image::ImageBuffer::<image::Rgb<u16>, _>::from_pixel(4, 2, image::Rgb([0, 32896, 65535]))
        .save(&deep)
        .unwrap();
    let l = load_detailed(&deep, &LoadOptions::default()).unwrap();
    assert_eq!(l.source.pixel_format, "16-bit sRGB RGB");
    let v = l.image.get(3, 1);
    assert_eq!(v[0], 0.0);
    assert!((v[1] - 0.215_860_5).abs() < 1e-6, "{v:?}");
    assert_eq!(v[2], 1.0);
}

// ---------------------------------------------------------------------------
// Six-file cubes

#[test]
fn six_files_save_each_face_as_gl_expects_and_load_back() {
    let dir = tempfile::tempdir().unwrap();
    let img = cube(Atlas::CUBE_VERTICAL_CROSS, 4);
    let base = dir.path().join("sky.exr");
    let opts = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    let written = save(&img, &base, &opts).unwrap();
    let expected: Vec<PathBuf> = CubeFace::ALL
        .iter()
        .map(|f| dir.path().join(format!("sky_{}.exr", f.name())))
        .collect();
    assert_eq!(written, expected);
    assert_eq!(
        entries(dir.path()),
        [
            "sky_+x.exr",
            "sky_+y.exr",
            "sky_+z.exr",
            "sky_-x.exr",
            "sky_-y.exr",
            "sky_-z.exr"
        ]
    );
    // Each file is its face in GL orientation: texel (i, j) of face f.
    for (f, p) in (0u32..).zip(&expected) {
        let (face, _) = read_rgb(p, u64::MAX, None).unwrap();
        assert_eq!((face.width, face.height), (4, 4));
        for j in 0..4 {
            for i in 0..4 {
                assert_eq!(
                    face.pixels[(j * 4 + i) as usize],
                    [f as f32 + 1.0, i as f32 * 10.0, j as f32 * 100.0 + 0.5]
                );
            }
        }
    }
    // Loaded back: from one face's name, from a pattern, from the base name.
    let strip = img.relayout(Atlas::CUBE_HORIZONTAL_STRIP).unwrap();
    let from_face = load_detailed(dir.path().join("sky_-y.exr"), &LoadOptions::default()).unwrap();
    assert_eq!(from_face.image, strip);
    assert_eq!(from_face.files, expected);
    let from_pattern = load(dir.path().join("sky_{face}.exr"), &LoadOptions::default()).unwrap();
    assert_eq!(from_pattern, strip);
    let faces = {
        let mut o = LoadOptions::default();
        o.layout = Some(Layout::Faces);
        o
    };
    assert_eq!(load(&base, &faces).unwrap(), strip);
    // A pattern in the output name writes six files too.
    let png = dir.path().join("room_{face}.png");
    let written = save(
        &cube(Atlas::CUBE_HORIZONTAL_CROSS, 2),
        &png,
        &SaveOptions::default(),
    );
    assert_eq!(written.unwrap().len(), 6);
    assert!(dir.path().join("room_-z.png").is_file());
}

#[test]
fn six_files_with_a_face_of_another_size_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let img = cube(Atlas::CUBE_HORIZONTAL_STRIP, 4);
    let opts = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    save(&img, dir.path().join("sky.png"), &opts).unwrap();
    let odd = dir.path().join("sky_-y.png");
    image::RgbImage::new(8, 8).save(&odd).unwrap();
    let e = load(dir.path().join("sky_+x.png"), &LoadOptions::default()).unwrap_err();
    let m = message(&e);
    assert!(m.starts_with(&format!("{}:", odd.display())), "{m}");
    assert!(m.contains("8×8") && m.contains("4×4"), "{m}");

    image::RgbImage::new(8, 4).save(&odd).unwrap();
    let m = message(&load(dir.path().join("sky_+x.png"), &LoadOptions::default()).unwrap_err());
    assert!(m.contains("8×4") && m.contains("square"), "{m}");

    fs::remove_file(&odd).unwrap();
    let m = message(&load(dir.path().join("sky_+x.png"), &LoadOptions::default()).unwrap_err());
    assert!(m.starts_with(&format!("{}:", odd.display())), "{m}");
    assert!(m.contains("missing"), "{m}");
}

#[test]
fn only_cubes_are_saved_as_six_files() {
    let dir = tempfile::tempdir().unwrap();
    let opts = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    let m = message(&save(&latlong(8, 0.0, 1.0), dir.path().join("a.exr"), &opts).unwrap_err());
    assert!(m.contains("only a cube"), "{m}");
    assert!(entries(dir.path()).is_empty());
}

// ---------------------------------------------------------------------------
// Layouts

#[test]
fn detection_for_every_aspect() {
    let cases = [
        ((64, 32), AnyMapping::LatLong, Atlas::LATLONG),
        ((64, 48), AnyMapping::Cube, Atlas::CUBE_HORIZONTAL_CROSS),
        ((48, 64), AnyMapping::Cube, Atlas::CUBE_VERTICAL_CROSS),
        ((96, 16), AnyMapping::Cube, Atlas::CUBE_HORIZONTAL_STRIP),
        ((16, 96), AnyMapping::Cube, Atlas::CUBE_VERTICAL_STRIP),
    ];
    for ((w, h), m, a) in cases {
        assert_eq!(detect(w, h).unwrap(), (m, a), "{w}×{h}");
        // An explicit mapping alone finds the same layout.
        assert_eq!(resolve(w, h, Some(m), None).unwrap(), (m, a));
    }
    // 3:2 is a tennisball or a cube of three faces by two: named, not guessed.
    let m = message(&detect(96, 64).unwrap_err());
    assert!(
        m.contains("--from tennisball") && m.contains("--from-layout 3x2"),
        "{m}"
    );
    assert_eq!(
        resolve(96, 64, Some(AnyMapping::Tennisball), None).unwrap(),
        (AnyMapping::Tennisball, Atlas::TENNISBALL_STACKED)
    );
    assert_eq!(
        resolve(96, 64, None, Some(Layout::Grid3x2)).unwrap(),
        (AnyMapping::Cube, Atlas::CUBE_3X2)
    );
    assert_eq!(
        resolve(96, 64, Some(AnyMapping::Eac), Some(Layout::Grid3x2)).unwrap(),
        (AnyMapping::Eac, Atlas::CUBE_3X2)
    );
    // ffmpeg v360's EAC file: refused, with the flag that reads it.
    let m = message(&detect(3076, 2056).unwrap_err());
    assert!(m.contains("--from eac") && m.contains("n = 1024"), "{m}");
    let m = message(&detect(64, 64).unwrap_err());
    for name in [
        "sphere",
        "sphere-gl",
        "mirror-ball",
        "angular",
        "light-probe",
        "octahedral",
        "octahedral-equal-area",
        "--from",
    ] {
        assert!(m.contains(name), "{m}");
    }
    let m = message(&detect(1000, 333).unwrap_err());
    assert!(m.contains("1000×333") && m.contains("1000:333"), "{m}");
    for ratio in [
        "2:1",
        "4:3",
        "3:4",
        "6:1",
        "1:6",
        "3:2",
        "1:1",
        "paraboloid",
    ] {
        assert!(m.contains(ratio), "{ratio}: {m}");
    }
    assert!(message(&detect(300, 100).unwrap_err()).contains("tennisball strip"));
    assert!(message(&detect(1001, 500).unwrap_err()).contains("close to 2:1"));
    assert!(detect(0, 10).is_err());
}

#[test]
fn explicit_layouts_are_checked() {
    // A dual paraboloid is 2:1 too: named, it is taken as one.
    assert_eq!(
        resolve(64, 32, Some(AnyMapping::DualParaboloid), None).unwrap(),
        (AnyMapping::DualParaboloid, Atlas::PARABOLOID_SIDE_BY_SIDE)
    );
    assert_eq!(
        resolve(32, 32, Some(AnyMapping::Octahedral), None).unwrap(),
        (AnyMapping::Octahedral, Atlas::SINGLE_SQUARE)
    );
    // The angular map (a light probe) is a square image too.
    assert_eq!(
        resolve(64, 64, Some(AnyMapping::Angular), None).unwrap(),
        (AnyMapping::Angular, Atlas::SINGLE_SQUARE)
    );
    assert_eq!(
        resolve(64, 64, Some(AnyMapping::Angular), Some(Layout::Square)).unwrap(),
        (AnyMapping::Angular, Atlas::SINGLE_SQUARE)
    );
    assert_eq!(
        resolve(16, 96, Some(AnyMapping::Cube), Some(Layout::VStrip)).unwrap(),
        (AnyMapping::Cube, Atlas::CUBE_VERTICAL_STRIP)
    );
    assert_eq!(
        message(&resolve(64, 32, None, Some(Layout::Cross)).unwrap_err()),
        "cross needs 4:3, this image is 64×32 (2:1)"
    );
    let m = message(&resolve(64, 32, Some(AnyMapping::Cube), None).unwrap_err());
    assert!(
        m.contains("4:3 (cross)") && m.contains("1:6 (vstrip)") && m.contains("64×32"),
        "{m}"
    );
    let m = message(&resolve(32, 32, None, Some(Layout::Square)).unwrap_err());
    assert!(
        m.contains("octahedral") && m.contains("name the mapping"),
        "{m}"
    );
    let m =
        message(&resolve(32, 32, Some(AnyMapping::Octahedral), Some(Layout::Cross)).unwrap_err());
    assert!(m.contains("octahedral has no cross layout"), "{m}");
    let m = message(&resolve(150, 60, Some(AnyMapping::Tennisball), None).unwrap_err());
    assert!(m.contains("3:2"), "{m}");
    assert!(resolve(96, 16, None, Some(Layout::Faces)).is_err());
    assert_eq!("VCROSS".parse::<Layout>().unwrap(), Layout::VCross);
}

#[test]
fn load_applies_explicit_mapping_and_names_the_file_on_mismatch() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("para.exr");
    save(&latlong(16, 0.0, 1.0), &path, &SaveOptions::default()).unwrap();
    let opts = {
        let mut o = LoadOptions::default();
        o.mapping = Some(AnyMapping::DualParaboloid);
        o.axes = Some(envmap_render::image::FileAxes::Frame(Frame::Y_UP_RH));
        o
    };
    let img = load(&path, &opts).unwrap();
    assert_eq!(img.mapping(), AnyMapping::DualParaboloid);
    assert_eq!(img.atlas(), &Atlas::PARABOLOID_SIDE_BY_SIDE);
    assert_eq!(img.representation().frame, Frame::Y_UP_RH);
    let opts = {
        let mut o = LoadOptions::default();
        o.layout = Some(Layout::Cross);
        o
    };
    let m = message(&load(&path, &opts).unwrap_err());
    assert_eq!(
        m,
        format!(
            "{}: cross needs 4:3, this image is 16×8 (2:1)",
            path.display()
        )
    );
}

// ---------------------------------------------------------------------------
// Errors on input

#[test]
fn missing_file_and_unknown_extension() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothing.exr");
    let m = message(&load(&missing, &LoadOptions::default()).unwrap_err());
    assert!(
        m.starts_with(&format!("{}: cannot read:", missing.display())),
        "{m}"
    );

    let odd = dir.path().join("sky.tga");
    fs::write(&odd, b"whatever").unwrap();
    let m = message(&load(&odd, &LoadOptions::default()).unwrap_err());
    assert!(m.starts_with(&format!("{}:", odd.display())), "{m}");
    assert!(
        m.contains(".tga") && m.contains("png, jpg, jpeg, hdr, exr"),
        "{m}"
    );

    let img = latlong(8, 0.0, 1.0);
    let out = dir.path().join("out.bmp");
    let m = message(&save(&img, &out, &SaveOptions::default()).unwrap_err());
    assert!(m.contains("out.bmp") && m.contains("accepted"), "{m}");
    assert!(!out.exists());

    let m = message(&load(dir.path(), &LoadOptions::default()).unwrap_err());
    assert!(m.contains("extension"), "{m}");
}

#[test]
fn truncated_and_corrupt_files_give_errors_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let img = latlong(32, 0.0, 1.0);
    for ext in ["png", "exr", "hdr", "jpg"] {
        let good = dir.path().join(format!("good.{ext}"));
        save(&img, &good, &SaveOptions::default()).unwrap();
        let bytes = fs::read(&good).unwrap();

        let cut = dir.path().join(format!("cut.{ext}"));
        fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        let m = message(&load(&cut, &LoadOptions::default()).unwrap_err());
        assert!(m.starts_with(&format!("{}:", cut.display())), "{m}");

        let header_only = dir.path().join(format!("header.{ext}"));
        fs::write(&header_only, &bytes[..bytes.len().min(20)]).unwrap();
        let m = message(&load(&header_only, &LoadOptions::default()).unwrap_err());
        assert!(m.starts_with(&format!("{}:", header_only.display())), "{m}");

        // Damaged in the middle: garbage after a valid header.
        let mut damaged = bytes.clone();
        let n = damaged.len();
        for b in &mut damaged[n / 3..n / 3 + 64.min(n / 3)] {
            *b = 0xa5;
        }
        let bad = dir.path().join(format!("damaged.{ext}"));
        fs::write(&bad, &damaged).unwrap();
        // May decode to something (JPEG and HDR are forgiving) but must not panic.
        if let Err(e) = load(&bad, &LoadOptions::default()) {
            assert!(message(&e).starts_with(&format!("{}:", bad.display())));
        }

        let garbage = dir.path().join(format!("garbage.{ext}"));
        fs::write(&garbage, b"this is not an image at all").unwrap();
        let m = message(&load(&garbage, &LoadOptions::default()).unwrap_err());
        assert!(
            m.starts_with(&format!("{}: cannot decode", garbage.display())),
            "{m}"
        );

        let empty = dir.path().join(format!("empty.{ext}"));
        fs::write(&empty, b"").unwrap();
        assert!(load(&empty, &LoadOptions::default()).is_err());
    }
}

#[test]
fn exr_without_rgb_channels_is_refused() {
    use exr::prelude::{Image, SpecificChannels, WritableImage};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("luma.exr");
    let channels = SpecificChannels::build()
        .with_channel("Y")
        .with_pixel_fn(|_| (0.5f32,));
    Image::from_channels((8, 4), channels)
        .write()
        .to_file(&path)
        .unwrap();
    let m = message(&load(&path, &LoadOptions::default()).unwrap_err());
    assert_eq!(
        m,
        format!(
            "{}: no RGB channels (an R, G and B channel in one layer are needed; found: Y)",
            path.display()
        )
    );
}

#[test]
fn images_above_the_limit_are_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let img = latlong(64, 0.0, 1.0);
    for ext in ["png", "exr", "hdr"] {
        let path = dir.path().join(format!("big.{ext}"));
        save(&img, &path, &SaveOptions::default()).unwrap();
        let opts = {
            let mut o = LoadOptions::default();
            o.max_texels = 1000;
            o
        };
        let m = message(&load(&path, &opts).unwrap_err());
        assert!(m.starts_with(&format!("{}:", path.display())), "{m}");
        assert!(m.contains("64×32") && m.contains("1000 texels"), "{m}");
    }
    // Six faces count together.
    let faces = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    save(
        &cube(Atlas::CUBE_HORIZONTAL_CROSS, 10),
        dir.path().join("c.exr"),
        &faces,
    )
    .unwrap();
    let opts = {
        let mut o = LoadOptions::default();
        o.max_texels = 500;
        o
    };
    let m = message(&load(dir.path().join("c_+x.exr"), &opts).unwrap_err());
    assert!(m.contains("600 texels"), "{m}");
}

// ---------------------------------------------------------------------------
// Safe writes

#[test]
fn writing_over_the_input_is_refused_unless_asked() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("sub")).unwrap();
    let input = dir.path().join("in.exr");
    save(&latlong(8, 0.0, 1.0), &input, &SaveOptions::default()).unwrap();
    let before = fs::read(&input).unwrap();
    let loaded = load_detailed(&input, &LoadOptions::default()).unwrap();
    let changed = latlong(8, 5.0, 6.0);

    // The same file, spelled another way.
    let other_spelling = dir.path().join("sub").join("..").join("in.exr");
    for target in [input.clone(), other_spelling] {
        let opts = {
            let mut o = SaveOptions::default();
            o.inputs = loaded.files.clone();
            o
        };
        let m = message(&save(&changed, &target, &opts).unwrap_err());
        assert!(m.starts_with(&format!("{}:", target.display())), "{m}");
        assert!(m.contains("refusing to write over the input"), "{m}");
        assert_eq!(fs::read(&input).unwrap(), before);
    }
    // Six-file outputs are checked face by face.
    let faces_in = dir.path().join("c.exr");
    let faces = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    let cube_img = cube(Atlas::CUBE_HORIZONTAL_CROSS, 2);
    save(&cube_img, &faces_in, &faces).unwrap();
    let cube_loaded = load_detailed(dir.path().join("c_+y.exr"), &LoadOptions::default()).unwrap();
    let opts = {
        let mut o = faces.clone();
        o.inputs = cube_loaded.files.clone();
        o
    };
    assert!(matches!(
        save(&cube_img, &faces_in, &opts),
        Err(Error::WouldOverwriteInput { .. })
    ));

    // Asked for: replaced.
    let opts = {
        let mut o = SaveOptions::default();
        o.inputs = loaded.files;
        o.overwrite_input = true;
        o
    };
    save(&changed, &input, &opts).unwrap();
    assert_eq!(load(&input, &LoadOptions::default()).unwrap(), changed);
    assert_eq!(
        entries(dir.path()),
        ["c_+x.exr", "c_+y.exr", "c_+z.exr", "c_-x.exr", "c_-y.exr", "c_-z.exr", "in.exr", "sub"]
    );
}

#[test]
fn failed_writes_leave_no_temporary_file_and_no_damage() {
    let dir = tempfile::tempdir().unwrap();
    let img = latlong(8, 0.0, 1.0);

    // The target's directory does not exist.
    let nowhere = dir.path().join("missing").join("out.exr");
    let m = message(&save(&img, &nowhere, &SaveOptions::default()).unwrap_err());
    assert!(
        m.starts_with(&format!("{}: cannot write:", nowhere.display())),
        "{m}"
    );
    assert!(entries(dir.path()).is_empty());

    // The target is a directory (with something in it).
    let as_dir = dir.path().join("out.png");
    fs::create_dir(&as_dir).unwrap();
    fs::write(as_dir.join("keep"), b"x").unwrap();
    let m = message(&save(&img, &as_dir, &SaveOptions::default()).unwrap_err());
    assert!(
        m.starts_with(&format!("{}: cannot write:", as_dir.display())),
        "{m}"
    );
    assert_eq!(entries(dir.path()), ["out.png"]);
    assert_eq!(entries(&as_dir), ["keep"]);

    // One of six faces is a directory: nothing is written, not even the others.
    let faces = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    let cube_img = cube(Atlas::CUBE_HORIZONTAL_CROSS, 2);
    fs::create_dir(dir.path().join("sky_-z.exr")).unwrap();
    let m = message(&save(&cube_img, dir.path().join("sky.exr"), &faces).unwrap_err());
    assert!(m.contains("sky_-z.exr: cannot write"), "{m}");
    assert_eq!(entries(dir.path()), ["out.png", "sky_-z.exr"]);

    // Encoding fails (JPEG cannot be 65536 wide) over an existing good file:
    // the file is untouched and no temporary file remains.
    let existing = dir.path().join("wide.jpg");
    fs::write(&existing, b"the good old file").unwrap();
    let wide = RgbImage {
        width: 65536,
        height: 1,
        pixels: vec![[0.5; 3]; 65536],
    };
    let m = message(&write_rgb(&wide, &existing, &SaveOptions::default()).unwrap_err());
    assert!(
        m.starts_with(&format!("{}: cannot encode JPEG", existing.display())),
        "{m}"
    );
    assert_eq!(fs::read(&existing).unwrap(), b"the good old file");
    assert_eq!(entries(dir.path()), ["out.png", "sky_-z.exr", "wide.jpg"]);
}

#[cfg(unix)]
#[test]
fn outputs_get_ordinary_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.hdr");
    save(&latlong(8, 0.0, 1.0), &path, &SaveOptions::default()).unwrap();
    // As any new file (0666 less the umask), not a temporary file's 0600.
    let plain = dir.path().join("plain");
    fs::write(&plain, b"").unwrap();
    let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&path), mode(&plain));
    // Replacing a file keeps its permissions.
    fs::set_permissions(&path, fs::Permissions::from_mode(0o640)).unwrap();
    save(&latlong(8, 1.0, 2.0), &path, &SaveOptions::default()).unwrap();
    assert_eq!(mode(&path), 0o640);
}

#[test]
fn face_paths_are_named_after_cube_faces() {
    let p = face_paths(Path::new("out/sky.hdr")).unwrap();
    assert_eq!(p[0], Path::new("out/sky_+x.hdr"));
    assert_eq!(p[5], Path::new("out/sky_-z.hdr"));
}

/// A conversion saved as it is made (`Outputs::stage_streamed`) gives the
/// file that converting first and saving after gives: every mapping kind
/// that is written row by row (cube cross, latlong, octahedral, sphere),
/// each block height (1 and 16 scan lines, PIZ's 32), both precisions; and
/// the forms that cannot stream (six files, turned cube faces, a Radiance
/// HDR) fall back to the whole image with the same result.
#[test]
fn a_streamed_conversion_saves_what_convert_then_save_saves() {
    use envmap_render::filter::Streamed;
    use envmap_render::image::{ExrCompression, Outputs};
    use envmap_render::image::{FaceTransforms, FaceTurn};
    let src = latlong(96, -0.5, 40.0);
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let copts = ConvertOptions::default();
    let check = |repr: Representation, (w, h): (u32, u32), name: &str, opts: &SaveOptions| {
        let want = convert(&src, repr, w, h, &copts, None).unwrap();
        let a = dir.join(format!("whole-{name}"));
        let b = dir.join(format!("streamed-{name}"));
        let a_files = save(&want, &a, opts).unwrap();
        let stream = Streamed::new(&src, repr, w, h, &copts, None).unwrap();
        let mut run = Outputs::new(opts);
        run.stage_streamed(&stream, &b, opts).unwrap();
        let b_files = run.commit().unwrap();
        assert_eq!(a_files.len(), b_files.len(), "{name}");
        let load_opts = {
            let mut o = LoadOptions::default();
            o.face_transforms = opts.face_transforms;
            o
        };
        let x = load(&a_files[0], &load_opts).unwrap();
        let y = load(&b_files[0], &load_opts).unwrap();
        assert_eq!(x.representation(), y.representation(), "{name}");
        assert_eq!((x.width(), x.height()), (y.width(), y.height()), "{name}");
        for (k, (p, q)) in x.pixels().iter().zip(y.pixels()).enumerate() {
            assert_eq!(
                p.map(f32::to_bits),
                q.map(f32::to_bits),
                "{name}: texel {k}"
            );
        }
    };
    let cube = Representation::default_for(AnyMapping::Cube);
    let cube_size = cube.atlas.image_size_for_cell_width(24).unwrap();
    let cases = [
        (cube, cube_size),
        (Representation::default_for(AnyMapping::LatLong), (64, 32)),
        (
            Representation::default_for(AnyMapping::Octahedral),
            (40, 40),
        ),
        (Representation::default_for(AnyMapping::SphereMap), (37, 37)),
        (
            Representation::default_for(AnyMapping::DualParaboloid),
            (48, 24),
        ),
    ];
    for (repr, size) in cases {
        for compression in [
            ExrCompression::None,
            ExrCompression::Zip,
            ExrCompression::Piz,
        ] {
            for precision in [ExrPrecision::F32, ExrPrecision::F16] {
                let opts = {
                    let mut o = SaveOptions::default();
                    o.exr_compression = compression;
                    o.exr_precision = precision;
                    o
                };
                let name = format!("{}-{compression:?}-{precision:?}.exr", repr.mapping);
                check(repr, size, &name, &opts);
            }
        }
    }
    let turned = {
        let mut o = SaveOptions::default();
        o.face_transforms = FaceTransforms::default().with(CubeFace::PosY, FaceTurn::ROT90);
        o
    };
    check(cube, cube_size, "turned.exr", &turned);
    let six = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    check(cube, cube_size, "six-{face}.exr", &six);
    check(cube, cube_size, "cube.hdr", &SaveOptions::default());
}
