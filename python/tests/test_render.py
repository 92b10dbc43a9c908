"""Rendering frames from NumPy: the layers, every input dtype, depth kinds, open water, and
the same pixels as `deepsea render`."""

import threading

import numpy as np
import pytest

import deepsea
from conftest import CAMERA, cli, tilted_plane

LAYERS = {"final": 3, "direct": 3, "forward": 3, "backscatter": 3, "transmission": 3,
          "depth": 1, "normal": 3}


def srgb_to_linear(codes, top):
    v = codes.astype(np.float64) / top
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def test_layers(asset, frame):
    rgb, depth = frame
    out = deepsea.Renderer(asset).render(rgb, depth)
    assert set(out) == set(LAYERS)
    for name, c in LAYERS.items():
        a = out[name]
        assert a.dtype == np.float32 and a.flags.c_contiguous and a.flags.writeable
        assert a.shape == ((48, 64) if c == 1 else (48, 64, c)), name
        assert np.isfinite(a).all(), name
    np.testing.assert_allclose(out["final"], out["direct"] + out["forward"] + out["backscatter"],
                               rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(out["depth"], depth, rtol=1e-6)
    assert (out["direct"] > 0).any() and (out["backscatter"] > 0).all()
    # zero copy: each array owns no data; a capsule holding the layer's pixels does
    assert not out["final"].flags.owndata and out["final"].base is not None


def test_final_only(asset, frame):
    out = deepsea.render(asset, *frame, layers="final")
    full = deepsea.render(asset, *frame)
    assert "final" in out and "backscatter" not in out
    np.testing.assert_array_equal(out["final"], full["final"])


def test_same_pixels_as_the_cli(asset_path, asset, frame, work):
    oiio = pytest.importorskip("OpenImageIO")
    rgb, depth = frame
    lin = srgb_to_linear(rgb, 255)
    h, w = depth.shape
    # Linear colour as PFM (rows bottom first), depth as .npy: formats the CLI reads exactly.
    with open(work / "cli_rgb.pfm", "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(lin[::-1]).astype("<f4").tobytes())
    np.save(work / "cli_depth.npy", depth)
    cli("render", "--asset", asset_path, "--rgb", work / "cli_rgb.pfm", "--depth",
        work / "cli_depth.npy", "--layers", work / "cli_layers.exr")
    inp = oiio.ImageInput.open(str(work / "cli_layers.exr"))
    names = list(inp.spec().channelnames)
    pixels = inp.read_image("float")
    inp.close()
    out = deepsea.Renderer(asset).render(rgb, depth)
    for layer in ("final", "direct", "forward", "backscatter", "transmission", "normal"):
        idx = [i for i, n in enumerate(names) if n.startswith(layer + ".")]
        assert len(idx) == 3, (layer, names)
        np.testing.assert_allclose(out[layer], pixels[..., idx], rtol=1e-6, atol=1e-9,
                                   err_msg=layer)


def test_dtypes_agree(asset, frame):
    rgb, depth = frame
    r = deepsea.Renderer(asset)
    ref = r.render(rgb, depth)["final"]
    lin = srgb_to_linear(rgb, 255)
    for colour in (lin, lin.astype(np.float64)):
        np.testing.assert_allclose(r.render(colour, depth, encoding="linear")["final"], ref,
                                   rtol=2e-5)
    np.testing.assert_allclose(r.render(rgb.astype(np.uint16) * 257, depth)["final"], ref,
                               rtol=2e-5)
    # sRGB values as floats (a PNG read as float by another reader): the same curve
    for colour in (rgb.astype(np.float32) / 255, rgb / 255.0):
        np.testing.assert_allclose(r.render(colour, depth, encoding="srgb")["final"], ref,
                                   rtol=2e-5)
    # integer codes taken as linear (encoding="linear"): code / top, as a float array of those
    np.testing.assert_allclose(r.render(rgb, depth, encoding="linear")["final"],
                               r.render(rgb / 255.0, depth, encoding="linear")["final"],
                               rtol=2e-5)
    np.testing.assert_allclose(r.render(rgb, depth.astype(np.float64))["final"], ref, rtol=1e-6)
    mm = np.round(depth * 1000).astype(np.uint16)
    np.testing.assert_allclose(r.render(rgb, mm)["final"],
                               r.render(rgb, mm.astype(np.float32) / 1000)["final"], rtol=1e-6)
    cm = np.round(depth * 100).astype(np.uint16)
    np.testing.assert_allclose(r.render(rgb, cm, depth_scale=0.01)["final"],
                               r.render(rgb, cm.astype(np.float32) / 100)["final"], rtol=1e-6)
    # grey and RGBA: as the CLI reads such files (grey expanded, alpha dropped)
    rgba = np.concatenate([rgb, np.full(rgb.shape[:2] + (1,), 7, np.uint8)], axis=2)
    np.testing.assert_array_equal(r.render(rgba, depth)["final"], ref)
    grey = rgb[..., 1]
    np.testing.assert_array_equal(r.render(grey, depth)["final"],
                                  r.render(np.repeat(grey[..., None], 3, axis=2), depth)["final"])
    # (H, W, 1) depth, and strided views (numpy makes them contiguous)
    np.testing.assert_array_equal(r.render(rgb, depth[..., None])["final"], ref)
    big_rgb = np.zeros((96, 128, 3), np.uint8)
    big_rgb[::2, ::2] = rgb
    big_d = np.zeros((96, 128), np.float32)
    big_d[::2, ::2] = depth
    np.testing.assert_array_equal(r.render(big_rgb[::2, ::2], big_d[::2, ::2])["final"], ref)
    np.testing.assert_array_equal(
        r.render(np.asfortranarray(rgb), np.asfortranarray(depth))["final"], ref)
    np.testing.assert_array_equal(
        r.render(rgb[:, ::-1].copy()[:, ::-1], depth[:, ::-1].copy()[:, ::-1])["final"], ref)


def test_range_depth(asset, frame):
    rgb, depth = frame
    v, u = np.mgrid[0:48, 0:64]
    ray = np.sqrt(((u - CAMERA["cx"]) / CAMERA["fx"]) ** 2 +
                  ((v - CAMERA["cy"]) / CAMERA["fy"]) ** 2 + 1.0)
    rng = (depth * ray).astype(np.float32)
    r = deepsea.Renderer(asset)
    z = r.render(rgb, depth)
    along = r.render(rgb, rng, depth_kind="range")
    np.testing.assert_allclose(along["depth"], z["depth"], rtol=1e-5)
    np.testing.assert_allclose(along["final"], z["final"], rtol=1e-3, atol=1e-7)


def test_open_water(asset, frame):
    rgb, depth = frame
    odd = depth.copy()
    odd[:8, :8] = np.nan
    odd[:8, 8:16] = np.inf
    odd[8:16, :8] = -1.0
    odd[8:16, 8:16] = 0.0
    odd[16:24, :8] = 1e10
    out = deepsea.render(asset, rgb, odd)
    water = ~(odd > 0) | ~np.isfinite(odd) | (odd >= 1e6)
    assert water.sum() == 5 * 64
    for name in ("depth", "transmission", "direct", "normal"):
        assert (out[name][water] == 0).all(), name
    assert (out["backscatter"][water] > 0).all() and np.isfinite(out["final"]).all()


def test_other_resolution_and_camera(asset, frame):
    rgb, depth = frame
    r = deepsea.Renderer(asset)
    half = r.render(rgb[::2, ::2].copy(), depth[::2, ::2].copy())  # same view, 32x24
    assert half["final"].shape == (24, 32, 3)
    assert r.camera["width"] == 32 and r.camera["fx"] == pytest.approx(24.0)
    # an explicit camera equal to the asset's
    out = deepsea.Renderer(asset, camera=CAMERA).render(rgb, depth)
    np.testing.assert_array_equal(out["final"], r.render(rgb, depth)["final"])


def test_no_forward_and_timing(asset, frame):
    with_fw = deepsea.Renderer(asset)
    without = deepsea.Renderer(asset, forward=False, threads=1)
    a = with_fw.render(*frame)
    b = without.render(*frame)
    assert (b["forward"] == 0).all()
    assert a["final"].shape == b["final"].shape
    t = without.timing
    assert 0 < t["composite_s"] <= t["call_s"]


def test_threads_give_the_same_pixels(asset, frame):
    one = deepsea.Renderer(asset, threads=1).render(*frame)
    two = deepsea.Renderer(asset, threads=2).render(*frame)
    for name in LAYERS:
        np.testing.assert_array_equal(one[name], two[name])


def test_shared_renderer_from_threads(asset, frame):
    """The GIL is released while rendering; a renderer renders one frame at a time, so Python
    threads may share it."""
    r = deepsea.Renderer(asset)
    want = r.render(*frame)["final"]
    results, errors = [], []

    def work():
        try:
            for _ in range(10):
                results.append(r.render(*frame)["final"])
        except Exception as e:  # pragma: no cover
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(results) == 40
    for got in results:
        np.testing.assert_array_equal(got, want)


def test_exposure_factor(asset, frame):
    final = deepsea.render(asset, *frame)["final"]
    f = deepsea.exposure_factor(final)
    assert f > 0 and np.isfinite(f)
    assert deepsea.exposure_factor(final, 2.5) == 2.5
    with pytest.raises(deepsea.ConfigError):
        deepsea.exposure_factor(final, "bright")


def test_reference_close_to_the_asset(asset, frame):
    rgb, depth = frame
    setup = {"camera": CAMERA, "rig": asset.bake_info["rig"]}
    ref = deepsea.reference(setup, rgb, depth, water="jerlov:IB", rel_tol=1e-4, threads=2)
    fast = deepsea.Renderer(asset, forward=False).render(rgb, depth)
    assert set(ref) == set(LAYERS)
    np.testing.assert_allclose(ref["direct"], fast["direct"], rtol=1e-3, atol=1e-9)
    rel = np.abs(ref["backscatter"] - fast["backscatter"]) / ref["backscatter"]
    assert rel.mean() < 0.02, rel.mean()


def test_buffers_are_reused_and_kept_arrays_stay(asset, frame):
    rgb, depth = frame
    r = deepsea.Renderer(asset)
    first = r.render(rgb, depth)
    kept = first["final"].copy()
    address = first["final"].__array_interface__["data"][0]
    del first  # its buffers return to the renderer
    second = r.render(rgb, depth)
    addresses = {a.__array_interface__["data"][0] for a in second.values()}
    assert address in addresses
    # arrays still held are never written by later frames
    held = r.render(rgb, depth)
    before = held["final"].copy()
    r.render(rgb[:, ::-1].copy(), depth[:, ::-1].copy())
    np.testing.assert_array_equal(held["final"], before)
    np.testing.assert_array_equal(second["final"], kept)
