#!/usr/bin/env python3
"""The job of `envmap convert IN.exr OUT.exr --to cube --size N` with
py360convert, for whole-process comparisons: read a float latitude-longitude
EXR with OpenCV's OpenEXR codec, resample it bilinearly into a horizontal cube
cross of N^2 faces with `py360convert.e2c(..., cube_format="dice")`, write a
float EXR with OpenCV.

    python3 py360-convert.py IN.exr OUT.exr [N] [none|zip|rle|piz]

The last argument is the EXR compression (default none, as envmap's f32 default
without the cross's empty cells). py360convert's latlong is envmap's default
convention (docs/conventions.md); its dice layout is the horizontal cross, with
+y and -y above and below +z as envmap's.

Needs `pip install "opencv-python-headless<4.11" numpy py360convert`.
"""
import os
import sys
import time

os.environ.setdefault("OPENCV_IO_ENABLE_OPENEXR", "1")
import cv2  # noqa: E402
import numpy as np  # noqa: E402
import py360convert  # noqa: E402


def main():
    src_path, out_path = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 1024
    codec = sys.argv[4] if len(sys.argv) > 4 else "none"
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
    src = np.ascontiguousarray(src[:, :, :3])
    t1 = time.perf_counter()
    out = py360convert.e2c(src, face_w=n, mode="bilinear", cube_format="dice")
    out = np.ascontiguousarray(out, dtype=np.float32)
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
    h, w = src.shape[:2]
    print(
        f"py360convert {w}x{h} -> {out.shape[1]}x{out.shape[0]}: load {1e3 * (t1 - t0):.0f} ms, "
        f"convert {1e3 * (t2 - t1):.0f} ms, save {1e3 * (t3 - t2):.0f} ms",
        file=sys.stderr,
    )


if __name__ == "__main__":
    main()
