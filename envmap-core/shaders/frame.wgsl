// envmap shaders: axis conventions (envmap-core/src/frame.rs). Needs common.wgsl.
//
// Every mapping is written in envmap's canonical frame: right-handed, z up
// for the latlong and the octahedral maps, z the view axis for the sphere
// maps, the paraboloid and the angular map; the cube's face table applies
// to the vector as given (GL's, Vulkan's, D3D's and wgpu's own vectors use
// no frame). A frame is the orthogonal matrix M taking the caller's
// coordinates to the canonical ones:
//
//   forward(d) = mapping_forward(M d),   inverse(c) = transpose(M) mapping_inverse(c)
//
// | constant               | caller's axes                         | caller (x, y, z) -> canonical |
// | ENVMAP_FRAME_Z_UP_RH   | z up, right-handed (seed 000, Blender) | (x, y, z)                     |
// | ENVMAP_FRAME_Y_UP_RH   | y up, right-handed (OpenGL, glTF)      | (x, -z, y)                    |
// | ENVMAP_FRAME_Y_UP_LH   | y up, left-handed (Direct3D, Unity)    | (x, z, y)                     |
//
// Y_UP_RH is the usual glTF-to-z-up rotation (+90 degrees about x); Y_UP_LH
// first flips z (left- to right-handed), then applies it.

/// Frame::Z_UP_RH (and Frame::IDENTITY): the canonical frame itself.
const ENVMAP_FRAME_Z_UP_RH: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(1.0, 0.0, 0.0),
    vec3<f32>(0.0, 1.0, 0.0),
    vec3<f32>(0.0, 0.0, 1.0),
);
/// Frame::Y_UP_RH: canonical = (x, -z, y).
const ENVMAP_FRAME_Y_UP_RH: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(1.0, 0.0, 0.0),
    vec3<f32>(0.0, 0.0, 1.0),
    vec3<f32>(0.0, -1.0, 0.0),
);
/// Frame::Y_UP_LH: canonical = (x, z, y).
const ENVMAP_FRAME_Y_UP_LH: mat3x3<f32> = mat3x3<f32>(
    vec3<f32>(1.0, 0.0, 0.0),
    vec3<f32>(0.0, 0.0, 1.0),
    vec3<f32>(0.0, 1.0, 0.0),
);

/// The caller's direction in canonical axes, as Framed::forward takes it:
/// divided by its largest magnitude first, so the product cannot overflow.
/// NaN, infinite and zero directions are returned as they are, for the
/// mapping's forward to reject.
fn envmap_frame_to_canonical(frame: mat3x3<f32>, d: vec3<f32>) -> vec3<f32> {
    if !envmap_all_finite(d) {
        return d;
    }
    let a = abs(d);
    let m = max(max(a.x, a.y), a.z);
    if m == 0.0 {
        return d;
    }
    return frame * (d / m);
}

/// A canonical direction (an inverse mapping's) in the caller's axes.
fn envmap_frame_from_canonical(frame: mat3x3<f32>, d: EnvmapDirection) -> EnvmapDirection {
    return EnvmapDirection(transpose(frame) * d.dir, d.valid);
}
