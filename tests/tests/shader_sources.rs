//! Tier 0 of the shader tests, no GPU needed: every WGSL module of
//! `envmap-core/shaders/` parsed and validated by naga; the GLSL 4.50,
//! GLSL ES 3.00 and HLSL written from it by naga equal the committed files
//! (`ENVMAP_BLESS_SHADERS=1` rewrites them); every public name survives the
//! translation unchanged; and, where `glslangValidator` is installed, the
//! GLSL compiles as GLSL 4.50 and GLSL ES 3.00 and the HLSL as HLSL
//! (`-D`; shader model 5 features only).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use envmap_core::shaders::{MODULES, WGSL_FILES};

/// The directory of the WGSL files.
fn shader_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../envmap-core/shaders")
}

/// A module's WGSL: its files concatenated.
fn module_source(files: &[&str]) -> String {
    files
        .iter()
        .map(|f| {
            WGSL_FILES
                .iter()
                .find(|(name, _)| name == f)
                .unwrap_or_else(|| panic!("{f} is not in WGSL_FILES"))
                .1
        })
        .collect()
}

fn parse(name: &str, src: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(src)
        .unwrap_or_else(|e| panic!("{name}: WGSL does not parse:\n{}", e.emit_to_string(src)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: WGSL does not validate:\n{}", e.emit_to_string(src)));
    (module, info)
}

/// The entry point the translations need (naga writes a module for one
/// entry point), removed from their text afterwards.
const ENTRY: &str = "envmap_generated_entry";

#[derive(Clone, Copy, Debug)]
enum Lang {
    Glsl450,
    GlslEs300,
    Hlsl,
}

impl Lang {
    const ALL: [Lang; 3] = [Lang::Glsl450, Lang::GlslEs300, Lang::Hlsl];
    fn dir(self) -> &'static str {
        match self {
            Lang::Glsl450 => "glsl450",
            Lang::GlslEs300 => "glsl300es",
            Lang::Hlsl => "hlsl",
        }
    }
    fn ext(self) -> &'static str {
        match self {
            Lang::Hlsl => "hlsl",
            _ => "glsl",
        }
    }
    fn describe(self) -> &'static str {
        match self {
            Lang::Glsl450 => "GLSL 4.50",
            Lang::GlslEs300 => "GLSL ES 3.00",
            Lang::Hlsl => "HLSL (shader model 5.0)",
        }
    }
}

/// The translation of a module's WGSL, as committed: no version line, no
/// entry point, a header saying what it is.
fn translate(name: &str, files: &[&str], lang: Lang) -> String {
    let wgsl = module_source(files);
    // GLSL ES 3.00 has no compute shaders: its entry point is a fragment one.
    let entry = match lang {
        Lang::GlslEs300 => format!("\n@fragment\nfn {ENTRY}() {{}}\n"),
        _ => format!("\n@compute @workgroup_size(1)\nfn {ENTRY}() {{}}\n"),
    };
    let src = format!("{wgsl}{entry}");
    let (module, info) = parse(name, &src);
    let mut out = String::new();
    match lang {
        Lang::Glsl450 | Lang::GlslEs300 => {
            let version = match lang {
                Lang::Glsl450 => naga::back::glsl::Version::Desktop(450),
                _ => naga::back::glsl::Version::Embedded {
                    version: 300,
                    is_webgl: false,
                },
            };
            let options = naga::back::glsl::Options {
                version,
                writer_flags: naga::back::glsl::WriterFlags::INCLUDE_UNUSED_ITEMS,
                ..naga::back::glsl::Options::default()
            };
            let pipeline = naga::back::glsl::PipelineOptions {
                shader_stage: match lang {
                    Lang::GlslEs300 => naga::ShaderStage::Fragment,
                    _ => naga::ShaderStage::Compute,
                },
                entry_point: ENTRY.into(),
                multiview: None,
            };
            let mut w = naga::back::glsl::Writer::new(
                &mut out,
                &module,
                &info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .unwrap_or_else(|e| panic!("{name}: naga's GLSL writer: {e}"));
            w.write()
                .unwrap_or_else(|e| panic!("{name}: naga's GLSL writer: {e}"));
        }
        Lang::Hlsl => {
            let options = naga::back::hlsl::Options {
                shader_model: naga::back::hlsl::ShaderModel::V5_0,
                ..naga::back::hlsl::Options::default()
            };
            let pipeline = naga::back::hlsl::PipelineOptions { entry_point: None };
            let mut w = naga::back::hlsl::Writer::new(&mut out, &options, &pipeline);
            w.write(&module, &info, None)
                .unwrap_or_else(|e| panic!("{name}: naga's HLSL writer: {e}"));
        }
    }
    out
}

/// The generator's header of a generated file.
fn header(name: &str, files: &[&str], lang: Lang) -> String {
    let mut h = String::new();
    let _ = writeln!(
        h,
        "// envmap shaders, {}: {name} (from {}).",
        lang.describe(),
        files.join(", ")
    );
    let _ = writeln!(
        h,
        "// Written by naga {} from the WGSL in envmap-core/shaders/ (the source, with every",
        NAGA_VERSION
    );
    let _ = writeln!(
        h,
        "// formula, source and comment): do not edit; after changing the WGSL run"
    );
    let _ = writeln!(
        h,
        "// ENVMAP_BLESS_SHADERS=1 cargo test --release -p envmap-tests --test shader_sources"
    );
    let _ = writeln!(
        h,
        "// A library: no #version line and no entry point (docs/shaders.md)."
    );
    h
}

/// naga's version, as Cargo.lock has it (written into the headers).
const NAGA_VERSION: &str = "29.0.4";

/// `text` with the entry point `translate` added removed, and the lines a
/// library must not carry (the version, the compute stage's extension and
/// workgroup size): what the committed files hold, after [`header`].
fn library_text(name: &str, text: &str, lang: Lang) -> String {
    let (cut, expected_tail) = match lang {
        Lang::Hlsl => (
            "[numthreads(1, 1, 1)]\n",
            format!("[numthreads(1, 1, 1)]\nvoid {ENTRY}()\n{{\n    return;\n}}\n"),
        ),
        _ => (
            "void main() {\n",
            "void main() {\n    return;\n}\n".to_string(),
        ),
    };
    let at = text
        .rfind(cut)
        .unwrap_or_else(|| panic!("{name}: no entry point in naga's {}", lang.describe()));
    assert_eq!(
        text[at..].trim_end(),
        expected_tail.trim_end(),
        "{name}: naga's {} ends otherwise than expected: the generator needs updating",
        lang.describe()
    );
    let mut out = String::new();
    for line in text[..at].lines() {
        let drop = line.starts_with("#version")
            || line.starts_with("#extension GL_ARB_compute_shader")
            || line.starts_with("layout(local_size_x");
        if !drop {
            out.push_str(line);
            out.push('\n');
        }
    }
    // One newline at the end, none at the start.
    format!("{}\n", out.trim())
}

/// Every generated file's path and expected text.
fn generated() -> Vec<(PathBuf, String)> {
    let mut v = Vec::new();
    for (name, files) in MODULES {
        for lang in Lang::ALL {
            let raw = translate(name, files, lang);
            let text = format!(
                "{}{}",
                header(name, files, lang),
                library_text(name, &raw, lang)
            );
            let path = shader_dir()
                .join("generated")
                .join(lang.dir())
                .join(format!("{name}.{}", lang.ext()));
            v.push((path, text));
        }
    }
    v
}

/// Every module of `MODULES` and every file alone where it stands alone
/// (common.wgsl) parses and validates.
#[test]
fn wgsl_parses_and_validates() {
    let (_, common) = WGSL_FILES[0];
    parse("common.wgsl", common);
    for (name, files) in MODULES {
        let src = module_source(files);
        parse(name, &src);
    }
    // ALL_WGSL is the whole list in order.
    let all: String = WGSL_FILES.iter().map(|(_, t)| *t).collect();
    assert_eq!(all, envmap_core::shaders::ALL_WGSL);
    parse("ALL_WGSL", envmap_core::shaders::ALL_WGSL);
    // Every file is in some module, and every module's files are in order.
    for (file, _) in WGSL_FILES {
        assert!(
            MODULES.iter().any(|(_, fs)| fs.contains(&file)),
            "{file} is in no module"
        );
    }
    let order: Vec<&str> = WGSL_FILES.iter().map(|(f, _)| *f).collect();
    for (name, files) in MODULES {
        let idx: Vec<usize> = files
            .iter()
            .map(|f| order.iter().position(|o| o == f).expect("listed"))
            .collect();
        assert!(
            idx.windows(2).all(|w| w[0] < w[1]),
            "{name}: files out of order"
        );
    }
}

/// The committed GLSL and HLSL are what naga writes from the committed WGSL;
/// `ENVMAP_BLESS_SHADERS=1` rewrites them.
#[test]
fn generated_files_are_current() {
    let bless = std::env::var("ENVMAP_BLESS_SHADERS").is_ok_and(|v| v == "1");
    // The headers name the naga that wrote the files: the one Cargo.lock has.
    let lock = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../Cargo.lock"))
        .expect("Cargo.lock");
    assert!(
        lock.contains(&format!("name = \"naga\"\nversion = \"{NAGA_VERSION}\"")),
        "Cargo.lock's naga is not {NAGA_VERSION}: update NAGA_VERSION and bless the files"
    );
    let mut stale = Vec::new();
    for (path, text) in generated() {
        let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
        if on_disk != text {
            if bless {
                std::fs::write(&path, &text)
                    .unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
                println!("rewrote {}", path.display());
            } else {
                stale.push(path.display().to_string());
            }
        }
    }
    assert!(
        stale.is_empty(),
        "generated shader files are stale (the WGSL changed, or naga did): {}\nrun \
         ENVMAP_BLESS_SHADERS=1 cargo test --release -p envmap-tests --test shader_sources \
         and commit the result",
        stale.join(", ")
    );
    // The constants are those files (compiled in when the crate was built).
    for (name, glsl, es, hlsl) in envmap_core::shaders::GENERATED {
        for (lang, text) in [
            (Lang::Glsl450, glsl),
            (Lang::GlslEs300, es),
            (Lang::Hlsl, hlsl),
        ] {
            let path = shader_dir()
                .join("generated")
                .join(lang.dir())
                .join(format!("{name}.{}", lang.ext()));
            if !bless {
                assert_eq!(
                    std::fs::read_to_string(&path).unwrap_or_default(),
                    text,
                    "{}: the constant differs from the file (rebuild)",
                    path.display()
                );
            }
        }
    }
}

/// The names a WGSL text declares at module scope (functions, structs and
/// constants), and the members of its structs (an engine's code names them
/// too), each with whether it is a member.
fn declared_names(src: &str) -> Vec<(String, bool)> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut names = Vec::new();
    let mut in_struct = false;
    for line in src.lines() {
        if in_struct {
            if line.starts_with('}') {
                in_struct = false;
            } else if let Some((member, _)) = line.trim().split_once(':') {
                names.push((ident(member), true));
            }
            continue;
        }
        for kw in ["fn ", "struct ", "const "] {
            if let Some(rest) = line.strip_prefix(kw) {
                names.push((ident(rest), false));
                in_struct = kw == "struct ";
            }
        }
    }
    names
}

/// Every module-scope name keeps its prefix, and it and every struct
/// member survive naga unchanged in every language, so an engine calls the
/// GLSL and HLSL by the WGSL's names.
#[test]
fn names_survive_translation() {
    for (file, text) in WGSL_FILES {
        for (name, member) in declared_names(text) {
            assert!(
                member
                    || name.starts_with("envmap_")
                    || name.starts_with("Envmap")
                    || name.starts_with("ENVMAP_"),
                "{file}: {name} lacks the envmap prefix"
            );
            assert!(
                !name.ends_with(|c: char| c.is_ascii_digit()),
                "{file}: {name} ends in a digit (naga would append an underscore)"
            );
        }
    }
    for (name, glsl, es, hlsl) in envmap_core::shaders::GENERATED {
        let files = MODULES.iter().find(|(n, _)| *n == name).expect("module").1;
        for file in files {
            let text = WGSL_FILES.iter().find(|(f, _)| f == file).expect("file").1;
            for (ident, _) in declared_names(text) {
                for (lang, out) in [("GLSL 4.50", glsl), ("GLSL ES 3.00", es), ("HLSL", hlsl)] {
                    let found = out.match_indices(ident.as_str()).any(|(i, _)| {
                        let after = out[i + ident.len()..].chars().next().unwrap_or(' ');
                        !(after.is_ascii_alphanumeric() || after == '_')
                    });
                    assert!(found, "{name}: {ident} is missing or renamed in the {lang}");
                }
            }
        }
    }
}

/// `glslangValidator` from the PATH; without it the compile checks fail
/// with how to install it (`.ci/run` installs it).
fn glslang() -> PathBuf {
    let found = std::process::Command::new("glslangValidator")
        .arg("--version")
        .output();
    match found {
        Ok(o) if o.status.success() => PathBuf::from("glslangValidator"),
        Ok(o) => panic!(
            "glslangValidator --version failed ({}): {}",
            o.status,
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(e) => panic!(
            "glslangValidator is not on the PATH ({e}): the generated GLSL and HLSL cannot be \
             checked (Debian: apt-get install glslang-tools)"
        ),
    }
}

/// The generated GLSL compiles as GLSL 4.50 (compute) and GLSL ES 3.00
/// (fragment), the HLSL as HLSL (glslang's HLSL front end, compute), each
/// wrapped in the smallest shader around it.
#[test]
fn generated_files_compile_with_glslang() {
    let tool = glslang();
    let dir = std::env::temp_dir().join(format!("envmap-shaders-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let mut failures = Vec::new();
    for (name, glsl, es, hlsl) in envmap_core::shaders::GENERATED {
        let cases = [
            (
                "glsl450",
                format!("#version 450\n{glsl}\nlayout(local_size_x = 1) in;\nvoid main() {{}}\n"),
                vec!["-S", "comp"],
            ),
            (
                "glsl300es",
                format!("#version 300 es\n{es}\nvoid main() {{}}\n"),
                vec!["-S", "frag"],
            ),
            (
                "hlsl",
                format!("{hlsl}\n[numthreads(1, 1, 1)]\nvoid main() {{}}\n"),
                vec!["-D", "-V", "-S", "comp", "-e", "main", "-o", "/dev/null"],
            ),
        ];
        for (lang, text, args) in cases {
            let path = dir.join(format!("{name}.{lang}"));
            std::fs::write(&path, text).expect("a temporary file");
            let out = std::process::Command::new(&tool)
                .args(&args)
                .arg(&path)
                .output()
                .expect("running glslangValidator");
            if !out.status.success() {
                failures.push(format!(
                    "{name} ({lang}):\n{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                ));
            } else {
                println!("{name} ({lang}): glslangValidator {} ok", args.join(" "));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        failures.is_empty(),
        "glslangValidator refused:\n{}",
        failures.join("\n")
    );
}

/// `envmap_atan_unit` of common.wgsl in f32, as a device may evaluate it:
/// each Horner step `p·u + c` rounded twice, or fused into one rounding.
fn atan_unit(z: f32, fused: bool) -> f32 {
    let c = envmap_simd::approx::coeffs::ATAN_EXACT;
    let u = z * z;
    let mut p = c[7];
    for &k in c[..7].iter().rev() {
        p = if fused { p.mul_add(u, k) } else { p * u + k };
    }
    if fused {
        z.mul_add(u * p, z)
    } else {
        z + z * (u * p)
    }
}

/// `envmap_atan2f` of common.wgsl in f32, with the quotient `num / den`
/// moved `ulps` representable values (WGSL allows a division 2.5 ULP).
fn atan2f(y: f32, x: f32, ulps: i32, fused: bool) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay > ax;
    let (num, den) = if swap { (ax, ay) } else { (ay, ax) };
    let mut z = if den > 0.0 { num / den } else { 0.0 };
    if z > 0.0 {
        z = f32::from_bits((z.to_bits() as i32 + ulps) as u32).min(1.0);
    }
    let p = atan_unit(z, fused);
    let half_pi = std::f32::consts::FRAC_PI_2;
    let a = match (swap, x.is_sign_negative()) {
        (true, false) => half_pi - p,
        (true, true) => half_pi + p,
        (false, false) => p,
        (false, true) => std::f32::consts::PI - p,
    };
    a.copysign(y)
}

/// The bound docs/shaders.md states for `envmap_atan2f` under WGSL's
/// accuracy rules (radians).
const ATAN2F_PORTABLE_BOUND: f64 = 3.5e-7;

/// common.wgsl's atan2 carries envmap-simd's exact-tier coefficients, and
/// its error, swept over z = min/max in [0, 1] (every 997th f32) in all
/// four octants and both signs of y, stays within the stated bound with
/// exact f32 arithmetic and with what WGSL allows a device: a quotient up
/// to 2 ULP off (2.5 ULP, in representable steps) and the Horner steps
/// fused or not.
#[test]
fn atan2f_meets_its_bound_under_the_spec_rules() {
    // The WGSL's literals are the coefficients, exactly.
    let common = envmap_core::shaders::COMMON_WGSL;
    let mut at = 0;
    for c in envmap_simd::approx::coeffs::ATAN_EXACT.iter().rev() {
        let text = rust_decimal_of(c.abs());
        let found = common[at..]
            .find(&text)
            .unwrap_or_else(|| panic!("common.wgsl lacks the coefficient {c} ({text}) in order"));
        at += found + text.len();
    }
    let mut exact = (0.0f64, (0.0f32, 0.0f32));
    let mut spec = (0.0f64, (0.0f32, 0.0f32));
    let one = 1.0f32.to_bits();
    let mut bits = 0u32;
    while bits <= one {
        let z = f32::from_bits(bits);
        for (y, x) in [
            (z, 1.0f32),
            (1.0, z),
            (z, -1.0),
            (1.0, -z),
            (-z, 1.0),
            (-1.0, -z),
        ] {
            let want = f64::from(y).atan2(f64::from(x));
            let e = (f64::from(atan2f(y, x, 0, false)) - want).abs();
            if e > exact.0 {
                exact = (e, (y, x));
            }
            for ulps in -2..=2 {
                for fused in [false, true] {
                    let e = (f64::from(atan2f(y, x, ulps, fused)) - want).abs();
                    if e > spec.0 {
                        spec = (e, (y, x));
                    }
                }
            }
        }
        bits += 997;
    }
    println!(
        "envmap_atan2f: exact f32 arithmetic {:.3e} rad at (y, x) = {:?}; as WGSL allows (quotient ±2 ulp, Horner fused or not) {:.3e} rad at {:?}",
        exact.0, exact.1, spec.0, spec.1
    );
    assert!(spec.0 <= ATAN2F_PORTABLE_BOUND, "{spec:?}");
}

/// `envmap_fisheye_sin` of fisheye.wgsl in f32, as a device may evaluate
/// it: each step `a·b + c` rounded twice, or fused into one rounding.
fn fisheye_sin(x: f32, fused: bool) -> f32 {
    let mad = |a: f32, b: f32, c: f32| if fused { a.mul_add(b, c) } else { a * b + c };
    if x <= std::f32::consts::FRAC_PI_4 {
        let s = envmap_simd::approx::coeffs::SIN_EXACT;
        let u = x * x;
        let mut p = s[2];
        p = mad(p, u, s[1]);
        p = mad(p, u, s[0]);
        return mad(x, u * p, x);
    }
    let c = envmap_simd::approx::coeffs::COS_EXACT;
    let lo = (std::f64::consts::FRAC_PI_2 - f64::from(std::f32::consts::FRAC_PI_2)) as f32;
    let y = (std::f32::consts::FRAC_PI_2 - x) + lo;
    let u = y * y;
    let mut q = c[2];
    q = mad(q, u, c[1]);
    q = mad(q, u, c[0]);
    let half_u = 0.5 * u;
    let w = 1.0 - half_u;
    let rest = (1.0 - w) - half_u;
    w + mad(u * u, q, rest)
}

/// The bound docs/shaders.md states for `envmap_fisheye_sin` under WGSL's
/// accuracy rules (relative).
const FISHEYE_SIN_PORTABLE_BOUND: f64 = 1.5e-7;

/// fisheye.wgsl's sine carries envmap-simd's exact-tier sine and cosine
/// coefficients and the low part of π/2, and its relative error, swept over
/// [0, π/2] (every 97th f32, and the ends), stays within the stated bound
/// with the steps fused or not; at π/2 (a 360° lens's k/2) it is 1 exactly.
#[test]
fn fisheye_sin_meets_its_bound_under_the_spec_rules() {
    let fisheye = envmap_core::shaders::FISHEYE_WGSL;
    let coeffs = envmap_simd::approx::coeffs::SIN_EXACT
        .iter()
        .rev()
        .chain(envmap_simd::approx::coeffs::COS_EXACT.iter().rev());
    let mut at = 0;
    for c in coeffs {
        let text = rust_decimal_of(c.abs());
        let found = fisheye[at..]
            .find(&text)
            .unwrap_or_else(|| panic!("fisheye.wgsl lacks the coefficient {c} ({text}) in order"));
        at += found + text.len();
    }
    let lo = (std::f64::consts::FRAC_PI_2 - f64::from(std::f32::consts::FRAC_PI_2)) as f32;
    assert!(
        fisheye.contains(&format!("-{}", rust_decimal_of(lo.abs()))),
        "fisheye.wgsl lacks pi/2's low part {lo:e}"
    );
    let half_pi = std::f32::consts::FRAC_PI_2;
    let mut worst = (0.0f64, 0.0f32);
    let mut bits = 1u32;
    let mut xs = Vec::new();
    while f32::from_bits(bits) < half_pi {
        xs.push(f32::from_bits(bits));
        bits += 97;
    }
    xs.extend([0.0, std::f32::consts::FRAC_PI_4, half_pi]);
    for x in xs {
        let want = f64::from(x).sin();
        for fused in [false, true] {
            let e = (f64::from(fisheye_sin(x, fused)) - want).abs() / want.max(f64::MIN_POSITIVE);
            if e > worst.0 {
                worst = (e, x);
            }
        }
    }
    assert_eq!(fisheye_sin(half_pi, false), 1.0);
    assert_eq!(fisheye_sin(half_pi, true), 1.0);
    println!(
        "envmap_fisheye_sin: worst relative error {:.3e} at x = {:e} (steps fused or not)",
        worst.0, worst.1
    );
    assert!(worst.0 <= FISHEYE_SIN_PORTABLE_BOUND, "{worst:?}");
}

/// The exact decimal expansion of an f32 (every f32 is a finite binary
/// fraction), as the WGSL files write their constants.
fn rust_decimal_of(x: f32) -> String {
    // x = m · 2^e exactly; m · 5^(-e) · 10^e written out.
    let bits = x.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let mut m = u128::from(bits & 0x7f_ffff);
    let mut e = exp - 150;
    if exp == 0 {
        e = -149;
    } else {
        m |= 1 << 23;
    }
    if e >= 0 {
        return format!("{}", m << e);
    }
    // m / 2^-e = m · 5^-e / 10^-e.
    let k = (-e) as u32;
    let mut digits = num_mul_pow5(m, k);
    while digits.len() <= k as usize {
        digits.insert(0, '0');
    }
    let point = digits.len() - k as usize;
    let s = format!("{}.{}", &digits[..point], &digits[point..]);
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// m · 5^k in decimal (arbitrary precision, small k).
fn num_mul_pow5(m: u128, k: u32) -> String {
    let mut d: Vec<u32> = m
        .to_string()
        .bytes()
        .rev()
        .map(|b| u32::from(b - b'0'))
        .collect();
    for _ in 0..k {
        let mut carry = 0;
        for x in &mut d {
            let v = *x * 5 + carry;
            *x = v % 10;
            carry = v / 10;
        }
        while carry > 0 {
            d.push(carry % 10);
            carry /= 10;
        }
    }
    d.iter()
        .rev()
        .map(|x| char::from(b'0' + *x as u8))
        .collect()
}

/// Bevy's way in (docs/shaders.md): the library registered under
/// `#define_import_path envmap` and a material's shader importing from it,
/// composed by naga_oil (the composer Bevy 0.19 uses) into one module that
/// naga validates.
#[test]
fn bevy_imports_compose() {
    use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor};
    let library = format!(
        "#define_import_path envmap\n{}",
        envmap_core::shaders::ALL_WGSL
    );
    let mut composer = Composer::default();
    let added = composer
        .add_composable_module(ComposableModuleDescriptor {
            source: &library,
            file_path: "envmap.wgsl",
            ..ComposableModuleDescriptor::default()
        })
        .map(drop);
    added.unwrap_or_else(|e| {
        panic!(
            "naga_oil refuses the library: {}",
            e.emit_to_string(&composer)
        )
    });
    let material = "
#import envmap::{envmap_octahedral_chain, envmap_roughness_to_lod_linear, envmap_sh9_irradiance_over_pi, envmap_cube_forward, ENVMAP_INVALID_CHART}

@group(0) @binding(0) var chain: texture_2d<f32>;

@fragment
fn fragment(@location(0) n: vec3<f32>) -> @location(0) vec4<f32> {
    var sh: array<vec3<f32>, 9>;
    sh[0] = vec3<f32>(1.0);
    let ld = envmap_octahedral_chain(chain, 9, n, envmap_roughness_to_lod_linear(0.5, 9.0));
    let e = envmap_sh9_irradiance_over_pi(sh, n);
    let face = envmap_cube_forward(n).chart;
    return vec4<f32>(ld + e, select(1.0, 0.0, face == ENVMAP_INVALID_CHART));
}
";
    let module = composer
        .make_naga_module(NagaModuleDescriptor {
            source: material,
            file_path: "material.wgsl",
            ..NagaModuleDescriptor::default()
        })
        .unwrap_or_else(|e| {
            panic!(
                "naga_oil cannot compose the import: {}",
                e.emit_to_string(&composer)
            )
        });
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .expect("the composed module validates");
}
