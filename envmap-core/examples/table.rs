//! Prints every mapping of a handful of directions as a table: the chart and
//! (u, v) each direction lands on, and the direction that point maps back to.
//!
//! ```text
//! cargo run --release -p envmap-core --example table
//! ```

use envmap_core::glam::Vec3;
use envmap_core::AnyMapping;

fn main() {
    let directions = [
        ("+x", Vec3::X),
        ("-x", Vec3::NEG_X),
        ("+y", Vec3::Y),
        ("-y", Vec3::NEG_Y),
        ("+z", Vec3::Z),
        ("-z", Vec3::NEG_Z),
        ("(1,1,1)", Vec3::ONE),
        ("(0.3,-0.5,0.8)", Vec3::new(0.3, -0.5, 0.8)),
        ("(-2,1,-0.5)", Vec3::new(-2.0, 1.0, -0.5)),
    ];
    println!("| mapping | direction | chart | u | v | inverse(forward(d)) | error (rad) |");
    println!("| --- | --- | ---: | ---: | ---: | --- | ---: |");
    for m in AnyMapping::ALL {
        for (name, d) in directions {
            let Some(c) = m.forward(d) else {
                println!("| {m} | {name} | - | - | - | - | - |");
                continue;
            };
            let back = m.inverse(c).unwrap_or(Vec3::NAN);
            let err = angle_f64(back, d);
            println!(
                "| {m} | {name} | {} | {:.6} | {:.6} | ({:+.4}, {:+.4}, {:+.4}) | {err:.1e} |",
                c.chart, c.u, c.v, back.x, back.y, back.z
            );
        }
    }
    println!();
    println!(
        "Bad input: forward(NaN) = {:?}",
        AnyMapping::Cube.forward(Vec3::NAN)
    );
    println!(
        "           forward(0)   = {:?}",
        AnyMapping::Cube.forward(Vec3::ZERO)
    );
}

/// Angle between two directions, computed in f64 as atan2(|a × b|, a · b)
/// (accurate for tiny angles, unlike acos of the dot product).
fn angle_f64(a: Vec3, b: Vec3) -> f64 {
    let a = [f64::from(a.x), f64::from(a.y), f64::from(a.z)];
    let b = [f64::from(b.x), f64::from(b.y), f64::from(b.z)];
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let c = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    c.atan2(d)
}
