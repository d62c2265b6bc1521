//! Arbitrary text through the `envmap map` and `envmap unmap` line parser
//! (`envmap_cli::text`), for every mapping, with and without an image
//! size. Each line gives a row or an error; nothing may panic, and a row of
//! `map` read back by `unmap` must be accepted.
#![no_main]

use envmap_cli::text::{MapLines, UnmapLines};
use envmap_core::{AnyMapping, Frame, Mapping};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&selector, bytes)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(bytes);
    // Bits 0..3: the mapping (modulo the number of mappings); bit 4: the
    // frame; bit 5: an image size, whose cell width is bits 6..7 plus one.
    let m = AnyMapping::ALL[usize::from(selector & 15) % AnyMapping::ALL.len()];
    let frame = if selector & 16 == 0 {
        Frame::IDENTITY
    } else {
        Frame::Y_UP_LH
    };
    let atlas = m.atlas();
    let size = (selector & 32 != 0)
        .then(|| atlas.image_size_for_cell_width(u32::from(selector >> 6) + 1))
        .flatten();
    let map = MapLines::new(m, frame, atlas, size);
    let unmap = UnmapLines::new(m, frame);
    for line in text.lines() {
        if let Ok(Some(row)) = map.line(line) {
            // chart,u,v[,x,y]: the chart point must invert.
            let back = unmap.line(&row);
            assert!(
                matches!(back, Ok(Some(_))),
                "{m}: map gave {row:?} for {line:?}, unmap said {back:?}"
            );
        }
        let _ = unmap.line(line);
    }
});
