#!/usr/bin/env python3
"""One layer of a validate.py row against the path tracer per 8x8 bin, one channel, the image's
four quadrants folded onto the lower right (summed before the ratio): for rigs mirror-symmetric
about both image axes in that channel (two-spots in green), four times the paths per bin.

    /usr/bin/python3 tools/reference/fold_bins.py WORK/ROW/baked.exr WORK/ROW/pt.exr \
        [LAYER [CHANNEL]]

LAYER: forward (default), direct, backscatter or final; CHANNEL 0-2 (1, green, by default).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_baked import bins, read_layer  # noqa: E402


def fold(a):
    h, w = a.shape[0] // 2, a.shape[1] // 2
    return a[h:, w:] + a[h - 1::-1, w:] + a[h:, w - 1::-1] + a[h - 1::-1, w - 1::-1]


def main():
    baked, pt = sys.argv[1], sys.argv[2]
    layer = sys.argv[3] if len(sys.argv) > 3 else "forward"
    ch = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    o = fold(bins(read_layer(baked, layer), 8)[:, :, ch])
    r = fold(bins(read_layer(pt, layer), 8)[:, :, ch])
    se = np.sqrt(fold(bins(read_layer(pt, layer + "_se") ** 2, 8)[:, :, ch])) / r
    print(f"{layer}, channel {ch}: deepsea / path tracer - 1 per 8x8 bin, quadrants folded (%):")
    print(np.array2string(100 * (o / r - 1), precision=1))
    print("the path tracer's standard error (%):")
    print(np.array2string(100 * se, precision=1))


if __name__ == "__main__":
    main()
