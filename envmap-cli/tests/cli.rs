//! The `envmap` command run as a user runs it: happy paths and mistakes.

use std::path::Path;
use std::process::Output;

use envmap_core::AnyMapping;
use envmap_render::image::Representation;
use envmap_render::image::{save, SaveOptions};
use envmap_render::scene::{fill, smooth};

mod common;
use common::{envmap, envmap_stdin, text};

/// Asserts a user-facing failure: exit code, message naming `needle`, no panic.
fn assert_fails(o: &Output, code: i32, needle: &str) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    assert!(err.contains(needle), "expected '{needle}' in: {err}");
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{err}"
    );
}

fn latlong_file(dir: &Path, name: &str, w: u32) {
    let img = fill(
        Representation::default_for(AnyMapping::LatLong),
        w,
        w / 2,
        smooth,
    )
    .unwrap();
    save(&img, dir.join(name), &SaveOptions::default()).unwrap();
}

#[test]
fn convert_and_info_happy_paths() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    latlong_file(d, "sky.hdr", 256);
    let o = envmap(
        &[
            "convert", "sky.hdr", "cube.exr", "--to", "cube", "--layout", "cross", "--size", "32",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = envmap(&["info", "cube.exr"], d);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let info = text(&o.stdout);
    assert!(
        info.contains("128 × 96") && info.contains("cube") && info.contains("cross"),
        "{info}"
    );
    assert!(info.contains("NaN texels       0"), "{info}");
    // Six files, and back to a latlong PNG with a rotation.
    let o = envmap(
        &[
            "convert",
            "cube.exr",
            "face_{face}.png",
            "--to",
            "cube",
            "--size",
            "16",
            "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    for f in ["+x", "-x", "+y", "-y", "+z", "-z"] {
        assert!(d.join(format!("face_{f}.png")).exists(), "{f}");
    }
    let o = envmap(
        &[
            "convert",
            "face_+x.png",
            "back.png",
            "--to",
            "latlong",
            "--size",
            "64",
            "--rotate",
            "90,-10,0",
            "--threads",
            "2",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = envmap(&["info", "back.png"], d);
    assert!(text(&o.stdout).contains("64 × 32"));
    // Every other mapping.
    for (m, size) in [
        ("sphere", "48"),
        ("paraboloid", "64"),
        ("tennisball", "48"),
        ("octahedral-equal-area", "32"),
    ] {
        let o = envmap(
            &[
                "convert",
                "sky.hdr",
                &format!("{m}.exr"),
                "--to",
                m,
                "--size",
                size,
                "-q",
            ],
            d,
        );
        assert!(o.status.success(), "{m}: {}", text(&o.stderr));
    }
    // A square image envmap wrote says what it holds; info reads it.
    let o = envmap(&["info", "sphere.exr"], d);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let info = text(&o.stdout);
    assert!(info.contains("mapping          sphere\n"), "{info}");
    assert!(info.contains("as the file says"), "{info}");
    // One that does not say needs --from; with it, info works.
    let plain = envmap_render::image::RgbImage {
        width: 8,
        height: 8,
        pixels: vec![[0.5; 3]; 64],
    };
    envmap_render::image::write_rgb(&plain, d.join("square.exr"), &SaveOptions::default()).unwrap();
    let o = envmap(&["info", "square.exr"], d);
    assert_fails(&o, 1, "square.exr");
    let o = envmap(&["info", "square.exr", "--from", "sphere"], d);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("the default: the file does not say"));
}

#[test]
fn map_and_unmap_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = "# directions\n1 0 0\n0,1,0\n-0.3, 0.5, 0.8\n0 0 -1\n";
    for m in AnyMapping::NAMES {
        let o = envmap_stdin(&["map", "--mapping", m], d, input);
        assert!(o.status.success(), "{m}: {}", text(&o.stderr));
        let coords = text(&o.stdout);
        assert!(coords.starts_with("chart,u,v\n"), "{coords}");
        let o = envmap_stdin(&["unmap", "--mapping", m], d, &coords);
        assert!(o.status.success(), "{m}: {}", text(&o.stderr));
        // Rows of numbers; an empty row (",,") for a direction a fisheye does not see.
        let dirs: Vec<Vec<f32>> = text(&o.stdout)
            .lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .filter(|t| !t.is_empty())
                    .map(|t| t.parse().unwrap())
                    .collect()
            })
            .collect();
        let want: [[f32; 3]; 4] = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-0.3, 0.5, 0.8],
            [0.0, 0.0, -1.0],
        ];
        assert_eq!(dirs.len(), 4, "{m}");
        for (g, w) in dirs.iter().zip(want) {
            if g.is_empty() {
                // The one-lens fisheye (180°, along +z) does not see −z.
                assert!(m == "fisheye" && w[2] < 0.0, "{m}: {w:?} unseen");
                continue;
            }
            let n = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            for k in 0..3 {
                assert!((g[k] - w[k] / n).abs() < 1e-5, "{m}: {g:?} vs {w:?}");
            }
        }
    }
    // Texel coordinates with --size: +x is face 0, centre texel of a 4-wide face in a cross.
    let o = envmap_stdin(&["map", "--mapping", "cube", "--size", "4"], d, "1 0 0\n");
    assert_eq!(text(&o.stdout), "chart,u,v,x,y\n0,0.5,0.5,10,6\n");
    // A y-up frame: +y is the latlong's top row.
    let o = envmap_stdin(
        &["map", "--mapping", "latlong", "--frame", "y-up"],
        d,
        "0 1 0\n",
    );
    assert!(
        text(&o.stdout).lines().nth(1).unwrap().ends_with(",0"),
        "{}",
        text(&o.stdout)
    );
}

#[test]
fn mistakes_get_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Missing file.
    let o = envmap(&["info", "nope.exr"], d);
    assert_fails(&o, 1, "nope.exr");
    // Unknown extension.
    std::fs::write(d.join("sky.tga"), b"not an image").unwrap();
    let o = envmap(&["convert", "sky.tga", "out.png", "--to", "cube"], d);
    assert_fails(&o, 1, "sky.tga");
    // Corrupt file with a known extension.
    std::fs::write(d.join("bad.png"), b"\x89PNG\r\n\x1a\nbroken").unwrap();
    let o = envmap(&["info", "bad.png"], d);
    assert_fails(&o, 1, "bad.png");
    // Wrong aspect ratio.
    let img = fill(
        Representation::default_for(AnyMapping::LatLong),
        64,
        32,
        smooth,
    )
    .unwrap();
    let rgb = envmap_render::image::RgbImage {
        width: 50,
        height: 30,
        pixels: img.pixels()[..1500].to_vec(),
    };
    envmap_render::image::write_rgb(&rgb, d.join("odd.png"), &SaveOptions::default()).unwrap();
    let o = envmap(&["convert", "odd.png", "out.exr", "--to", "cube"], d);
    assert_fails(&o, 1, "odd.png");
    assert!(!d.join("out.exr").exists());
    // Faces of different sizes.
    latlong_file(d, "sky.hdr", 64);
    let o = envmap(
        &[
            "convert",
            "sky.hdr",
            "f_{face}.png",
            "--to",
            "cube",
            "--size",
            "8",
            "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let small = fill(
        Representation::default_for(AnyMapping::Octahedral),
        4,
        4,
        smooth,
    )
    .unwrap();
    save(&small, d.join("f_-y.png"), &SaveOptions::default()).unwrap();
    let o = envmap(&["info", "f_+x.png"], d);
    assert_fails(&o, 1, "f_-y.png");
    // Writing over the input is refused, and the input is untouched.
    let before = std::fs::read(d.join("sky.hdr")).unwrap();
    let o = envmap(
        &[
            "convert", "sky.hdr", "sky.hdr", "--to", "latlong", "--size", "32",
        ],
        d,
    );
    assert_fails(&o, 1, "sky.hdr");
    assert_eq!(std::fs::read(d.join("sky.hdr")).unwrap(), before);
    // Bad values.
    let o = envmap(
        &[
            "convert",
            "sky.hdr",
            "o.png",
            "--to",
            "tennisball",
            "--size",
            "100",
        ],
        d,
    );
    assert_fails(&o, 1, "divisible by 3");
    let o = envmap(
        &[
            "convert",
            "sky.hdr",
            "o.png",
            "--to",
            "cube",
            "--samples",
            "0",
        ],
        d,
    );
    assert_fails(&o, 1, "--samples");
    let o = envmap(&["convert", "sky.hdr", "o.png", "--to", "cubic"], d);
    assert_fails(&o, 2, "unknown mapping");
    let o = envmap(
        &[
            "convert", "sky.hdr", "o.png", "--to", "latlong", "--layout", "cross",
        ],
        d,
    );
    assert_fails(&o, 1, "cross");
    // Bad map input names the line.
    let o = envmap_stdin(&["map", "--mapping", "cube"], d, "1 0 0\n1 two 3\n");
    assert_fails(&o, 1, "<stdin>:2");
    let o = envmap_stdin(&["map", "--mapping", "cube"], d, "0 0 0\n");
    assert_fails(&o, 1, "<stdin>:1");
    let o = envmap_stdin(&["map", "--mapping", "latlong"], d, "x,y,z\nnan 0 1\n");
    assert_fails(&o, 1, "<stdin>:2");
    let o = envmap(
        &[
            "convert", "sky.hdr", "o.png", "--to", "latlong", "--size", "33",
        ],
        d,
    );
    assert_fails(&o, 1, "try 32 or 34");
    let o = envmap_stdin(&["unmap", "--mapping", "cube"], d, "7,0.5,0.5\n");
    assert_fails(&o, 1, "chart 7");
    let o = envmap_stdin(&["unmap", "--mapping", "sphere"], d, "0,0.01,0.01\n");
    assert_fails(&o, 1, "outside");
}

#[test]
fn render_happy_paths_and_mistakes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for args in [
        &[
            "render",
            "a.png",
            "--env",
            "sky",
            "--mapping",
            "latlong",
            "--env-size",
            "256",
            "--width",
            "64",
            "--height",
            "48",
        ][..],
        &[
            "render",
            "b.exr",
            "--env",
            "room",
            "--object",
            "sphere",
            "--mode",
            "per-vertex",
            "--width",
            "64",
            "--height",
            "48",
            "--samples",
            "1",
        ][..],
        &[
            "render",
            "c.png",
            "--env",
            "sky",
            "--analytic",
            "--object",
            "torus",
            "--eye",
            "3,-6,3",
            "--fresnel",
            "0.04",
            "--width",
            "32",
            "--height",
            "32",
        ][..],
    ] {
        let o = envmap(args, d);
        assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
        assert!(d.join(args[1]).exists());
    }
    let o = envmap(
        &["info", "b.exr", "--from", "latlong", "--layout", "latlong"],
        d,
    );
    assert_fails(&o, 1, "b.exr");
    let o = envmap(&["render", "x.png", "--env", "nowhere.hdr"], d);
    assert_fails(&o, 1, "nowhere.hdr");
    let o = envmap(&["render", "x.png", "--object", "cow"], d);
    assert_fails(&o, 1, "unknown object");
    let o = envmap(&["render", "x.png", "--eye", "0,0"], d);
    assert_fails(&o, 2, "--eye");
}

/// The demo runs end to end at a small size and writes what it promises.
#[test]
fn demo_runs_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = envmap(
        &[
            "demo",
            "--out",
            "demo",
            "--ktexels",
            "6",
            "--width",
            "48",
            "--samples",
            "1",
            "--reference-samples",
            "8",
            "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let table = text(&o.stdout);
    // Every mapping that holds the whole sky.
    for m in AnyMapping::ALL
        .into_iter()
        .filter(|m| m.covers_sphere())
        .map(|m| envmap_core::Mapping::name(&m))
    {
        assert!(
            table.contains(&format!("| {m} |")),
            "{m} missing from {table}"
        );
        for f in [
            "atlas_{}.png",
            "teapot_{}_per_pixel.png",
            "teapot_{}_per_vertex.png",
            "error_{}_per_pixel.png",
        ] {
            let name = f.replace("{}", m);
            assert!(d.join("demo").join(&name).exists(), "{name}");
        }
    }
    let report = std::fs::read_to_string(d.join("demo/report.md")).unwrap();
    assert!(
        report.contains("PSNR per pixel") && report.contains("octahedral-equal-area"),
        "{report}"
    );
    // Every PSNR is a finite number well above noise.
    let (mappings, lit) = report.split_once("## Lit").expect("the lit section");
    let rows = |table: &str, header: &str| -> Vec<Vec<String>> {
        table
            .lines()
            .filter(|l| l.starts_with("| ") && !l.contains(header) && !l.contains("---"))
            .map(|l| l.split('|').map(|c| c.trim().to_owned()).collect())
            .collect()
    };
    for cells in rows(mappings, "representation") {
        let p: f64 = cells[5].parse().unwrap();
        assert!(p.is_finite() && p > 15.0, "{cells:?}");
    }
    // The lit section: ten spheres in each environment and three teapots,
    // the split sum's PSNR against the reference finite and above 15 dB.
    let lit_rows = rows(lit, "scene");
    assert_eq!(lit_rows.len(), 23, "{lit}");
    for cells in &lit_rows {
        let p: f64 = cells[4].parse().unwrap();
        assert!(p.is_finite() && p > 15.0, "{cells:?}");
    }
    for name in [
        "spheres_sky.png",
        "spheres_sky_reference.png",
        "error_spheres_sky.png",
        "spheres_room.png",
        "spheres_room_reference.png",
        "error_spheres_room.png",
        "teapots_lit.png",
        "teapots_lit_reference.png",
        "error_teapots_lit.png",
        "seed002_lit_teapots.png",
    ] {
        assert!(d.join("demo").join(name).exists(), "{name}");
    }
    assert!(
        table.contains("| sphere, room | gold (metal) | 1.00 |"),
        "{table}"
    );
}

#[test]
fn help_states_the_exit_codes() {
    let dir = tempfile::tempdir().unwrap();
    let o = envmap(&["--help"], dir.path());
    assert!(o.status.success());
    let out = text(&o.stdout);
    assert!(
        out.contains("Exit status: 0 success; 1 an error while running"),
        "{out}"
    );
    assert!(out.contains("2 a usage error"), "{out}");
    let o = envmap(&["bogus"], dir.path());
    assert_fails(&o, 2, "unrecognized subcommand 'bogus'");
}

#[test]
fn bake_writes_every_output_and_refuses_mistakes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    latlong_file(d, "in.hdr", 256);
    // A built-in, with no file at all, and a file.
    for input in ["sky", "in.hdr"] {
        let out = d.join(format!("bake-{input}"));
        let o = envmap(
            &[
                "bake",
                input,
                "--out",
                out.to_str().unwrap(),
                "--size",
                "32",
                "--env-size",
                "64",
                "--quality",
                "draft",
                "--check",
                "50",
            ],
            d,
        );
        assert!(o.status.success(), "{}", text(&o.stderr));
        let err = text(&o.stderr);
        assert!(err.contains("| level |") && err.contains("E/pi"), "{err}");
        let mut names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        // 32, 16, 8, 4, 2: five levels by the linear rule's 2² floor.
        let mut want: Vec<String> = (0..5).map(|k| format!("specular_{k}.exr")).collect();
        want.extend(
            [
                "dfg.exr",
                "dfg_multiscatter.exr",
                "irradiance.exr",
                "manifest.json",
                "sh.json",
            ]
            .map(String::from),
        );
        want.sort();
        assert_eq!(names, want);
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap())
                .unwrap();
        assert_eq!(m["irradiance"]["value"], "E/pi");
        assert_eq!(m["specular"]["roughness_rule"], "linear");
        assert_eq!(m["specular"]["levels"][4]["perceptual_roughness"], 1.0);
        // --check: every level above 0, the irradiance map and the SH9
        // measured against the oracle of the input itself.
        let mut measured = 0;
        for l in m["specular"]["levels"].as_array().unwrap().iter().skip(1) {
            let e = l["measured"]["relative_rms_error"].as_f64().unwrap();
            assert!(e.is_finite() && e < 0.05, "{l}");
            measured += 1;
        }
        assert_eq!(measured, 4, "{m}");
        let e = m["irradiance"]["measured"]["relative_rms_error"]
            .as_f64()
            .unwrap();
        assert!(e.is_finite() && e < 0.2, "{m}");
        let e = m["sh"]["measured_relative_error"].as_f64().unwrap();
        assert!(e < 1e-3, "{m}");
        let energy = &m["specular"]["energy"];
        assert!(energy["relative_gap"].as_f64().unwrap() < 1e-3, "{energy}");
        let sh: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("sh.json")).unwrap()).unwrap();
        assert_eq!(sh["filament"]["value"], "E/pi");
        assert_eq!(
            sh["irradiance"]["coefficients"]["L00"]
                .as_array()
                .unwrap()
                .len(),
            3
        );
        // The irradiance cube reads back as a 32² cross.
        let o = envmap(&["info", out.join("irradiance.exr").to_str().unwrap()], d);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let info = text(&o.stdout);
        assert!(info.contains("cube"), "{info}");
        // The files say what they hold.
        assert!(
            info.lines()
                .any(|l| l.starts_with("content") && l.contains("irradiance E/pi")),
            "{info}"
        );
        let o = envmap(&["info", out.join("specular_4.exr").to_str().unwrap()], d);
        let info = text(&o.stdout);
        assert!(
            info.contains("level 4 of 5, perceptual roughness 1.0000"),
            "{info}"
        );
    }
    // A ringing sun (a lossy EXR's negative texels): counted by info, and
    // the bake's outputs clamped at zero with the count in the manifest.
    let ring = fill(
        Representation::default_for(AnyMapping::LatLong),
        256,
        128,
        |v| {
            let c = v.normalize().z;
            if c > 0.9995 {
                [3e4; 3]
            } else if c > 0.995 {
                [-3894.0, -20.0, 0.5]
            } else {
                [0.2; 3]
            }
        },
    )
    .unwrap();
    let negative = ring
        .pixels()
        .iter()
        .filter(|p| p.iter().any(|c| *c < 0.0))
        .count();
    assert!(negative > 0);
    save(&ring, d.join("ring.exr"), &SaveOptions::default()).unwrap();
    let o = envmap(&["info", "ring.exr"], d);
    let info = text(&o.stdout);
    assert!(
        info.lines()
            .any(|l| l.starts_with("negative texels") && l.contains(&format!(" {negative} ("))),
        "{info}"
    );
    let rb = d.join("ring-bake");
    let o = envmap(
        &[
            "bake",
            "ring.exr",
            "--out",
            rb.to_str().unwrap(),
            "--size",
            "32",
            "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(rb.join("manifest.json")).unwrap()).unwrap();
    let clamped: u64 = m["specular"]["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["texels_clamped_at_zero"].as_u64().unwrap())
        .sum();
    assert!(clamped > 0, "{m}");
    // SH alone.
    let only = d.join("sh-only");
    let o = envmap(
        &[
            "bake",
            "in.hdr",
            "--out",
            only.to_str().unwrap(),
            "--sh-only",
            "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let n = std::fs::read_dir(&only).unwrap().count();
    assert_eq!(n, 2, "sh.json and manifest.json only");
    // Mistakes: clear errors, nothing written.
    let bad = d.join("bad");
    let b = bad.to_str().unwrap();
    assert_fails(
        &envmap(&["bake", "sky", "--out", b, "--levels", "12"], d),
        1,
        "at most 10 levels",
    );
    assert_fails(
        &envmap(&["bake", "nothing.hdr", "--out", b], d),
        1,
        "built-in environments: sky, room",
    );
    assert_fails(
        &envmap(&["bake", "sky", "--out", b, "--sh-window=-3"], d),
        2,
        "positive cutoff",
    );
    assert!(!bad.exists(), "nothing written for a refused bake");
}

/// A report nobody reads any more (`envmap bake … 2>&1 | head -1` closes
/// the pipe after one line): the outputs are written and the command
/// succeeds, with no panic; `info`, whose output is its result, says on
/// standard error that standard output could not be written.
#[test]
fn closed_report_pipes_do_not_stop_a_job() {
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    latlong_file(d, "sky.hdr", 64);
    // Pipes whose reading end is closed before the command starts, so that
    // its first write fails, however fast it runs.
    let closed = || {
        let (reader, writer) = std::io::pipe().expect("pipe");
        drop(reader);
        Stdio::from(writer)
    };
    let run = |args: &[&str], close_stderr: bool| {
        Command::new(env!("CARGO_BIN_EXE_envmap"))
            .args(args)
            .current_dir(d)
            .stdin(Stdio::null())
            .stdout(closed())
            .stderr(if close_stderr {
                closed()
            } else {
                Stdio::piped()
            })
            .spawn()
            .expect("run envmap")
            .wait_with_output()
            .expect("wait")
    };
    for (args, made) in [
        (
            &[
                "bake",
                "sky.hdr",
                "--out",
                "ibl",
                "--size",
                "8",
                "--dfg-size",
                "8",
            ][..],
            "ibl/manifest.json",
        ),
        (
            &[
                "convert", "sky.hdr", "cube.exr", "--to", "cube", "--size", "16",
            ][..],
            "cube.exr",
        ),
        (
            &[
                "render", "a.png", "--env", "sky.hdr", "--width", "32", "--height", "24",
            ][..],
            "a.png",
        ),
    ] {
        let o = run(args, true);
        assert_eq!(o.status.code(), Some(0), "{}", args[0]);
        assert!(d.join(made).is_file(), "{}: {made}", args[0]);
    }
    let o = run(&["info", "sky.hdr"], false);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains("<stdout>") && !err.contains("panicked"),
        "{err}"
    );
}

/// Fisheyes on the command line: the lens and field of view go into the file and come back
/// out of it; a one-lens fisheye turned into a latlong is black where it does not see, the
/// summary says how much it sees and `--mask` writes where; mistakes are named.
#[test]
fn fisheyes_keep_their_lens_and_say_what_they_see() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    latlong_file(d, "sky.exr", 256);
    let o = envmap(
        &[
            "convert",
            "sky.exr",
            "dual.exr",
            "--to",
            "dual-fisheye",
            "--fov",
            "190",
            "--lens",
            "equisolid",
            "--size",
            "128",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let info = text(&envmap(&["info", "dual.exr"], d).stdout);
    assert!(info.contains("mapping          dual-fisheye\n"), "{info}");
    assert!(
        info.contains("equisolid, 190° per lens (sees 100.0 %"),
        "{info}"
    );
    // One lens of 180° from the file (its own lens read back), then into a latlong.
    let o = envmap(
        &[
            "convert", "dual.exr", "one.exr", "--to", "fisheye", "--size", "64", "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = envmap(
        &[
            "convert", "one.exr", "back.exr", "--to", "latlong", "--size", "128", "--mask",
            "mask.png",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary = text(&o.stderr);
    assert!(
        summary.contains("coverage: the input sees 50.00 % of the output's directions"),
        "{summary}"
    );
    let back = envmap_render::image::load(d.join("back.exr"), &Default::default()).unwrap();
    let mask = image::open(d.join("mask.png")).unwrap().to_luma8();
    assert_eq!((mask.width(), mask.height()), (128, 64));
    // The latlong's centre (+z, the lens's axis) is seen, its left and right edges (−z) are
    // not: black there, and so says the mask.
    assert_eq!(mask.get_pixel(64, 32).0[0], 255);
    assert_eq!(mask.get_pixel(1, 32).0[0], 0);
    assert!(back.pixels()[32 * 128 + 64].iter().all(|&c| c > 0.0));
    assert_eq!(back.pixels()[32 * 128 + 1], [0.0; 3]);
    // Mistakes.
    let o = envmap(
        &[
            "convert", "sky.exr", "x.exr", "--to", "cube", "--fov", "190",
        ],
        d,
    );
    assert_fails(&o, 1, "for fisheye and dual-fisheye, not cube");
    let o = envmap(
        &[
            "convert", "sky.exr", "x.exr", "--to", "fisheye", "--fov", "400",
        ],
        d,
    );
    assert_fails(&o, 2, "at most 360");
    let o = envmap(
        &[
            "convert",
            "sky.exr",
            "x.exr",
            "--to",
            "cube",
            "--from-fov",
            "190",
        ],
        d,
    );
    assert_fails(&o, 1, "need --from fisheye");
    let o = envmap(
        &[
            "convert",
            "sky.exr",
            "x.exr",
            "--to",
            "fisheye",
            "--lens",
            "stereographic",
        ],
        d,
    );
    assert_fails(&o, 2, "equidistant or equisolid");
}
