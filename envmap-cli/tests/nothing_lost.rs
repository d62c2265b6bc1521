//! Nothing lost: failed writes leave no partial file and the previous file
//! intact, inputs are never modified, f32 data round-trips bit for bit, and
//! NaN / infinite texels are counted and handled as documented.

use std::fs;
use std::path::Path;
use std::process::Command;

use envmap_core::AnyMapping;
use envmap_render::filter::{convert, ConvertOptions};
use envmap_render::image::load_detailed;
use envmap_render::image::{save, EnvImage, LoadOptions, NonFinite, Representation, SaveOptions};
use envmap_render::scene::{fill, smooth};

mod common;
use common::{entries, envmap, text};

fn sky(w: u32) -> EnvImage {
    fill(
        Representation::default_for(AnyMapping::LatLong),
        w,
        w / 2,
        smooth,
    )
    .unwrap()
}

/// A latlong with one NaN texel (a quiet NaN with a payload), one +Inf and
/// one −Inf component, next to ordinary values.
fn with_bad_texels() -> EnvImage {
    let mut img = sky(32);
    img.set(5, 3, [f32::from_bits(0x7fc0_1234), 1.0, 1.0]);
    img.set(20, 8, [1.0, f32::INFINITY, 1.0]);
    img.set(9, 12, [1.0, 1.0, f32::NEG_INFINITY]);
    img
}

fn finite(img: &EnvImage) -> bool {
    img.pixels().iter().flatten().all(|c| c.is_finite())
}

#[test]
fn exr_f32_keeps_every_bit_pattern() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bits.exr");
    let mut img = with_bad_texels();
    img.set(
        0,
        0,
        [-0.0, f32::from_bits(1), -f32::from_bits(0x007f_ffff)],
    );
    img.set(1, 0, [f32::MAX, -f32::MAX, f32::from_bits(0xffc0_0001)]);
    save(&img, &path, &SaveOptions::default()).unwrap();
    let loaded = load_detailed(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.replaced, 0);
    for (a, b) in loaded.image.pixels().iter().zip(img.pixels()) {
        assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
    }
}

#[test]
fn non_finite_texels_are_kept_or_replaced_as_asked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.exr");
    save(&with_bad_texels(), &path, &SaveOptions::default()).unwrap();

    // Kept: counted by the statistics, and (as documented) spread by the
    // filter over the output texels whose footprint covers them.
    let kept = load_detailed(&path, &LoadOptions::default()).unwrap();
    let s = kept.image.stats();
    assert_eq!((s.nan, s.inf, kept.replaced), (1, 2, 0));
    assert!(s.mean.iter().all(|m| m.is_finite()));
    let cube = Representation::default_for(AnyMapping::Cube);
    let (w, h) = cube.atlas.image_size_for_cell_width(8).unwrap();
    let out = convert(&kept.image, cube, w, h, &ConvertOptions::default(), None).unwrap();
    assert!(!finite(&out));

    // Replaced by black at load time: nothing reaches the filter.
    let opts = {
        let mut o = LoadOptions::default();
        o.non_finite = NonFinite::Zero;
        o
    };
    let zeroed = load_detailed(&path, &opts).unwrap();
    assert_eq!(zeroed.replaced, 3);
    let s = zeroed.image.stats();
    assert_eq!((s.nan, s.inf), (0, 0));
    assert_eq!(zeroed.image.get(5, 3), [0.0; 3]);
    assert_eq!(zeroed.image.get(20, 8), [0.0; 3]);
    assert_eq!(zeroed.image.get(6, 3), kept.image.get(6, 3));
    let out = convert(&zeroed.image, cube, w, h, &ConvertOptions::default(), None).unwrap();
    assert!(finite(&out));

    // Six-file cubes count over all faces.
    let faces = dir.path().join("c.exr");
    let mut c = convert(&zeroed.image, cube, w, h, &ConvertOptions::default(), None).unwrap();
    assert!(c.set_chart_texel(1, 2, 3, [f32::NAN; 3]));
    assert!(c.set_chart_texel(5, 0, 0, [0.0, f32::INFINITY, 0.0]));
    let six = {
        let mut o = SaveOptions::default();
        o.six_files = true;
        o
    };
    save(&c, &faces, &six).unwrap();
    let loaded = load_detailed(dir.path().join("c_+x.exr"), &opts).unwrap();
    assert_eq!(loaded.replaced, 2);
    assert!(finite(&loaded.image));
}

#[test]
fn info_counts_and_convert_replaces_non_finite_texels() {
    let dir = tempfile::tempdir().unwrap();
    save(
        &with_bad_texels(),
        dir.path().join("bad.exr"),
        &SaveOptions::default(),
    )
    .unwrap();
    let o = envmap(&["info", "bad.exr"], dir.path());
    let out = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(out.contains("NaN texels       1\n"), "{out}");
    assert!(out.contains("Inf texels       2\n"), "{out}");
    // 32 × 16 texels of 12 bytes, and twice that for a conversion.
    assert!(out.contains("memory           0.0 MiB"), "{out}");
    assert!(
        out.contains("conversion       needs about 0.0 MiB"),
        "{out}"
    );

    let o = envmap(
        &[
            "convert", "bad.exr", "out.exr", "--to", "cube", "--size", "8", "-q",
        ],
        dir.path(),
    );
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("bad.exr: 3 texels with NaN or infinite values replaced by black"),
        "{err}"
    );
    let out =
        envmap_render::image::load(dir.path().join("out.exr"), &LoadOptions::default()).unwrap();
    assert!(finite(&out));
}

#[test]
fn the_size_limit_is_stated_and_can_be_raised() {
    let dir = tempfile::tempdir().unwrap();
    save(
        &sky(2048),
        dir.path().join("big.exr"),
        &SaveOptions::default(),
    )
    .unwrap();
    for cmd in ["info", "convert", "render"] {
        let mut args = vec![cmd, "big.exr"];
        if cmd == "convert" {
            args.extend(["out.exr", "--to", "cube", "-q"]);
        }
        if cmd == "render" {
            args = vec![
                cmd, "out.png", "--env", "big.exr", "--width", "32", "--height", "24",
            ];
        }
        args.extend(["--max-megatexels", "1"]);
        let o = envmap(&args, dir.path());
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains(
                "big.exr: image is 2048×1024 (2097152 texels), above the limit of 1000000 texels \
                 (raise the limit with --max-megatexels)"
            ),
            "{err}"
        );
        args.pop();
        args.push("3");
        let o = envmap(&args, dir.path());
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
}

/// Whether this process can create files in a directory without write
/// permission (it runs as root, or with CAP_DAC_OVERRIDE).
#[cfg(unix)]
fn permissions_are_ignored(dir: &Path) -> bool {
    let probe = dir.join("probe");
    let ignored = fs::write(&probe, b"").is_ok();
    let _ = fs::remove_file(&probe);
    ignored
}

#[cfg(unix)]
#[test]
fn a_read_only_directory_leaves_the_old_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let ro = dir.path().join("ro");
    fs::create_dir(&ro).unwrap();
    let target = ro.join("out.exr");
    fs::write(&target, b"the good old file").unwrap();
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
    if permissions_are_ignored(&ro) {
        // Root writes anyway: the same save by the `envmap` command run as
        // user 65534 (`setpriv`, util-linux), from a copy of the binary in
        // the temporary directory so that the user can run it wherever the
        // build is.
        let d = dir.path();
        fs::set_permissions(d, fs::Permissions::from_mode(0o755)).unwrap();
        let exe = d.join("envmap");
        fs::copy(env!("CARGO_BIN_EXE_envmap"), &exe).unwrap();
        save(&sky(16), d.join("in.exr"), &SaveOptions::default()).unwrap();
        fs::set_permissions(d.join("in.exr"), fs::Permissions::from_mode(0o644)).unwrap();
        let o = Command::new("setpriv")
            .args(["--reuid=65534", "--regid=65534", "--clear-groups"])
            .arg(&exe)
            .args(["convert", "in.exr"])
            .arg(&target)
            .args(["--to", "latlong", "-q"])
            .current_dir(d)
            .output()
            .expect(
                "run setpriv (util-linux): as root, the read-only case runs the command as \
                 an unprivileged user",
            );
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains(&format!("{}: cannot write:", target.display())),
            "{err}"
        );
    } else {
        let e = save(&sky(16), &target, &SaveOptions::default()).unwrap_err();
        let m = e.to_string();
        assert!(
            m.starts_with(&format!("{}: cannot write:", target.display())),
            "{m}"
        );
    }
    assert_eq!(fs::read(&target).unwrap(), b"the good old file");
    assert_eq!(entries(&ro), ["out.exr"]);
    fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
}

/// A file-size limit (`ulimit -f`, with SIGXFSZ ignored so that the write
/// fails with EFBIG instead of killing the process) makes the encoder's
/// writes fail partway through the output, as a full disk would, whoever
/// runs the test.
#[cfg(unix)]
#[test]
fn a_write_that_fails_partway_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    save(
        &sky(256),
        dir.path().join("in.exr"),
        &SaveOptions::default(),
    )
    .unwrap();
    let input = fs::read(dir.path().join("in.exr")).unwrap();
    for out in ["out.exr", "out.hdr", "out.png", "out_{face}.exr"] {
        let old = dir.path().join(out.replace("{face}", "+x"));
        fs::write(&old, b"the good old file").unwrap();
        let before = entries(dir.path());
        let script = format!(
            "trap '' XFSZ; ulimit -f 16; exec '{}' convert in.exr '{out}' --to cube --size 128 -q",
            env!("CARGO_BIN_EXE_envmap")
        );
        let o = Command::new("sh")
            .arg("-c")
            .arg(&script)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{out}: {err}");
        assert!(err.contains("cannot write"), "{out}: {err}");
        assert!(err.contains("File too large"), "{out}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        // No temporary file left, the old file as it was, the input untouched.
        assert_eq!(entries(dir.path()), before, "{out}");
        assert_eq!(fs::read(&old).unwrap(), b"the good old file", "{out}");
        assert_eq!(fs::read(dir.path().join("in.exr")).unwrap(), input);
        fs::remove_file(&old).unwrap();
    }
    // Without the limit the same commands succeed (so the limit is what
    // made them fail).
    let o = envmap(
        &[
            "convert", "in.exr", "out.exr", "--to", "cube", "--size", "128", "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
}

#[test]
fn inputs_are_never_modified() {
    let dir = tempfile::tempdir().unwrap();
    let img = sky(64);
    let names = ["in.exr", "in.hdr", "in.png"];
    for n in names {
        save(&img, dir.path().join(n), &SaveOptions::default()).unwrap();
    }
    let snapshot = || -> Vec<(Vec<u8>, std::time::SystemTime)> {
        names
            .iter()
            .map(|n| {
                let p = dir.path().join(n);
                (
                    fs::read(&p).unwrap(),
                    fs::metadata(&p).unwrap().modified().unwrap(),
                )
            })
            .collect()
    };
    let before = snapshot();
    for n in names {
        let runs: [&[&str]; 6] = [
            &["info", n],
            &["convert", n, "out.exr", "--to", "cube", "-q"],
            &[
                "convert",
                n,
                "o_{face}.png",
                "--to",
                "cube",
                "--size",
                "8",
                "-q",
            ],
            // Failing conversions: the output is the input, a bad size, a
            // directory as output.
            &["convert", n, n, "--to", "latlong", "-q"],
            &[
                "convert",
                n,
                "x.exr",
                "--to",
                "tennisball",
                "--size",
                "7",
                "-q",
            ],
            &["convert", n, ".", "--to", "cube", "-q"],
        ];
        for (k, args) in runs.iter().enumerate() {
            let o = envmap(args, dir.path());
            assert_eq!(o.status.success(), k < 3, "{args:?}: {}", text(&o.stderr));
        }
    }
    assert!(before == snapshot(), "an input changed");
}
