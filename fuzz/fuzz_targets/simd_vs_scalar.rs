//! Arbitrary f32 bit patterns through the scalar core and the SIMD kernels
//! at each tier, forward and inverse: fails on any chart or validity
//! mismatch or an error beyond the tier's bound (the rule of the tests
//! crate, `envmap_tests::check_simd_forward` and `check_simd_inverse`).
#![no_main]

use envmap_core::glam::Vec3;
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::{forward_slice, inverse_slice, Exact, Fast, Fine, Tier};
use envmap_tests::{check_simd_forward, check_simd_inverse};
use libfuzzer_sys::fuzz_target;

fn word(b: &[u8]) -> u32 {
    u32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

fn check<T: Tier>(m: AnyMapping, dirs: &[Vec3], coords: &[ChartUv]) {
    let mut out = vec![ChartUv::default(); dirs.len()];
    forward_slice::<_, T>(&m, dirs, &mut out);
    for (d, got) in dirs.iter().zip(&out) {
        if let Err(e) = check_simd_forward(m, T::NAME, *d, *got) {
            panic!("{e}");
        }
    }
    let mut back = vec![Vec3::ZERO; coords.len()];
    inverse_slice::<_, T>(&m, coords, &mut back);
    for (c, got) in coords.iter().zip(&back) {
        if let Err(e) = check_simd_inverse(m, T::NAME, *c, *got) {
            panic!("{e}");
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let words: Vec<u32> = data.chunks_exact(4).map(word).collect();
    let dirs: Vec<Vec3> = words
        .chunks_exact(3)
        .map(|w| {
            Vec3::new(
                f32::from_bits(w[0]),
                f32::from_bits(w[1]),
                f32::from_bits(w[2]),
            )
        })
        .collect();
    for m in AnyMapping::ALL {
        let n = m.chart_count();
        // Chart points: the raw bits, and the same bits folded into a valid
        // chart and [0, 1] (24 bits of each word), so inside points are
        // exercised as often as bad ones.
        let mut coords = Vec::with_capacity(2 * dirs.len());
        for w in words.chunks_exact(3) {
            coords.push(ChartUv::new(
                w[0],
                f32::from_bits(w[1]),
                f32::from_bits(w[2]),
            ));
            let unit = |x: u32| (x >> 8) as f32 / ((1u32 << 24) - 1) as f32;
            coords.push(ChartUv::new(w[0] % n, unit(w[1]), unit(w[2])));
        }
        check::<Exact>(m, &dirs, &coords);
        check::<Fine>(m, &dirs, &coords);
        check::<Fast>(m, &dirs, &coords);
    }
});
