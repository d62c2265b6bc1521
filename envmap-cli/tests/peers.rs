//! envmap's default file conventions against the peer tools themselves:
//! Filament's `cmgen` (Debian's `libfilament-tools`) and `py360convert`
//! (PyPI), and its default EXR files read by OpenEXR's library through
//! OpenCV (PyPI). The tests are ignored by default (they need the tools);
//! `.ci/run` installs the tools and runs them, and a missing tool fails them:
//!
//! ```sh
//! apt-get install libfilament-tools && pip install py360convert numpy scipy "opencv-python-headless<4.11"
//! cargo test --release -p envmap-cli --test peers -- --ignored --nocapture
//! ```
//!
//! A smooth latlong goes through `envmap convert --to cube` and through each
//! tool; each face the tool writes must match envmap's face of the same
//! name best, against every other face and every turn or mirror of it,
//! and closely. The faces are compared, not the texels one by one: cmgen
//! averages nearest-texel samples and py360convert puts its edge texels on
//! the cube's edges, so the two tools differ from envmap by a fraction of a
//! texel.

use std::path::Path;
use std::process::Command;

use envmap_core::AnyMapping;
use envmap_render::image::FaceTurn;
use envmap_render::image::{load, save, LoadOptions, SaveOptions};
use envmap_render::image::{EnvImage, Representation, RgbImage};
use envmap_render::scene::{fill, smooth};

mod common;
use common::{envmap, text};

/// A file of little-endian f32 values (what the Python peers write).
fn raw_f32(path: &Path) -> Vec<f32> {
    std::fs::read(path)
        .unwrap()
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// The smooth test environment as an envmap latlong file (default
/// conventions), 512 × 256.
fn input(dir: &Path, name: &str) {
    let img = fill(
        Representation::for_file(AnyMapping::LatLong, Default::default()),
        512,
        256,
        smooth,
    )
    .unwrap();
    save(&img, dir.join(name), &SaveOptions::default()).unwrap();
}

/// Relative RMS difference of two faces.
fn rel_rms(a: &RgbImage, b: &RgbImage) -> f64 {
    let (mut se, mut ss) = (0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            let d = f64::from(p[c]) - f64::from(q[c]);
            se += d * d;
            ss += f64::from(q[c]) * f64::from(q[c]);
        }
    }
    (se / ss).sqrt()
}

/// Checks that face `k` of `theirs` matches face `k` of `ours` within `tol`
/// (relative RMS) and better than any other face in any of the eight turns.
fn same_faces(tool: &str, theirs: &EnvImage, ours: &EnvImage, tol: f64) {
    let turns = FaceTurn::ALL;
    for k in 0..6u32 {
        let t = theirs.chart_image(k).unwrap();
        let same = rel_rms(&t, &ours.chart_image(k).unwrap());
        let mut best_other = f64::INFINITY;
        for j in 0..6u32 {
            for turn in turns {
                if j == k && turn == FaceTurn::IDENTITY {
                    continue;
                }
                let o = turn.apply(&ours.chart_image(j).unwrap());
                best_other = best_other.min(rel_rms(&t, &o));
            }
        }
        println!(
            "{tool}: face {k}: {same:.4} relative RMS from envmap's, {best_other:.4} from the nearest other face or turn"
        );
        assert!(same < tol, "{tool} face {k}: {same}");
        assert!(
            same < 0.5 * best_other,
            "{tool} face {k}: {same} vs {best_other}"
        );
    }
}

fn ours(dir: &Path, extra: &[&str]) -> EnvImage {
    let mut args = vec![
        "convert", "in.exr", "ours.exr", "--to", "cube", "--size", "64", "--layout", "strip", "-q",
    ];
    args.extend_from_slice(extra);
    let o = envmap(&args, dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    load(dir.join("ours.exr"), &LoadOptions::default()).unwrap()
}

#[test]
#[ignore = "needs Filament's cmgen (apt-get install libfilament-tools); run with cargo test --release -p envmap-cli --test peers -- --ignored"]
fn the_default_cube_is_cmgens_without_mirroring_and_the_cmgen_preset_its_default() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    input(d, "in.exr");
    for (mirror, convention) in [(true, "envmap"), (false, "cmgen")] {
        let out = d.join(if mirror { "nomirror" } else { "mirror" });
        let mut cmd = Command::new("cmgen");
        cmd.args(["--format=exr", "--size=64", "-q"]);
        if mirror {
            cmd.arg("--no-mirror");
        }
        let o = cmd
            .arg(format!("--extract={}", out.display()))
            .arg(d.join("in.exr"))
            .output()
            .expect("run cmgen (apt-get install libfilament-tools)");
        assert!(o.status.success(), "{}", text(&o.stderr));
        // cmgen names its faces px nx py ny pz nz: envmap finds the six
        // from one of them.
        let theirs = load(out.join("in").join("px.exr"), &LoadOptions::default()).unwrap();
        let mine = ours(d, &["--convention", convention]);
        same_faces(&format!("cmgen ({convention})"), &theirs, &mine, 0.02);
    }
}

#[test]
#[ignore = "needs python3 with py360convert (pip install py360convert numpy scipy); run with cargo test --release -p envmap-cli --test peers -- --ignored"]
fn the_default_cube_is_py360converts() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    input(d, "in.exr");
    // The latlong as raw f32 for numpy; the faces come back the same way.
    let img = load(d.join("in.exr"), &LoadOptions::default()).unwrap();
    let raw: Vec<u8> = img
        .pixels()
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    std::fs::write(d.join("in.f32"), raw).unwrap();
    let script = "import numpy as np, py360convert\n\
        img = np.fromfile('in.f32', dtype='<f4').reshape(256, 512, 3)\n\
        faces = py360convert.e2c(img, face_w=64, mode='bilinear', cube_format='dict')\n\
        for k in 'RLUDFB':\n\
        \x20   faces[k].astype('<f4').tofile('face_%s.f32' % k)\n";
    let o = Command::new("python3")
        .args(["-c", script])
        .current_dir(d)
        .output()
        .expect("run python3 (pip install py360convert numpy scipy)");
    assert!(
        o.status.success(),
        "py360convert's conversion failed (pip install py360convert numpy scipy): {}",
        text(&o.stderr)
    );
    // R L U D F B are +x −x +y −y +z −z.
    let repr = Representation::new(
        AnyMapping::Cube,
        envmap_core::Atlas::CUBE_HORIZONTAL_STRIP,
        envmap_core::Frame::Y_UP_RH,
    )
    .unwrap();
    let mut theirs = EnvImage::new(6 * 64, 64, repr).unwrap();
    for (k, f) in "RLUDFB".chars().enumerate() {
        let px: Vec<[f32; 3]> = raw_f32(&d.join(format!("face_{f}.f32")))
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let face = RgbImage {
            width: 64,
            height: 64,
            pixels: px,
        };
        theirs.set_chart_image(k as u32, &face).unwrap();
    }
    same_faces("py360convert", &theirs, &ours(d, &[]), 0.02);
}

/// The cube cross `auto` writes (an RLE file whose lines through the empty
/// cells alone are compressed, the rest stored raw) and a bake's level,
/// read by OpenEXR's own library through OpenCV (`pip install
/// "opencv-python-headless<4.11" numpy`): every texel to the bit.
#[test]
#[ignore = "needs python3 with OpenCV (pip install \"opencv-python-headless<4.11\" numpy); run with cargo test --release -p envmap-cli --test peers -- --ignored"]
fn opencv_reads_the_default_cross_to_the_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    input(d, "in.exr");
    let o = envmap(
        &[
            "convert",
            "in.exr",
            "cross.exr",
            "--to",
            "cube",
            "--size",
            "48",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = envmap(&["bake", "in.exr", "--out", "ibl", "--size", "32", "-q"], d);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for file in ["cross.exr", "ibl/specular_0.exr", "ibl/specular_3.exr"] {
        let ours = load(d.join(file), &LoadOptions::default()).unwrap();
        let script = format!(
            "import os\n\
            os.environ['OPENCV_IO_ENABLE_OPENEXR'] = '1'\n\
            import cv2, numpy as np\n\
            a = cv2.imread('{file}', cv2.IMREAD_UNCHANGED)\n\
            assert a is not None and a.dtype == np.float32, 'not read as f32'\n\
            a[:, :, ::-1].astype('<f4').tofile('back.f32')\n\
            print(a.shape[1], a.shape[0])\n"
        );
        let o = Command::new("python3")
            .args(["-c", &script])
            .current_dir(d)
            .output()
            .expect(r#"run python3 (pip install "opencv-python-headless<4.11" numpy)"#);
        assert!(
            o.status.success(),
            r#"{file}: OpenCV's read failed (pip install "opencv-python-headless<4.11" numpy): {}"#,
            text(&o.stderr)
        );
        assert_eq!(
            text(&o.stdout).trim(),
            format!("{} {}", ours.width(), ours.height()),
            "{file}"
        );
        let theirs: Vec<u32> = raw_f32(&d.join("back.f32"))
            .iter()
            .map(|v| v.to_bits())
            .collect();
        let mine: Vec<u32> = ours
            .pixels()
            .iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect();
        assert!(theirs == mine, "{file}: OpenCV reads other texels");
    }
    // The cross was written as this test means: its empty half compressed.
    let size = std::fs::metadata(d.join("cross.exr")).unwrap().len();
    assert!(size < 6 * 48 * 48 * 12 * 21 / 20, "{size} bytes");
}
