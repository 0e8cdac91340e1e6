#!/usr/bin/env python3
"""Compare an image against a reference with the metrics of host/io/metrics.c.

    compare.py TEST.exr REFERENCE.exr

Prints one JSON object:
  relMSE = mean((a - b)^2 / (b^2 + 0.01)) over pixels and channels (b: reference)
  RMSE   = sqrt(mean((a - b)^2))
  FLIP   = mean HDR-FLIP error (flip-evaluator), or null when not importable
plus the mean RGB of both images.  Exit status 1 on unreadable input or
mismatched sizes.
"""

import json
import sys

import numpy as np


def read_image(path):
    """Linear float RGB (H, W, 3) from any format Mitsuba's Bitmap reads."""
    import mitsuba as mi
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path)
    bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
    arr = np.array(bmp, copy=True, dtype=np.float32)
    return arr.reshape(bmp.height(), bmp.width(), 3)


def metrics(a, b):
    a = a.astype(np.float64)
    b = b.astype(np.float64)
    d2 = (a - b) ** 2
    out = {"relMSE": float(np.mean(d2 / (b * b + 0.01))),
           "RMSE": float(np.sqrt(np.mean(d2))),
           "FLIP": None}
    try:
        import flip_evaluator as flip
        ref = np.ascontiguousarray(np.maximum(b, 0.0), dtype=np.float32)
        tst = np.ascontiguousarray(np.maximum(a, 0.0), dtype=np.float32)
        res = flip.evaluate(ref, tst, "HDR", applyMagma=False)
        out["FLIP"] = float(res[1])
    except ImportError:
        pass
    out["mean_rgb_test"] = [float(c) for c in a.reshape(-1, 3).mean(axis=0)]
    out["mean_rgb_ref"] = [float(c) for c in b.reshape(-1, 3).mean(axis=0)]
    return out


def main():
    if len(sys.argv) != 3:
        print("usage: compare.py TEST.exr REFERENCE.exr", file=sys.stderr)
        return 2
    try:
        a = read_image(sys.argv[1])
        b = read_image(sys.argv[2])
    except Exception as e:  # Mitsuba raises RuntimeError on unreadable files
        print("compare: %s" % e, file=sys.stderr)
        return 1
    if a.shape != b.shape:
        print("compare: size mismatch %s vs %s" % (a.shape, b.shape), file=sys.stderr)
        return 1
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        print("compare: non-finite pixels", file=sys.stderr)
        return 1
    print(json.dumps(metrics(a, b)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
