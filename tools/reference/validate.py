#!/usr/bin/env python3
"""deepsea against its own all-order path tracer over the range of real use (docs/validation.md).

Usage: validate.py DEEPSEA WORK [--set table|wall|ci] [--rows a,b] [--paths-scale F]
                   [--threads N] [--keep-reference] [--reference-only] [--check] [--confirm F]
                   [--confirm-over P] [--bin N] [--min-paths N]
  table: the validation table's rows (waters, beams, rigs, cameras, phase functions)
  wall:  the surface's effect on the water light: planes at 1, 2, 3 m against empty water
         ending at the same depth (the path tracer's own water light, same seed), and deepsea's
  ci:    a reduced table for the test suite; --check exits 1 where a row misses its target
Each row: deepsea bake --scattering multiple + render --layers, against deepsea reference
--scattering multiple. Prints a Markdown table: per layer (water = backscatter, surface =
direct + forward, final) the largest channel difference in image sums, and the worst 4x4 bin
of those the path tracer resolves (the bin's standard error <= 2.5 %; where fewer than half are,
the smallest power-of-two bin with half resolved, named in the bin column; --bin N: N x N bins
whatever share is resolved). --confirm F: each
resolved bin over the 10 % target path-traced again alone, in a window of the row's camera, with
F times the paths (a bin's own error understates it where its paths missed the bright ones);
--confirm-over P: every resolved bin over P % instead.
Debian's python3, numpy, OIIO.
"""

import argparse
import math
import os
import sys
import time

import numpy as np

# the EXR reader and writer, the command runner and the bins are compare_baked.py's
from compare_baked import bins, read_layer, run, write_exr


def spot(name, pos, aim, rgb, sigma):
    n = math.sqrt(sum(a * a for a in aim))
    d = ", ".join(f"{a / n:.6f}" for a in aim)
    p = ", ".join(str(a) for a in pos)
    return (f"    - name: {name}\n      position: [{p}]\n      direction: [{d}]\n"
            f"      intensity: [{rgb[0]}, {rgb[1]}, {rgb[2]}]\n"
            f"      rid: {{gaussian: {{sigma_deg: {sigma}}}}}\n")


RIGS = {
    # the Cycles scenes' two 35 degree spots, toed in 30.7 degrees (docs/validation-cycles.md)
    "two-spots": [spot("left", (-0.5, 0, 0), (0.510586, 0, 0.859826), (1.0, 0.9, 0.8), 35),
                  spot("right", (0.5, 0, 0), (-0.510586, 0, 0.859826), (0.8, 0.9, 1.0), 35)],
    # an AUV: a lamp 0.7 m above and 0.2 m behind the camera (sigma 20), a warm side lamp (15)
    "auv": [spot("top", (0, -0.7, -0.2), (0, 0.25, 1), (1.0, 1.0, 1.0), 20),
            spot("side", (0.6, 0, 0), (-0.2, 0, 1), (1.0, 0.8, 0.6), 15)],
    # two sigma 8 degree pencil beams crossing at 2 m
    "pencil": [spot("left", (-0.5, 0, 0), (0.5, 0, 2), (1.0, 1.0, 1.0), 8),
               spot("right", (0.5, 0, 0), (-0.5, 0, 2), (1.0, 1.0, 1.0), 8)],
}


def water(name, c, b, phase):
    return (f"water:\n  name: {name}\n  attenuation: {list(c)}\n  scattering: {list(b)}\n"
            f"  phase: {phase}\n  forward_scatter: on\n")


HG = "{henyey_greenstein: {g: %s}}"
WATERS = {
    "clear": water("clear", (0.4901, 0.1982, 0.1763), (0.1140, 0.1223, 0.1357), HG % 0.9),
    "nepheloid": water("nepheloid", (0.2, 0.2, 0.2), (0.13, 0.13, 0.13), HG % 0.92),
    "coastal": water("coastal", (0.6, 0.4, 0.35), (0.3, 0.3, 0.3), HG % 0.9),
    "petzold": water("petzold", (0.6, 0.4, 0.35), (0.3, 0.3, 0.3), "{petzold: coastal}"),
    "turbid": water("turbid", (1.0, 0.95, 1.05), (0.8, 0.78, 0.82), HG % 0.85),
}
ALBEDO = (0.7, 0.55, 0.4)
Z_MAX = 20.0  # open water ends here for both renderers

# name: (water, rig, width x height, horizontal field of view (deg), plane depth or None,
#        path-tracer paths per pixel, reference z-max or None)
TABLE = {
    "clear-plane": ("clear", "two-spots", "64x48", 64.5, 3.0, 1024),
    "clear-empty": ("clear", "two-spots", "64x48", 64.5, None, 1024),
    "coastal-plane": ("coastal", "two-spots", "64x48", 64.5, 3.0, 1024),
    "petzold-empty": ("petzold", "two-spots", "64x48", 64.5, None, 1024),
    "turbid-plane": ("turbid", "two-spots", "64x48", 64.5, 2.0, 1024),
    "turbid-empty": ("turbid", "two-spots", "64x48", 64.5, None, 1024),
    "nepheloid-auv": ("nepheloid", "auv", "64x48", 64.5, 4.0, 1024),
    "coastal-auv": ("coastal", "auv", "160x120", 64.5, 3.0, 256),
    "pencil-empty": ("clear", "pencil", "64x48", 90.0, None, 1024),
    "clear-800": ("clear", "two-spots", "800x800", 64.5, 3.0, 4),
}
# CI: 1/16 of the default Monte Carlo paths per column (a 16x12 bake in about 20 s of one core)
CI_BAKE = "--paths 4096 --no-preview"
CI = {
    "ci-clear-plane": ("clear", "two-spots", "16x12", 64.5, 3.0, 512),
    "ci-turbid-plane": ("turbid", "two-spots", "16x12", 64.5, 2.0, 512),
}


def wall_rows():
    rows = {}
    for w in ("clear", "coastal", "turbid"):
        for z in (1.0, 2.0, 3.0):
            rows[f"{w}-{z:g}m"] = (w, "two-spots", "16x12", 64.5, z, 2048)
            rows[f"{w}-{z:g}m-open"] = (w, "two-spots", "16x12", 64.5, ("open", z), 2048)
    return rows


def camera(w, h, fov, window=None):
    """(width, height, fx, fy, cx, cy) of a row's camera: w x h px, horizontal field of view fov
    (degrees), centred. window (row, column, height, width): that window of it alone, the same
    rays through the same pixels (pixel (u, v) of the window is (column + u, row + v))."""
    f = (w / 2) / math.tan(math.radians(fov) / 2)
    cx, cy = (w - 1) / 2, (h - 1) / 2
    if window is None:
        return (w, h, f, f, cx, cy)
    r0, c0, wh, ww = window
    return (ww, wh, f, f, cx - c0, cy - r0)


def write_scene(d, row, cam, plane):
    """A row's setup.yaml, uniform albedo and depth (plane or open water) in folder d."""
    wname, rig = row[0], row[1]
    w, h, fx, fy, cx, cy = cam
    os.makedirs(d, exist_ok=True)
    setup = os.path.join(d, "setup.yaml")
    with open(setup, "w") as fh:
        fh.write(f"camera: {{width: {w}, height: {h}, fx: {fx}, fy: {fy}, "
                 f"cx: {cx}, cy: {cy}}}\nrig:\n  name: {rig}\n  lights:\n"
                 + "".join(RIGS[rig]) + WATERS[wname])
    rgb, depth = os.path.join(d, "albedo.exr"), os.path.join(d, "depth.exr")
    write_exr(rgb, np.tile(np.array(ALBEDO, np.float32), (h, w, 1)))
    write_exr(depth, np.full((h, w, 1), plane if plane else np.inf, np.float32))
    return setup, rgb, depth


def render_row(a, name, row):
    """Bakes (once per camera, rig and water), renders and path-traces one row's scene."""
    wname, rig, size, fov, z, paths = row
    paths = max(1, int(paths * a.paths_scale))
    w, h = map(int, size.split("x"))
    d = os.path.join(a.work, name)
    # ("open", z): empty water whose camera rays end at z (the same seed as the plane at z)
    open_to = z[1] if isinstance(z, tuple) else None
    plane = None if isinstance(z, tuple) else z
    setup, rgb, depth = write_scene(d, row, camera(w, h, fov), plane)
    th = ["--threads", str(a.threads)]
    asset = os.path.join(a.work, f"{wname}_{rig}_{size}_{fov:g}.vdb")
    times = {}
    baked, pt = os.path.join(d, "baked.exr"), os.path.join(d, "pt.exr")
    if not (a.keep_reference and os.path.exists(pt)):
        times["reference"] = run(
            [a.deepsea, "reference", "--config", setup, "--rgb", rgb, "--depth", depth,
             "--scattering", "multiple", "--paths", str(paths),
             "--z-max", str(open_to if open_to else Z_MAX), "--layers", pt] + th)
    if a.reference_only:
        pass
    elif open_to is None:
        if not os.path.exists(asset):
            times["bake"] = run([a.deepsea, "bake", "--config", setup, "--scattering",
                                 "multiple", "--z-max", str(Z_MAX), "-o", asset]
                                + a.bake_args.split() + th)
        times["render"] = run([a.deepsea, "render", "--asset", asset, "--rgb", rgb, "--depth",
                               depth, "--layers", baked] + th)
    print(f"{name}: " + ", ".join(f"{k} {v:.0f} s" for k, v in times.items())
          + f" ({paths} paths per pixel)", file=sys.stderr)
    return baked if open_to is None else None, pt, plane


LAYERS = {"water": ["backscatter"], "surface": ["direct", "forward"], "final": ["final"]}
BIN_TARGET = 0.10  # per bin, of the path tracer's value
RETRACE_SEED = 2  # --confirm: the windows' seed (the rows path-trace with seed 1)


def compare(baked, pt, plane, fixed_bin=0, over_at=BIN_TARGET, min_paths=0):
    """Per layer: (sum diff %, its SE %, worst resolved bin %, bin size, % of bins resolved),
    the channel furthest off in sums. fixed_bin: that bin size, whatever share is resolved;
    over_at: the bins listed for --confirm are the resolved ones off by more than this;
    min_paths: only bins whose pixels had this many paths on average (combine_traces.py's
    `paths` layer: a trace pooled from windows) count as resolved."""
    traced = read_layer(pt, "paths")[:, :, :1] if min_paths else None
    out = {}
    for name, parts in LAYERS.items():
        if plane is None and name == "surface":
            continue
        ours = sum(read_layer(baked, p) for p in parts)
        ref = sum(read_layer(pt, p) for p in parts)
        var = sum(read_layer(pt, p + "_se") ** 2 for p in parts)
        diff = [100 * (ours[:, :, c].sum() / ref[:, :, c].sum() - 1) for c in range(3)]
        se = [100 * math.sqrt(var[:, :, c].sum()) / ref[:, :, c].sum() for c in range(3)]
        worst = max(range(3), key=lambda c: abs(diff[c]))
        # Bins the path tracer resolves: its own standard error <= 2.5 % (its heavy tails leave
        # a few bins far off with errors of 10-40 %); 4x4, or larger while fewer than half are.
        b = fixed_bin or 4
        while True:
            bo, br, bv = bins(ours, b), bins(ref, b), bins(var, b)
            bse = np.sqrt(bv) / br
            ok = bse <= 0.025
            if min_paths:
                ok &= bins(np.repeat(traced, 3, axis=2), b) >= min_paths * b * b
            if fixed_bin or ok.mean() >= 0.5 or b * 2 > min(ours.shape[:2]) // 2:
                break
            b *= 2
        rel = np.abs(bo - br) / br
        # bins with a resolved channel over over_at: (row, column, its worst such channel %)
        hot = (ok & (rel > over_at)).any(2)
        over = [(int(r), int(c), 100 * rel[r, c][ok[r, c]].max(),
                 100 * bse[r, c][ok[r, c]].max()) for r, c in zip(*np.nonzero(hot))]
        rest = ok & ~hot[:, :, None]
        # the mean signed bin error, resolved bins and the others, in the channel furthest off
        signed = (bo - br)[:, :, worst] / br[:, :, worst]
        lean = [100 * signed[m].mean() if m.any() else math.nan
                for m in (ok[:, :, worst], ~ok[:, :, worst])]
        out[name] = (diff[worst], se[worst], 100 * rel[ok].max() if ok.any() else math.nan, b,
                     100 * ok.mean(), (over, 100 * rel[rest].max() if rest.any() else 0.0, lean))
    return out


def retrace(a, name, row, baked, plane, layers):
    """Each resolved bin over the target, path-traced again in a window of its own (the same
    rays: camera(window=...)) with a.confirm times the row's paths and another seed: a bin's
    own standard error understates its error where its paths missed the rare bright ones, so
    the bins that look worst are those that missed most (docs/validation.md). Returns per layer [(bin row, bin column, size, first %, its SE %,
    re-traced %, its SE %, paths per pixel)]."""
    wname, rig, size, fov, z, paths = row
    w, h = map(int, size.split("x"))
    paths = max(1, int(paths * a.paths_scale)) * a.confirm
    out = {}
    traced = 0.0
    for layer, (_, _, _, b, _, (over, _, _)) in layers.items():
        parts = LAYERS[layer]
        ours = sum(read_layer(baked, p) for p in parts)
        for r, c, first, first_se in over:
            d = os.path.join(a.work, name, f"window-{b}-{r}-{c}")
            pt = os.path.join(d, "pt.exr")
            setup, rgb, depth = write_scene(d, row, camera(w, h, fov, (r * b, c * b, b, b)), plane)
            if not (a.keep_reference and os.path.exists(pt)):
                traced += run([a.deepsea, "reference", "--config", setup, "--rgb", rgb,
                               "--depth", depth, "--scattering", "multiple", "--paths", str(paths),
                               "--seed", str(RETRACE_SEED), "--z-max", str(Z_MAX), "--layers", pt,
                               "--threads", str(a.threads)])
            ref = sum(read_layer(pt, p) for p in parts).sum(axis=(0, 1))
            var = sum(read_layer(pt, p + "_se") ** 2 for p in parts).sum(axis=(0, 1))
            mine = ours[r * b:(r + 1) * b, c * b:(c + 1) * b].sum(axis=(0, 1))
            again = mine / ref - 1
            ch = int(np.argmax(np.abs(again)))
            out.setdefault(layer, []).append((r, c, b, first, first_se, 100 * again[ch],
                                              100 * math.sqrt(var[ch]) / ref[ch], paths))
    print(f"{name}: windows path-traced in {traced:.0f} s", file=sys.stderr)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("deepsea")
    ap.add_argument("work")
    ap.add_argument("--set", default="table", choices=["table", "wall", "ci"])
    ap.add_argument("--rows", default="")
    ap.add_argument("--paths-scale", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--keep-reference", action="store_true",
                    help="reuse a row's pt.exr already in WORK (same paths and seed)")
    ap.add_argument("--bake-args", default="", help="more options for deepsea bake")
    ap.add_argument("--reference-only", action="store_true",
                    help="path-trace only (then rerun with --keep-reference)")
    ap.add_argument("--confirm", type=int, default=0, metavar="F",
                    help="path-trace each resolved bin over the 10 %% target again, alone in a "
                         "window, with F times the row's paths and seed 2")
    ap.add_argument("--min-paths", type=int, default=0, metavar="N",
                    help="count a bin as resolved only where the path tracer ran N paths per "
                         "pixel there (a trace pooled by combine_traces.py from windows)")
    ap.add_argument("--confirm-over", type=float, default=100 * BIN_TARGET, metavar="P",
                    help="--confirm re-traces the resolved bins off by more than P %% (default: "
                         "the 10 %% target; lower where the worst bin left is near the target)")
    ap.add_argument("--bin", type=int, default=0, metavar="N",
                    help="compare N x N bins whatever share of them the path tracer resolves")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 where a row misses 5 %% + 3 SE in image sums")
    a = ap.parse_args()
    rows = {"table": TABLE, "wall": wall_rows(), "ci": CI}[a.set]
    if a.set == "ci" and not a.bake_args:
        a.bake_args = CI_BAKE
    if a.rows:
        rows = {k: rows[k] for k in a.rows.split(",")}
    os.makedirs(a.work, exist_ok=True)
    t0 = time.time()
    results = {name: render_row(a, name, row) for name, row in rows.items()}
    print(f"total {time.time() - t0:.0f} s", file=sys.stderr)
    if a.reference_only:
        return 0
    if a.set == "wall":
        return wall_table(rows, results)
    print("| row | water | rig | camera | plane | layer | sum diff | SE | worst bin | bin "
          "| bins resolved |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    failed = []
    retraced = {}
    for name, (baked, pt, plane) in results.items():
        wname, rig, size, fov, z, _ = rows[name]
        layers = compare(baked, pt, plane, a.bin, a.confirm_over / 100, a.min_paths)
        for layer, (dd, se, wb, b, bse, _) in layers.items():
            print(f"| {name} | {wname} | {rig} | {size} {fov:g} deg | "
                  f"{f'{plane:g} m' if plane else 'none'} | {layer} | {dd:+.1f}% | {se:.1f}% | "
                  f"{wb:.1f}% | {b}x{b} | {bse:.0f}% |")
            if abs(dd) > 5 + 3 * se:
                failed.append(f"{name} {layer} {dd:+.1f}%")
        if a.confirm:
            retraced[name] = (layers, retrace(a, name, rows[name], baked, plane, layers))
    if any(per_layer for _, per_layer in retraced.values()):
        print_retraced(retraced, a.confirm_over)
    if a.check and failed:
        print("missed 5 % + 3 SE in image sums: " + "; ".join(failed), file=sys.stderr)
        return 1
    return 0


def print_retraced(retraced, over_at):
    """The re-traced bins, and each layer's worst resolved bin with them in place."""
    print("\n| row | layer | bin | pixels (rows, columns) | first | its SE | re-traced | its SE "
          "| paths per pixel |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (layers, per_layer) in retraced.items():
        for layer, hits in per_layer.items():
            for r, c, b, first, first_se, again, se, paths in hits:
                print(f"| {name} | {layer} | {b}x{b} | {r * b}-{r * b + b - 1}, "
                      f"{c * b}-{c * b + b - 1} | {first:.1f}% | {first_se:.1f}% | {again:+.1f}% "
                      f"| {se:.1f}% | {paths} |")
    for name, (layers, per_layer) in retraced.items():
        for layer, (_, _, wb, b, _, (_, rest, lean)) in layers.items():
            hits = per_layer.get(layer, [])
            if not hits:
                continue
            again = max(abs(h[5]) for h in hits)
            print(f"{name} {layer}: worst resolved {b}x{b} bin {wb:.1f}% as first traced; the "
                  f"{len(hits)} over {over_at:g}% re-traced: worst {again:.1f}%; "
                  f"with them in place {max(rest, again):.1f}%; mean bin error (the sum's "
                  f"channel) {lean[0]:+.1f}% on resolved bins, {lean[1]:+.1f}% on the others")


def wall_table(rows, results):
    """The surface's effect on the water light: path tracer plane vs open water to its depth."""
    print("| water | plane | PT water, plane / open to its depth | its SE | deepsea water / PT "
          "| PT forward / final | deepsea forward / PT |")
    print("|---|---|---|---|---|---|---|")
    for name, (baked, pt, plane) in results.items():
        if plane is None:
            continue
        _, pt_open, _ = results[name + "-open"]
        wp, wo = read_layer(pt, "backscatter"), read_layer(pt_open, "backscatter")
        sp = read_layer(pt, "backscatter_se") ** 2
        so = read_layer(pt_open, "backscatter_se") ** 2
        ours = read_layer(baked, "backscatter")
        fw, fin = read_layer(pt, "forward"), read_layer(pt, "final")
        ofw = read_layer(baked, "forward")
        ch = lambda f: " / ".join(f(c) for c in range(3))  # noqa: E731
        s = lambda x, c: x[:, :, c].sum()  # noqa: E731
        print(f"| {rows[name][0]} | {plane:g} m "
              f"| {ch(lambda c: f'{100 * (s(wp, c) / s(wo, c) - 1):+.1f}%')} "
              f"| {ch(lambda c: f'{100 * math.sqrt(s(sp, c) + s(so, c)) / s(wo, c):.1f}%')} "
              f"| {ch(lambda c: f'{100 * (s(ours, c) / s(wp, c) - 1):+.1f}%')} "
              f"| {ch(lambda c: f'{100 * s(fw, c) / s(fin, c):.0f}%')} "
              f"| {ch(lambda c: f'{100 * (s(ofw, c) / s(fw, c) - 1):+.1f}%')} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
