#!/usr/bin/python3
"""Independent NumPy implementation of docs/model.md (direct signal and single-scattering
backscatter) for planar scenes, compared with `deepsea reference`.

It shares no code with the C++ library: its own ray set-up, analytic plane normal, Gaussian RID,
Henyey-Greenstein / isotropic phase, Petzold phase read from ../shared/data/optics (the measured
table, not deepsea's embedded copy; skipped where ../shared is absent), and a composite Simpson
rule on a fine grid along each ray.

usage: reference_check.py DEEPSEA_BIN WORKDIR
"""
import math
import os
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

W, H, FX, FY, CX, CY = 80, 60, 60.0, 60.0, 39.5, 29.5
LIGHTS = [  # position, direction (unnormalised), intensity RGB, sigma_deg
    ((-0.5, 0.0, 0.0), (math.sin(0.536), 0.0, math.cos(0.536)), (1.0, 0.9, 0.8), 35.0),
    ((0.6, -0.2, 0.1), (-0.5, 0.3, 1.0), (0.7, 0.8, 1.0), 25.0),
]
WATERS = {
    "hg": dict(c=(0.45, 0.20, 0.17), b=(0.12, 0.12, 0.13), phase="henyey_greenstein", g=0.8),
    "iso": dict(c=(0.6, 0.35, 0.3), b=(0.3, 0.25, 0.2), phase="isotropic", g=0.0),
    "petzold": dict(c=(0.49, 0.20, 0.18), b=(0.11, 0.12, 0.14), phase="petzold", g=0.0),
}
PETZOLD_CSV = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                           "shared", "data", "optics", "petzold_1972_vsf.csv")


def petzold_phase(column="coastal"):
    """p(cos psi) from the measured table: linear in log(beta) vs log(psi), constant below the
    first angle (DESIGN: docs/model.md), normalised numerically to 1 over the sphere."""
    rows = [l.split(",") for l in open(PETZOLD_CSV) if l[0].isdigit()]
    header = [l for l in open(PETZOLD_CSV) if l.startswith("psi")][0].strip().split(",")
    col = header.index(column)
    psi = np.array([float(r[0]) for r in rows])
    beta = np.array([float(r[col]) for r in rows])
    lp, lb = np.log(psi), np.log(beta)

    def beta_at(deg):
        deg = np.clip(deg, psi[0], 180.0)
        return np.exp(np.interp(np.log(deg), lp, lb))

    # normalise: 2 pi integral beta(psi) sin(psi) dpsi, fine grid, dense near 0
    grid = np.concatenate([np.linspace(0.0, psi[0], 2001), np.geomspace(psi[0], 180.0, 400001)[1:]])
    f = beta_at(grid) * np.sin(np.radians(grid))
    total = 2 * math.pi * np.trapz(f, np.radians(grid))
    return lambda cos_psi: beta_at(np.degrees(np.arccos(np.clip(cos_psi, -1, 1)))) / total


def write_yaml(path, water):
    lights = []
    for i, (p, d, inten, sigma) in enumerate(LIGHTS):
        lights.append(
            f"    - name: l{i}\n      position: [{p[0]}, {p[1]}, {p[2]}]\n"
            f"      direction: [{d[0]}, {d[1]}, {d[2]}]\n"
            f"      intensity: [{inten[0]}, {inten[1]}, {inten[2]}]\n"
            f"      rid: {{gaussian: {{sigma_deg: {sigma}}}}}\n")
    phase = {"isotropic": "isotropic", "petzold": "{petzold: coastal}"}.get(
        water["phase"], f"{{henyey_greenstein: {{g: {water['g']}}}}}")
    c, b = water["c"], water["b"]
    text = (f"camera: {{width: {W}, height: {H}, fx: {FX}, fy: {FY}, cx: {CX}, cy: {CY}}}\n"
            "rig:\n  name: check\n  lights:\n" + "".join(lights) +
            f"water:\n  name: check\n  attenuation: [{c[0]}, {c[1]}, {c[2]}]\n"
            f"  scattering: [{b[0]}, {b[1]}, {b[2]}]\n  phase: {phase}\n")
    with open(path, "w") as f:
        f.write(text)


def write_exr(path, arr):
    if arr.ndim == 2:
        arr = arr[:, :, None]
    arr = np.ascontiguousarray(arr, dtype=np.float32)
    ch = arr.shape[2]
    spec = oiio.ImageSpec(arr.shape[1], arr.shape[0], ch, oiio.FLOAT)
    if ch == 1:
        spec.channelnames = ("Z",)
    out = oiio.ImageOutput.create(path)
    assert out.open(path, spec), oiio.geterror()
    out.write_image(arr)
    out.close()


def read_layer(path, layer, chans):
    buf = oiio.ImageBuf(path)
    names = list(buf.spec().channelnames)
    px = buf.get_pixels(oiio.FLOAT)
    return np.stack([px[:, :, names.index(f"{layer}.{c}")] for c in chans], axis=-1)


def phase(cos_psi, water):
    if water["phase"] == "petzold":
        return water["p"](cos_psi)
    if water["phase"] == "isotropic":
        return np.full_like(cos_psi, 1.0 / (4 * math.pi))
    g = water["g"]
    return (1 - g * g) / (4 * math.pi * (1 + g * g - 2 * g * cos_psi) ** 1.5)


def rays():
    u, v = np.meshgrid(np.arange(W, dtype=np.float64), np.arange(H, dtype=np.float64))
    return np.stack([(u - CX) / FX, (v - CY) / FY, np.ones_like(u)], axis=-1)


def direct_and_backscatter(depth, albedo, water):
    r = rays()
    c, b = np.array(water["c"]), np.array(water["b"])
    P = r * depth[..., None]
    d2 = np.linalg.norm(P, axis=-1)
    # analytic normal of the plane z = z0 + a x (x in metres, camera frame): n ~ (-a, 0, 1)
    n = np.array([-PLANE_A, 0.0, 1.0]) / math.hypot(PLANE_A, 1.0)
    n = -n  # facing the camera
    D = np.zeros(depth.shape + (3,))
    # backscatter: Simpson on N intervals along each ray from 0 to d2
    N = 3000
    s = np.linspace(0.0, 1.0, N + 1)
    wts = np.ones(N + 1)
    wts[1:-1:2], wts[2:-1:2] = 4, 2
    wts /= 3 * N
    unit = r / np.linalg.norm(r, axis=-1, keepdims=True)
    B = np.zeros(depth.shape + (3,))
    for pos, dirn, inten, sigma in LIGHTS:
        L = np.array(pos)
        a = np.array(dirn) / np.linalg.norm(dirn)
        I0 = np.array(inten)
        sig = math.radians(sigma)
        # direct
        toL = L - P
        d1 = np.linalg.norm(toL, axis=-1)
        wl = toL / d1[..., None]
        theta = np.arccos(np.clip(-(wl @ a), -1, 1))
        rid = np.exp(-theta ** 2 / (2 * sig * sig))
        cosn = np.maximum(0.0, wl @ n)
        D += (albedo / math.pi) * I0 * (rid * cosn / d1 ** 2)[..., None] * \
            np.exp(-c * (d1 + d2)[..., None])
        # backscatter, pixel row by pixel row to bound memory
        for y in range(H):
            t = d2[y][:, None] * s[None, :]                       # (W, N+1)
            X = unit[y][:, None, :] * t[..., None]                # (W, N+1, 3)
            LX = X - L
            d1p = np.linalg.norm(LX, axis=-1)
            wlx = LX / d1p[..., None]
            cos_psi = np.sum(wlx * -unit[y][:, None, :], axis=-1)
            th = np.arccos(np.clip(wlx @ a, -1, 1))
            f = np.exp(-th ** 2 / (2 * sig * sig)) * phase(cos_psi, water) / d1p ** 2
            att = np.exp(-c[None, None, :] * (d1p + t)[..., None])
            integrand = f[..., None] * att * b * I0
            B[y] += np.einsum("wnc,n->wc", integrand, wts) * d2[y][:, None]
    return D, B


PLANE_Z0, PLANE_A = 3.0, 0.35


def main():
    deepsea, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    rng = np.random.default_rng(7)
    albedo = rng.uniform(0.1, 0.6, size=(H, W, 3))
    r = rays()
    # plane z = z0 + a x with x = z * rx  =>  z = z0 / (1 - a rx)
    depth = PLANE_Z0 / (1.0 - PLANE_A * r[..., 0])
    write_exr(os.path.join(work, "albedo.exr"), albedo)
    write_exr(os.path.join(work, "depth.exr"), depth)
    albedo32 = albedo.astype(np.float32).astype(np.float64)
    depth32 = depth.astype(np.float32).astype(np.float64)
    failures = 0
    for name, water in WATERS.items():
        if water["phase"] == "petzold":
            if not os.path.exists(PETZOLD_CSV):
                print(f"{name}: skipped ({PETZOLD_CSV} absent)")
                continue
            water["p"] = petzold_phase()
        cfg = os.path.join(work, f"{name}.yaml")
        write_yaml(cfg, water)
        out = os.path.join(work, f"{name}.exr")
        subprocess.run([deepsea, "reference", "--config", cfg, "--rgb",
                        os.path.join(work, "albedo.exr"), "--depth",
                        os.path.join(work, "depth.exr"), "--layers", out], check=True)
        D_ref, B_ref = direct_and_backscatter(depth32, albedo32, water)
        D = read_layer(out, "direct", "RGB")
        B = read_layer(out, "backscatter", "RGB")
        # the C++ normals come from the depth map by finite differences; exclude the border
        inner = (slice(1, -1), slice(1, -1))
        eD = np.abs(D[inner] - D_ref[inner]) / np.maximum(D_ref[inner], 1e-12)
        eB = np.abs(B - B_ref) / np.maximum(B_ref, 1e-12)
        print(f"{name}: direct rel err mean {eD.mean():.2e} max {eD.max():.2e}; "
              f"backscatter rel err mean {eB.mean():.2e} max {eB.max():.2e}")
        if eD.max() > 1e-3 or eB.max() > 2e-3:
            failures += 1
            print(f"FAIL {name}: tolerance direct 1e-3, backscatter 2e-3")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
