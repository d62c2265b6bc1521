//! The bake directory from the library: the files `Baked::files`
//! makes equal, byte for byte, those `envmap bake --target …` writes, for
//! every preset; the engine upload data equals the KTX2 file's levels.

mod common;

use std::collections::BTreeMap;
use std::path::Path;

use envmap_core::AnyMapping;
use envmap_render::bake::{Baker, Preset, Target};
use envmap_render::image::FileFormat;
use envmap_render::image::{FileAxes, Representation, TexelFormat};
use envmap_render::scene::Builtin;

use common::{envmap, text};

/// The fields that hold timings (different in every run).
const TIMINGS: [&str; 3] = ["seconds", "load", "bake"];

fn without_timings(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            for k in TIMINGS {
                m.remove(k);
            }
            m.values_mut().for_each(without_timings);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(without_timings),
        _ => {}
    }
}

/// An OpenEXR file's header attributes (name → type and value) and what
/// follows the header. The `exr` crate writes the custom attributes in a
/// hash map's order, which differs from run to run; everything else is
/// compared byte for byte.
fn exr_parts(b: &[u8]) -> (BTreeMap<Vec<u8>, Vec<u8>>, &[u8]) {
    assert_eq!(&b[..4], b"\x76\x2f\x31\x01", "OpenEXR magic");
    let mut i = 8;
    let mut attrs = BTreeMap::new();
    let zero = |from: usize| from + b[from..].iter().position(|&c| c == 0).expect("NUL");
    while b[i] != 0 {
        let n = zero(i);
        let t = zero(n + 1);
        let size = u32::from_le_bytes(b[t + 1..t + 5].try_into().expect("size")) as usize;
        let value = b[n + 1..t + 5 + size].to_vec();
        attrs.insert(b[i..n].to_vec(), value);
        i = t + 5 + size;
    }
    (attrs, &b[i + 1..])
}

/// `a` and `b` are the same file: bytes, or JSON without timings, or EXR
/// with its attributes compared as a set.
fn same(name: &str, a: &[u8], b: &[u8]) {
    if name.ends_with(".json") {
        let mut x: serde_json::Value = serde_json::from_slice(a).expect("json");
        let mut y: serde_json::Value = serde_json::from_slice(b).expect("json");
        without_timings(&mut x);
        without_timings(&mut y);
        assert_eq!(x, y, "{name}");
    } else if name.ends_with(".exr") {
        let (ha, da) = exr_parts(a);
        let (hb, db) = exr_parts(b);
        assert_eq!(ha, hb, "{name}: header");
        assert!(da == db, "{name}: pixel data differs");
    } else {
        assert!(a == b, "{name}: {} against {} bytes", a.len(), b.len());
    }
}

const ENV_SIZE: u32 = 32;

fn source() -> envmap_render::image::EnvImage {
    let repr = Representation::for_file(AnyMapping::Cube, FileAxes::default());
    let (w, h) = repr
        .atlas
        .image_size_for_cell_width(ENV_SIZE)
        .expect("size");
    Builtin::Sky.image(repr, w, h).expect("sky")
}

#[test]
fn in_memory_files_equal_what_the_command_writes_for_every_preset() {
    let dir = tempfile::tempdir().expect("tempdir");
    let src = source();
    let name = format!("built-in sky (a cube of {ENV_SIZE}² faces)");
    for target in [
        None,
        Some(Target::Bevy),
        Some(Target::Gltf),
        Some(Target::Filament),
    ] {
        let label = target.map_or("envmap", Target::name);
        let out = dir.path().join(format!("ibl-{label}"));
        let mut args = vec![
            "bake".to_owned(),
            "sky".to_owned(),
            "--out".to_owned(),
            out.to_string_lossy().into_owned(),
            "--env-size".to_owned(),
            ENV_SIZE.to_string(),
            "--size".to_owned(),
            "16".to_owned(),
            "--irradiance-size".to_owned(),
            "4".to_owned(),
            "--dfg-size".to_owned(),
            "8".to_owned(),
            "-q".to_owned(),
        ];
        if let Some(t) = target {
            args.extend(["--target".to_owned(), t.name().to_owned()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = envmap(&args, dir.path());
        assert!(o.status.success(), "{label}: {}", text(&o.stderr));

        let mut preset = match target {
            Some(t) => Preset::for_target(t, FileAxes::default()),
            None => Preset::default(),
        };
        preset.size = 16;
        preset.irradiance_size = 4;
        preset.dfg_size = 8;
        let baked = Baker::with_preset(preset)
            .input_name(name.clone())
            .bake(&src)
            .expect("bake");
        let files = baked.files(&out).expect("in memory");
        let mut on_disk: Vec<String> = std::fs::read_dir(&out)
            .expect("out")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        on_disk.sort();
        let mut made: Vec<String> = files
            .files
            .iter()
            .map(|f| f.path.to_string_lossy().into_owned())
            .collect();
        made.sort();
        assert_eq!(made, on_disk, "{label}: the same files");
        for f in &files.files {
            let name = f.path.to_string_lossy();
            let disk = std::fs::read(out.join(&f.path)).expect("read");
            same(&format!("{label}/{name}"), &f.bytes, &disk);
        }
        // Nothing was written for the in-memory run.
        assert!(!Path::new(&format!("ibl-{label}")).exists());
    }
}

#[test]
fn engine_upload_data_is_the_ktx2_files_levels() {
    let src = source();
    let mut preset = Preset::for_target(Target::Gltf, FileAxes::default());
    preset.size = 16;
    preset.irradiance_size = 4;
    preset.dfg_size = 0;
    assert_eq!(preset.container, FileFormat::Ktx2);
    let baked = Baker::with_preset(preset)
        .input_name("sky")
        .bake(&src)
        .expect("bake");
    let up = baked.textures().expect("upload");
    let spec = up.specular.expect("chain");
    assert_eq!(spec.format, TexelFormat::Rgba16f);
    assert_eq!(spec.format.wgpu_name(), Some("Rgba16Float"));
    assert_eq!(
        spec.levels.len(),
        baked.bake().chain.as_ref().expect("chain").levels.len()
    );
    let files = baked.files("ibl").expect("files");
    let bytes = files.get("specular.ktx2").expect("specular.ktx2");
    let reader = ktx2::Reader::new(bytes).expect("a KTX2 file");
    let header = reader.header();
    assert_eq!(header.face_count, 6);
    assert_eq!(header.pixel_width, 16);
    for (k, (level, ours)) in reader.levels().zip(&spec.levels).enumerate() {
        assert_eq!(ours.faces.len(), 6);
        assert_eq!(ours.width, 16 >> k);
        assert!(level.data == ours.concatenated().as_slice(), "level {k}");
    }
    let irr = up.irradiance.expect("irradiance");
    let bytes = files.get("diffuse.ktx2").expect("diffuse.ktx2");
    let reader = ktx2::Reader::new(bytes).expect("a KTX2 file");
    let level = reader.levels().next().expect("level 0");
    assert!(level.data == irr.levels[0].concatenated().as_slice());
}

/// The chain's OpenEXR files, written from the levels' faces as the writer
/// asks for rows, read back: every face of every level exactly, the cells
/// without a face black, in each cube layout a bake writes as one image.
#[test]
fn exr_levels_read_back_face_for_face_in_every_layout() {
    use envmap_render::image::Layout;
    use envmap_render::image::{load, LoadOptions};
    let dir = tempfile::tempdir().expect("tempdir");
    let src = source();
    for layout in [Layout::Cross, Layout::VCross, Layout::Strip, Layout::VStrip] {
        let mut preset = Preset::default();
        preset.size = 16;
        preset.irradiance_size = 4;
        preset.dfg_size = 0;
        preset.layout = layout;
        let baked = Baker::with_preset(preset)
            .input_name("sky")
            .bake(&src)
            .expect("bake");
        let out = dir.path().join(layout.name());
        baked.write(&out).expect("write");
        let baked = baked.bake();
        let atlas = layout.atlas();
        let chain = baked.chain.as_ref().expect("chain");
        let images = chain
            .levels
            .iter()
            .enumerate()
            .map(|(k, l)| (format!("specular_{k}.exr"), l))
            .chain(
                baked
                    .irradiance
                    .as_ref()
                    .map(|i| ("irradiance.exr".to_owned(), &i.image)),
            );
        for (name, level) in images {
            let file = load(out.join(&name), &LoadOptions::default()).expect("load");
            let what = format!("{} {name}", layout.name());
            assert_eq!(file.atlas(), &atlas, "{what}");
            for f in 0..6 {
                assert_eq!(file.chart_image(f), level.chart_image(f), "{what} face {f}");
            }
            let (cw, ch) = file.cell_size();
            for r in 0..atlas.rows {
                for c in 0..atlas.cols {
                    if atlas.cell_at(c, r).is_some() {
                        continue;
                    }
                    let black = (r * ch..(r + 1) * ch)
                        .all(|y| (c * cw..(c + 1) * cw).all(|x| file.get(x, y) == [0.0; 3]));
                    assert!(black, "{what}: cell {c},{r}");
                }
            }
        }
    }
}

/// The files of one directory, by name.
fn files_of(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| {
            let e = e.expect("entry");
            let name = e.file_name().to_string_lossy().into_owned();
            (name, std::fs::read(e.path()).expect("read"))
        })
        .collect()
}

/// `Baker::bake_into` (each OpenEXR level written while the next is made)
/// writes the files `Baker::bake` then `Baked::write` write, in every layout
/// and container; cancelled while it bakes, it leaves no file and no
/// directory.
#[test]
fn bake_into_writes_what_a_bake_then_write_writes_and_nothing_when_cancelled() {
    use envmap_render::image::Layout;
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let dir = tempfile::tempdir().expect("tempdir");
    let src = source();
    let mut presets = Vec::new();
    for layout in [Layout::Cross, Layout::Strip, Layout::Faces] {
        let mut p = Preset::default();
        p.layout = layout;
        presets.push((layout.name().to_owned(), p));
    }
    for t in [Target::Bevy, Target::Gltf, Target::Filament] {
        presets.push((
            t.name().to_owned(),
            Preset::for_target(t, FileAxes::default()),
        ));
    }
    for (label, mut preset) in presets {
        // Two levels at least, in every rule.
        preset.size = 32;
        preset.irradiance_size = 4;
        preset.dfg_size = 8;
        let baker = Baker::with_preset(preset).input_name("sky");
        // The same name (KTX 1 files are named after their directory).
        let a = dir.path().join("a").join(&label);
        let b = dir.path().join("b").join(&label);
        let baked = baker.bake(src.clone()).expect("bake");
        baked.write(&a).expect("write");
        let baked = baked.bake();
        let levels = AtomicUsize::new(0);
        let progress = |k: usize, _: usize| {
            levels.fetch_max(k, Ordering::Relaxed);
        };
        let into = baker
            .clone()
            .progress(&progress)
            .bake_into(src.clone(), &b)
            .expect("bake into");
        let chain = into.bake().chain.as_ref().expect("chain");
        assert_eq!(
            levels.load(Ordering::Relaxed) + 1,
            chain.levels.len(),
            "{label}"
        );
        for (x, y) in chain
            .levels
            .iter()
            .zip(&baked.chain.as_ref().expect("chain").levels)
        {
            assert!(x.pixels() == y.pixels(), "{label}: the same bake");
        }
        let (fa, fb) = (files_of(&a), files_of(&b));
        assert_eq!(
            fa.keys().collect::<Vec<_>>(),
            fb.keys().collect::<Vec<_>>(),
            "{label}: the same files"
        );
        for (name, bytes) in &fa {
            same(&format!("{label}/{name}"), bytes, &fb[name]);
        }
        let mut written: Vec<String> = into
            .written()
            .expect("written")
            .0
            .files
            .iter()
            .map(|p| p.file_name().expect("name").to_string_lossy().into_owned())
            .collect();
        written.sort();
        assert_eq!(written, fb.keys().cloned().collect::<Vec<_>>(), "{label}");

        // Stopped as level 1 starts: level 0 may be staged already.
        let stop = AtomicBool::new(false);
        let c = dir.path().join(format!("{label}-cancelled"));
        let stopping = |k: usize, _: usize| {
            if k == 1 {
                stop.store(true, Ordering::Relaxed);
            }
        };
        let e = baker
            .clone()
            .cancel(&stop)
            .progress(&stopping)
            .bake_into(src.clone(), &c);
        let Err(e) = e else {
            panic!("{label}: not cancelled");
        };
        assert!(e.to_string().contains("cancel"), "{label}: {e}");
        assert!(!c.exists(), "{label}: the new directory is removed");
    }
}
