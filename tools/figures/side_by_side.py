#!/usr/bin/python3
"""Lays images side by side in rows (each row: files given after a '--' separator), scaled to
a common tile width, into one PNG. Used by scripts/make-figures.sh for docs/.

usage: side_by_side.py OUT.png TILE_WIDTH a1.png a2.png ... -- b1.png b2.png ...
"""
import sys

import numpy as np
import OpenImageIO as oiio


def load(path, width):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    h = round(spec.height * width / spec.width)
    out = oiio.ImageBufAlgo.resize(buf, roi=oiio.ROI(0, width, 0, h, 0, 1, 0, 3))
    px = out.get_pixels(oiio.FLOAT)
    if px.shape[2] == 1:
        px = np.repeat(px, 3, axis=2)
    return px[:, :, :3]


def main():
    out, width, files = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    rows, row = [], []
    for f in files + ["--"]:
        if f == "--":
            if row:
                rows.append(row)
            row = []
        else:
            row.append(load(f, width))
    gap = 4
    th = max(t.shape[0] for r in rows for t in r)
    cols = max(len(r) for r in rows)
    sheet = np.full((len(rows) * (th + gap) + gap, cols * (width + gap) + gap, 3), 0.04, np.float32)
    for i, r in enumerate(rows):
        for j, t in enumerate(r):
            y, x = gap + i * (th + gap), gap + j * (width + gap)
            sheet[y:y + t.shape[0], x:x + t.shape[1]] = t
    o = oiio.ImageOutput.create(out)
    o.open(out, oiio.ImageSpec(sheet.shape[1], sheet.shape[0], 3, oiio.UINT8))
    o.write_image(sheet)
    o.close()


if __name__ == "__main__":
    main()
