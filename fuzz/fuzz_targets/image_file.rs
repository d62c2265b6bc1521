//! Arbitrary bytes as an image file: loading (every format, chosen by the
//! first byte), layout detection, the `info` statistics and a small
//! conversion. Loading may fail (with an error naming the file); nothing
//! may panic, and a loaded image must be consistent.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use envmap_core::AnyMapping;
use envmap_render::filter::Filter;
use envmap_render::filter::{convert, ConvertOptions};
use envmap_render::image::Representation;
use envmap_render::image::{load_detailed, LoadOptions, NonFinite};
use libfuzzer_sys::fuzz_target;

const EXTENSIONS: [&str; 4] = ["png", "jpg", "hdr", "exr"];

fn dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| tempfile::tempdir().expect("temporary directory").keep())
}

fuzz_target!(|data: &[u8]| {
    let Some((&selector, bytes)) = data.split_first() else {
        return;
    };
    let ext = EXTENSIONS[usize::from(selector & 3)];
    let path = dir().join(format!("input.{ext}"));
    std::fs::write(&path, bytes).expect("write the input file");
    // Bits 2..5: an explicit mapping (for square and ambiguous images), any
    // of `AnyMapping::ALL`; the values past its end: none.
    let mapping = AnyMapping::ALL
        .get(usize::from((selector >> 2) & 15))
        .copied();
    let opts = {
        let mut o = LoadOptions::default();
        o.mapping = mapping;
        o.layout = None;
        o.axes = None;
        // Small enough that the fuzzer cannot ask for gigabytes.
        o.max_texels = 1 << 18;
        // Bit 6: replace NaN and infinite texels.
        o.non_finite = if selector & 0x40 == 0 {
            NonFinite::Keep
        } else {
            NonFinite::Zero
        };
        o.face_transforms = Default::default();
        o.cancel = None;
        o
    };
    let Ok(loaded) = load_detailed(&path, &opts) else {
        return;
    };
    let img = &loaded.image;
    assert_eq!(
        img.pixels().len(),
        img.width() as usize * img.height() as usize
    );
    assert!(u64::from(img.width()) * u64::from(img.height()) <= opts.max_texels);
    let s = img.stats();
    assert_eq!(s.texels, s.finite + s.nan + s.inf);
    if opts.non_finite == NonFinite::Zero {
        assert_eq!((s.nan, s.inf), (0, 0));
        assert!(loaded.replaced <= img.pixels().len() as u64);
    } else {
        assert_eq!(loaded.replaced, 0);
    }
    let _ = img.memory_bytes();
    // A cube of 4×4 faces in its default layout (the horizontal cross).
    let repr = Representation::default_for(AnyMapping::Cube);
    let (w, h) = repr
        .atlas
        .image_size_for_cell_width(4)
        .expect("the cross holds 4×4 faces");
    let out = convert(
        img,
        repr,
        w,
        h,
        &{
            let mut o = ConvertOptions::default();
            o.filter = if selector & 0x80 == 0 {
                Filter::Bilinear
            } else {
                Filter::Nearest
            };
            o.samples = Some(1);
            o.rotation = None;
            o.cancel = None;
            o
        },
        None,
    )
    .expect("a small cube is a valid output");
    assert_eq!(out.pixels().len(), w as usize * h as usize);
});
