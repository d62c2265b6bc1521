//! File conventions as a user meets them: cube files in the GL world by
//! default, one world for the whole command, the seed's z-up frame by name,
//! every face naming scheme and face transform round-tripping, and files
//! that say what they hold.

use std::fs;
use std::path::Path;

use envmap_core::{AnyMapping, Atlas, Frame};
use envmap_render::image::{face_paths_named, load, load_detailed, FaceNames, LoadOptions};
use envmap_render::image::{save, EnvImage, Representation, SaveOptions};
use envmap_render::image::{Convention, FileAxes, World};
use envmap_render::image::{FaceTransforms, FaceTurn};
use envmap_render::scene::{fill, smooth};

mod common;
use common::{envmap, text};

/// A latlong file (no envmap metadata: a plain HDR) whose top half is bright.
fn bright_top(dir: &Path) {
    let repr = Representation::for_file(AnyMapping::LatLong, FileAxes::default());
    let mut img = EnvImage::new(64, 32, repr).unwrap();
    for y in 0..16 {
        for x in 0..64 {
            img.set(x, y, [10.0, 10.0, 10.0]);
        }
    }
    save(&img, dir.join("top.hdr"), &SaveOptions::default()).unwrap();
}

/// Mean of one cube face.
fn face_mean(img: &EnvImage, face: u32) -> f32 {
    let f = img.chart_image(face).unwrap();
    f.pixels.iter().map(|p| p[0]).sum::<f32>() / f.pixels.len() as f32
}

#[test]
fn a_bright_sky_lands_on_the_plus_y_face_by_default_and_on_plus_z_in_the_seeds_frame() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    bright_top(d);
    let o = envmap(
        &[
            "convert", "top.hdr", "cube.exr", "--to", "cube", "--size", "16", "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let cube = load(d.join("cube.exr"), &LoadOptions::default()).unwrap();
    let means: Vec<f32> = (0..6).map(|f| face_mean(&cube, f)).collect();
    // +y (face 2) all sky, −y (face 3) all ground, the four sides half and half.
    assert!(means[2] > 9.99 && means[3] < 0.01, "{means:?}");
    for f in [0, 1, 4, 5] {
        assert!((means[f] - 5.0).abs() < 0.5, "{means:?}");
    }
    // The seed's z-up frame, by name, puts the sky on +z.
    let o = envmap(
        &[
            "convert",
            "top.hdr",
            "cube_z.exr",
            "--to",
            "cube",
            "--size",
            "16",
            "-q",
            "--from-frame",
            "z-up",
            "--to-frame",
            "z-up",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let cube = load(d.join("cube_z.exr"), &{
        let mut o = LoadOptions::default();
        o.axes = Some(FileAxes::Z_UP);
        o
    })
    .unwrap();
    assert!(face_mean(&cube, 4) > 9.99 && face_mean(&cube, 5) < 0.01);
}

#[test]
fn gl_directions_give_gl_faces_and_z_up_gives_the_old_answer() {
    let dir = tempfile::tempdir().unwrap();
    let map = |args: &[&str], input: &str| {
        let o = common::envmap_stdin(&[&["map"], args].concat(), dir.path(), input);
        assert!(o.status.success(), "{}", text(&o.stderr));
        text(&o.stdout).lines().nth(1).unwrap().to_owned()
    };
    assert_eq!(map(&["--mapping", "cube"], "0 1 0\n"), "2,0.5,0.5");
    assert_eq!(map(&["--mapping", "cube"], "0 0 1\n"), "4,0.5,0.5");
    assert_eq!(
        map(&["--mapping", "cube", "--frame", "z-up"], "0 0 1\n"),
        "4,0.5,0.5"
    );
    assert_eq!(
        map(&["--mapping", "cube", "--frame", "z-up"], "0 1 0\n"),
        "2,0.5,0.5"
    );
    // A latlong: GL's +z is the image centre, +y the top row; in the seed's
    // frame, −x is the centre and +z the top.
    assert_eq!(map(&["--mapping", "latlong"], "0 0 1\n"), "0,0.5,0.5");
    assert!(map(&["--mapping", "latlong"], "0 1 0\n").ends_with(",0"));
    assert_eq!(
        map(&["--mapping", "latlong", "--frame", "z-up"], "-1 0 0\n"),
        "0,0.5,0.5"
    );
    // Blender's convention: centre +x.
    assert_eq!(
        map(
            &["--mapping", "latlong", "--convention", "blender"],
            "1 0 0\n"
        ),
        "0,0.5,0.5"
    );
    // unmap prints GL directions back.
    let o = common::envmap_stdin(&["unmap", "--mapping", "cube"], dir.path(), "2,0.5,0.5\n");
    assert_eq!(text(&o.stdout).lines().nth(1).unwrap(), "0,1,0");
}

#[test]
fn every_naming_scheme_and_face_transform_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let repr = Representation::new(
        AnyMapping::Cube,
        Atlas::CUBE_HORIZONTAL_STRIP,
        Frame::Y_UP_RH,
    )
    .unwrap();
    let cube = fill(repr, 6 * 8, 8, smooth).unwrap();
    // Every turn but the identity.
    let turns = &FaceTurn::ALL[1..];
    for (k, scheme) in FaceNames::ALL.into_iter().enumerate() {
        let sub = d.join(format!("s{k}"));
        fs::create_dir(&sub).unwrap();
        let transforms = FaceTransforms::default()
            .with(envmap_core::CubeFace::PosX, turns[k])
            .with(envmap_core::CubeFace::NegZ, turns[(k + 2) % turns.len()]);
        let opts = {
            let mut o = SaveOptions::default();
            o.six_files = true;
            o.face_names = Some(scheme);
            o.face_transforms = transforms;
            o
        };
        let written = save(&cube, sub.join("sky.exr"), &opts).unwrap();
        let names = face_paths_named(&sub.join("sky.exr"), scheme).unwrap();
        assert_eq!(written, names.to_vec(), "{scheme}");
        // The stored +x face is the GL face turned.
        let stored = envmap_render::image::read_rgb(&names[0], u64::MAX, None)
            .unwrap()
            .0;
        assert_eq!(
            stored,
            turns[k].apply(&cube.chart_image(0).unwrap()),
            "{scheme}"
        );
        // Read back from any one face's name, with the transforms undone:
        // the same cube, texel for texel.
        for name in &names {
            let back = load(name, &{
                let mut o = LoadOptions::default();
                o.face_transforms = transforms;
                o
            })
            .unwrap();
            assert_eq!(
                back.pixels(),
                cube.pixels(),
                "{scheme} from {}",
                name.display()
            );
        }
    }
    // The command line: cmgen's names, and a transform, both ways.
    let o = envmap(
        &[
            "convert",
            "s1/sky_px.exr",
            "out/{face}.exr",
            "--to",
            "cube",
            "--face-names",
            "posx",
            "--face-transform",
            "+y:rot90,-y:flipx",
            "-q",
        ],
        d,
    );
    assert!(
        !o.status.success(),
        "out/ does not exist: {}",
        text(&o.stderr)
    );
    fs::create_dir(d.join("out")).unwrap();
    let o = envmap(
        &[
            "convert",
            "s1/sky_px.exr",
            "out/{face}.exr",
            "--to",
            "cube",
            "--face-names",
            "posx",
            "--face-transform",
            "+y:rot90,-y:flipx",
            "--from-face-transform",
            "+x:rot180,-z:flipx",
            "-q",
        ],
        d,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    for f in ["posx", "negx", "posy", "negy", "posz", "negz"] {
        assert!(d.join("out").join(format!("{f}.exr")).is_file(), "{f}");
    }
    let back = load(d.join("out/negy.exr"), &{
        let mut o = LoadOptions::default();
        o.face_transforms = "+y:rot90,-y:flipx".parse().unwrap();
        o
    })
    .unwrap();
    // Conversion is cube → cube at the same size: exact up to the bilinear
    // filter at texel centres.
    for (a, b) in back.pixels().iter().zip(cube.pixels()) {
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-5, "{a:?} {b:?}");
        }
    }
}

#[test]
fn weak_face_names_are_a_cube_only_when_six_square_files_exist() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A latlong named like a face of the index scheme: one image.
    let ll = fill(
        Representation::default_for(AnyMapping::LatLong),
        32,
        16,
        smooth,
    )
    .unwrap();
    save(&ll, d.join("pano_2.exr"), &SaveOptions::default()).unwrap();
    let img = load(d.join("pano_2.exr"), &LoadOptions::default()).unwrap();
    assert_eq!(img.mapping(), AnyMapping::LatLong);
    // A distinctive name with a face missing: the error lists the faces.
    save(&ll, d.join("sky_+x.exr"), &SaveOptions::default()).unwrap();
    let e = load(d.join("sky_+x.exr"), &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing") && e.contains("sky_-z.exr"), "{e}");
}

#[test]
fn files_say_what_they_hold_and_loading_believes_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (m, name) in [
        (AnyMapping::Octahedral, "oct.exr"),
        (AnyMapping::SphereMapGl, "ball.png"),
        (AnyMapping::LatLong, "ll.exr"),
    ] {
        for axes in [
            FileAxes::default(),
            FileAxes::Convention(Convention::Blender, World::YUp),
            FileAxes::Z_UP,
        ] {
            let repr = Representation::for_file(m, axes);
            let (w, h) = repr.atlas.image_size_for_cell_width(16).unwrap();
            let img = fill(repr, w, h, smooth).unwrap();
            save(&img, d.join(name), &SaveOptions::default()).unwrap();
            let l = load_detailed(d.join(name), &LoadOptions::default()).unwrap();
            assert_eq!(l.image.mapping(), m, "{name}");
            assert_eq!(
                l.image.representation().frame,
                repr.frame,
                "{name} {axes:?}"
            );
            assert!(l.metadata.axes.is_some(), "{name}");
            // What info prints.
            let o = envmap(&["info", name], d);
            let info = text(&o.stdout);
            assert!(info.contains("as the file says"), "{info}");
        }
    }
    // envmap's EXR files are scan lines in increasing order, which every
    // reader handles (a tiled file in any order is misread by some).
    let meta = exr::meta::MetaData::read_from_file(d.join("ll.exr"), false).unwrap();
    let h = &meta.headers[0];
    assert_eq!(h.blocks, exr::meta::BlockDescription::ScanLines);
    assert_eq!(h.line_order, exr::meta::attribute::LineOrder::Increasing);
    assert!(h
        .own_attributes
        .comments
        .as_ref()
        .unwrap()
        .to_string()
        .contains("latlong"));
}
