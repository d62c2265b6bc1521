//! The bad-input matrix: every mapping × scalar core and SIMD at each tier ×
//! forward and inverse, on the inputs programs and people get wrong.
//!
//! Directions are every triple of a set of components that holds NaN (both
//! signs), ±Inf, ±0, denormals, ±1e±30, ±`f32::MAX` and ordinary values (so
//! also every non-unit length); chart points are every chart number in and
//! out of range (including [`INVALID_CHART`]) with u, v inside, on and
//! outside `[0, 1]`, NaN and ±Inf. For each input the test checks the result
//! documented in `docs/bad-input.md`:
//!
//! * scalar `forward`: `None` exactly when a component is NaN or infinite or
//!   all are zero, or (a fisheye under 360°) the direction is not seen; otherwise a chart below `chart_count`, u, v in `[0, 1]`
//!   and inside the chart's domain;
//! * scalar `inverse`: `None` exactly when the point is outside its chart
//!   (`in_chart` is false); otherwise a finite unit direction;
//! * SIMD (`forward8`, `inverse8`, the slice functions) at each tier: the
//!   same validity, invalid lanes as [`INVALID_CHART`] with NaN u, v (or a
//!   NaN direction), and valid lanes within the tier's bound of the core;
//! * texel indices of every result and every chart point, NaN included,
//!   stay inside the chart and the atlas image (a chart out of range has
//!   no texel);
//! * every lane of a batch mixing good and bad inputs is bit-identical to
//!   the same input evaluated alone.
//!
//! Nothing here may panic: a panic fails the test.

use envmap_core::glam::Vec3;
use envmap_core::texel::{bilinear_footprint, texel_index};
use envmap_core::{AnyMapping, ChartUv, Mapping};
use envmap_simd::{
    forward_slice, inverse_slice, Dir8, Exact, Fast, Fine, Mapping8, Tier, Uv8, INVALID_CHART,
    LANES,
};
use envmap_tests::{check_simd_forward, check_simd_inverse, past_rim, SplitMix64};

/// Components: bad (NaN, ±Inf), zeros, denormals, tiny, huge and ordinary.
const COMPONENTS: [f32; 17] = [
    f32::NAN,
    -f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    1e-45, // the smallest denormal
    -3e-39,
    1e-30,
    -1e-30,
    1e30,
    -1e30,
    f32::MAX,
    -f32::MAX,
    1.0,
    -0.75,
    0.3,
];

/// u or v: inside, on and just outside `[0, 1]`, far outside, NaN, ±Inf.
const COORDS: [f32; 16] = [
    0.0,
    -0.0,
    1e-45,
    0.25,
    0.5,
    0.999_999_94,
    1.0,
    1.000_000_1,
    -1e-45,
    -1e-30,
    2.0,
    1e30,
    f32::NAN,
    -f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
];

fn directions() -> Vec<Vec3> {
    let mut v = Vec::new();
    for x in COMPONENTS {
        for y in COMPONENTS {
            for z in COMPONENTS {
                v.push(Vec3::new(x, y, z));
            }
        }
    }
    v
}

fn chart_points(m: AnyMapping) -> Vec<ChartUv> {
    let n = m.chart_count();
    let mut charts: Vec<u32> = (0..n).collect();
    charts.extend([n, n + 1, 6, 7, 1 << 31, INVALID_CHART - 1, INVALID_CHART]);
    let mut v = Vec::new();
    for c in charts {
        for u in COORDS {
            for w in COORDS {
                v.push(ChartUv::new(c, u, w));
            }
        }
    }
    v
}

fn bad_direction(d: Vec3) -> bool {
    !d.is_finite() || (d.x == 0.0 && d.y == 0.0 && d.z == 0.0)
}

/// Texel indices of `u` stay inside rows of every width, whatever `u` is.
fn check_texels(u: f32, what: &dyn Fn() -> String) {
    for n in [1u32, 2, 7, 4096, 8192] {
        let i = texel_index(u, n);
        assert!(i < n, "{}: texel_index({u}, {n}) = {i}", what());
        let (i0, i1, t) = bilinear_footprint(u, n);
        assert!(
            i0 >= -1 && i1 <= i64::from(n) && i1 == i0 + 1 && (0.0..=1.0).contains(&t),
            "{}: bilinear_footprint({u}, {n}) = {:?}",
            what(),
            (i0, i1, t)
        );
    }
}

#[test]
fn scalar_forward() {
    for m in AnyMapping::ALL {
        for d in directions() {
            let got = m.forward(d);
            if bad_direction(d) {
                assert_eq!(got, None, "{m} {d:?}");
                continue;
            }
            // A fisheye under 360° sees only its field of view (the rim may go either way).
            let past = past_rim(m, d);
            if got.is_none() && past.is_some_and(|p| p > -1e-6) {
                continue;
            }
            let c = got.unwrap_or_else(|| panic!("{m} {d:?}: None for a valid direction"));
            assert!(
                past.is_none_or(|p| p < 1e-6),
                "{m} {d:?}: {c:?} for an unseen direction"
            );
            assert!(c.chart < m.chart_count(), "{m} {d:?}: {c:?}");
            assert!(
                (0.0..=1.0).contains(&c.u) && (0.0..=1.0).contains(&c.v),
                "{m} {d:?}: {c:?}"
            );
            assert!(m.in_chart(c.chart, c.u, c.v), "{m} {d:?}: {c:?}");
            check_texels(c.u, &|| format!("{m} {d:?}"));
            check_texels(c.v, &|| format!("{m} {d:?}"));
        }
    }
}

#[test]
fn scalar_inverse() {
    for m in AnyMapping::ALL {
        for c in chart_points(m) {
            let got = m.inverse(c);
            let inside = c.chart < m.chart_count()
                && (0.0..=1.0).contains(&c.u)
                && (0.0..=1.0).contains(&c.v)
                && m.in_chart(c.chart, c.u, c.v);
            match got {
                None => assert!(!inside, "{m} {c:?}: None inside the chart"),
                Some(d) => {
                    assert!(inside, "{m} {c:?}: {d} outside the chart");
                    assert!(
                        d.is_finite() && (d.length() - 1.0).abs() < 1e-6,
                        "{m} {c:?}: {d}"
                    );
                }
            }
            // Texel addressing of any coordinate stays in range, in the
            // chart and in the atlas image; a chart out of range has no texel.
            check_texels(c.u, &|| format!("{m} {c:?}"));
            check_texels(c.v, &|| format!("{m} {c:?}"));
            let atlas = m.atlas();
            let (w, h) = atlas.image_size_for_cell_width(24).unwrap();
            let (cw, ch) = atlas.cell_size(w, h).unwrap();
            let (i, j) = (texel_index(c.u, cw), texel_index(c.v, ch));
            match atlas.chart_to_texel(c.chart, i, j, w, h) {
                Some((x, y)) => assert!(
                    c.chart < m.chart_count() && x < w && y < h,
                    "{m} {c:?}: texel ({x}, {y}) of {w}×{h}"
                ),
                None => assert!(c.chart >= m.chart_count(), "{m} {c:?}: no texel"),
            }
        }
    }
}

fn simd_forward<T: Tier>() {
    let dirs = directions();
    for m in AnyMapping::ALL {
        // Through the slice function (full batches and a padded tail).
        let mut out = vec![ChartUv::new(99, -1.0, -1.0); dirs.len()];
        assert_eq!(forward_slice::<_, T>(&m, &dirs, &mut out), dirs.len());
        for (d, got) in dirs.iter().zip(&out) {
            if let Err(e) = check_simd_forward(m, T::NAME, *d, *got) {
                panic!("{e}");
            }
            // NaN lanes included: addressing stays in range.
            check_texels(got.u, &|| format!("{m} {} {d:?}", T::NAME));
            check_texels(got.v, &|| format!("{m} {} {d:?}", T::NAME));
        }
        // Through forward8 directly.
        for chunk in dirs.chunks(LANES) {
            let b = m.forward8::<T>(Dir8::from_partial(chunk));
            for (k, d) in chunk.iter().enumerate() {
                if let Err(e) = check_simd_forward(m, T::NAME, *d, b.lane_raw(k)) {
                    panic!("forward8: {e}");
                }
                if past_rim(m, *d).is_none_or(|p| p.abs() >= 1e-3) {
                    assert_eq!(b.lane(k).is_none(), m.forward(*d).is_none(), "{m} {d:?}");
                }
            }
        }
    }
}

fn simd_inverse<T: Tier>() {
    for m in AnyMapping::ALL {
        let coords = chart_points(m);
        let mut out = vec![Vec3::splat(99.0); coords.len()];
        assert_eq!(inverse_slice::<_, T>(&m, &coords, &mut out), coords.len());
        for (c, got) in coords.iter().zip(&out) {
            if let Err(e) = check_simd_inverse(m, T::NAME, *c, *got) {
                panic!("{e}");
            }
        }
        for chunk in coords.chunks(LANES) {
            let b = m.inverse8::<T>(Uv8::from_partial(chunk));
            for (k, c) in chunk.iter().enumerate() {
                if let Err(e) = check_simd_inverse(m, T::NAME, *c, b.lane(k)) {
                    panic!("inverse8: {e}");
                }
            }
        }
    }
}

#[test]
fn simd_forward_exact() {
    simd_forward::<Exact>();
}
#[test]
fn simd_forward_fine() {
    simd_forward::<Fine>();
}
#[test]
fn simd_forward_fast() {
    simd_forward::<Fast>();
}
#[test]
fn simd_inverse_exact() {
    simd_inverse::<Exact>();
}
#[test]
fn simd_inverse_fine() {
    simd_inverse::<Fine>();
}
#[test]
fn simd_inverse_fast() {
    simd_inverse::<Fast>();
}

fn same_uv(a: ChartUv, b: ChartUv) -> bool {
    (a.chart, a.u.to_bits(), a.v.to_bits()) == (b.chart, b.u.to_bits(), b.v.to_bits())
}

fn same_dir(a: Vec3, b: Vec3) -> bool {
    a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)
}

/// Batches that mix good and bad lanes at random positions: every lane is
/// bit-identical to its input evaluated alone (broadcast to all eight lanes).
fn lanes_are_independent<T: Tier>() {
    let dirs = directions();
    let mut rng = SplitMix64::new(0xBAD_1A9E5);
    for m in AnyMapping::ALL {
        let coords = chart_points(m);
        for _ in 0..2000 {
            let batch: [Vec3; LANES] =
                core::array::from_fn(|_| dirs[rng.next_u64() as usize % dirs.len()]);
            let got = m.forward8::<T>(Dir8::from_vec3s(&batch));
            let mut sliced = [ChartUv::default(); LANES];
            forward_slice::<_, T>(&m, &batch, &mut sliced);
            for (k, d) in batch.iter().enumerate() {
                let alone = m.forward8::<T>(Dir8::splat(*d)).lane_raw(0);
                assert!(
                    same_uv(got.lane_raw(k), alone) && same_uv(sliced[k], alone),
                    "{m} {} lane {k} of {batch:?}: {:?} / {:?} vs alone {alone:?}",
                    T::NAME,
                    got.lane_raw(k),
                    sliced[k]
                );
            }

            let batch: [ChartUv; LANES] =
                core::array::from_fn(|_| coords[rng.next_u64() as usize % coords.len()]);
            let got = m.inverse8::<T>(Uv8::from_chart_uvs(&batch));
            let mut sliced = [Vec3::ZERO; LANES];
            inverse_slice::<_, T>(&m, &batch, &mut sliced);
            for (k, c) in batch.iter().enumerate() {
                let alone = m.inverse8::<T>(Uv8::from_chart_uvs(&[*c; LANES])).lane(0);
                assert!(
                    same_dir(got.lane(k), alone) && same_dir(sliced[k], alone),
                    "{m} {} lane {k} of {batch:?}: {} / {} vs alone {alone}",
                    T::NAME,
                    got.lane(k),
                    sliced[k]
                );
            }
        }
    }
}

#[test]
fn lanes_are_independent_exact() {
    lanes_are_independent::<Exact>();
}
#[test]
fn lanes_are_independent_fine() {
    lanes_are_independent::<Fine>();
}
#[test]
fn lanes_are_independent_fast() {
    lanes_are_independent::<Fast>();
}
