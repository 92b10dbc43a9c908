"""Files of the Cycles comparison (cycles_check.py): EXR layers of both renderers, as
{layer: H x W x 3 float64}, with Cycles' passes summed into deepsea's layers, and the commands'
log."""

import subprocess
import sys

import numpy as np
import OpenImageIO as oiio


def write_exr(path, pixels, names):
    pixels = np.ascontiguousarray(pixels, dtype=np.float32)
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], pixels.shape[2], oiio.FLOAT)
    spec.channelnames = tuple(names)
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), pixels)
    if not buf.write(path):
        raise RuntimeError(f"cannot write {path}: {buf.geterror()}")


def read_channels(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise RuntimeError(f"cannot read {path}: {buf.geterror()}")
    px = buf.get_pixels(oiio.FLOAT)
    return {n: px[:, :, i].astype(np.float64) for i, n in enumerate(buf.spec().channelnames)}


def rgb(ch, prefix):
    return np.stack([ch[f"{prefix}.{c}"] for c in "RGB"], axis=-1)


def cycles_layers(path):
    ch = read_channels(path)
    p = "ViewLayer."
    col = rgb(ch, p + "DiffCol")
    return dict(backscatter=rgb(ch, p + "VolumeDir") + rgb(ch, p + "VolumeInd"),
                surface=(rgb(ch, p + "DiffDir") + rgb(ch, p + "DiffInd")) * col,
                final=rgb(ch, p + "Combined"))


def deepsea_layers(path):
    ch = read_channels(path)
    return dict(backscatter=rgb(ch, "backscatter") + rgb(ch, "forward"),
                surface=rgb(ch, "direct"),
                final=rgb(ch, "final"))


def run(cmd, log):
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode:
        sys.stdout.write(open(log).read()[-3000:])
        raise RuntimeError(f"failed ({r.returncode}): {' '.join(cmd)}")
