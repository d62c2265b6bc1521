#!/usr/bin/env python3
"""The job of `envmap convert IN.exr OUT.exr --to cube --size N` with OpenCV and
its OpenEXR codec, for whole-process comparisons: read a float latitude-longitude
EXR, resample it bilinearly into a horizontal cube cross of N^2 faces (the GL
face table, y up, as envmap's default cube file; the latlong as envmap reads it:
u = 1/2 + atan2(x, z)/(2 pi), centre +z, v = acos(y)/pi), write a float EXR.

    OPENCV_IO_ENABLE_OPENEXR=1 python3 opencv-convert.py IN.exr OUT.exr [N] [none|zip|rle|piz]

The last argument is the EXR compression (OpenCV's default, as OpenEXR's, is zip;
envmap's default for f32 is none).

Needs `pip install "opencv-python-headless<4.11" numpy` (the 5.x wheels carry no
OpenEXR codec). The face table and the cross
follow docs/conventions.md; the output is checked against envmap's own in the
comparison that docs/performance.md reports (PSNR printed with --check FILE).
"""
import os
import sys
import time

os.environ.setdefault("OPENCV_IO_ENABLE_OPENEXR", "1")
import cv2  # noqa: E402
import numpy as np  # noqa: E402


def face_dirs(face, n):
    """Unit directions of face `face`'s texel centres (GL table, s right, t down)."""
    c = (np.arange(n, dtype=np.float32) + 0.5) / n * 2.0 - 1.0
    sc, tc = np.meshgrid(c, c)
    one = np.ones_like(sc)
    x, y, z = {
        0: (one, -tc, -sc),  # +x: sc = -z, tc = -y
        1: (-one, -tc, sc),  # -x: sc = +z, tc = -y
        2: (sc, one, tc),  # +y: sc = +x, tc = +z
        3: (sc, -one, -tc),  # -y: sc = +x, tc = -z
        4: (sc, -tc, one),  # +z: sc = +x, tc = -y
        5: (-sc, -tc, -one),  # -z: sc = -x, tc = -y
    }[face]
    return x, y, z


# Cell (column, row) of each face in the horizontal cross (4 x 3 cells):
#   .  +y  .   .
#  -x  +z  +x  -z
#   .  -y  .   .
CROSS = {0: (2, 1), 1: (0, 1), 2: (1, 0), 3: (1, 2), 4: (1, 1), 5: (3, 1)}


def main():
    src_path, out_path = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 1024
    codec = sys.argv[4] if len(sys.argv) > 4 else "zip"
    codecs = {
        "none": cv2.IMWRITE_EXR_COMPRESSION_NO,
        "rle": cv2.IMWRITE_EXR_COMPRESSION_RLE,
        "zip": cv2.IMWRITE_EXR_COMPRESSION_ZIP,
        "piz": cv2.IMWRITE_EXR_COMPRESSION_PIZ,
    }
    t0 = time.perf_counter()
    src = cv2.imread(src_path, cv2.IMREAD_UNCHANGED)
    if src is None:
        sys.exit(f"{src_path}: OpenCV could not read it")
    src = src[:, :, :3]
    t1 = time.perf_counter()
    h, w = src.shape[:2]
    out = np.zeros((3 * n, 4 * n, 3), dtype=np.float32)
    for face, (cx, cy) in CROSS.items():
        x, y, z = face_dirs(face, n)
        inv = 1.0 / np.sqrt(x * x + y * y + z * z)
        x, y, z = x * inv, y * inv, z * inv
        u = 0.5 + np.arctan2(x, z) / (2.0 * np.pi)
        v = np.arccos(np.clip(y, -1.0, 1.0)) / np.pi
        map_x = (u * w - 0.5).astype(np.float32)
        map_y = (v * h - 0.5).astype(np.float32)
        out[cy * n:(cy + 1) * n, cx * n:(cx + 1) * n] = cv2.remap(
            src, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_WRAP
        )
    t2 = time.perf_counter()
    params = [
        cv2.IMWRITE_EXR_TYPE,
        cv2.IMWRITE_EXR_TYPE_FLOAT,
        cv2.IMWRITE_EXR_COMPRESSION,
        codecs[codec],
    ]
    if not cv2.imwrite(out_path, out, params):
        sys.exit(f"{out_path}: OpenCV could not write it")
    t3 = time.perf_counter()
    print(
        f"opencv {w}x{h} -> {4 * n}x{3 * n}: load {1e3 * (t1 - t0):.0f} ms, "
        f"convert {1e3 * (t2 - t1):.0f} ms, save {1e3 * (t3 - t2):.0f} ms",
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
