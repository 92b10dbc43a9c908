"""Files as the CLI reads and writes them: read_frame's arrays render as `deepsea render`
renders the files (PNG codes, 16-bit PNG depth with a scale, EXR colour, TIFF through the
OpenImageIO module), write_image writes -o's codes, write_layers --layers' channels, and
layers= takes --layer-set's names and returns those only."""

import os

import numpy as np
import pytest

import deepsea
from conftest import CAMERA, cli, tilted_plane

H, W = CAMERA["height"], CAMERA["width"]


@pytest.fixture(scope="module")
def frames(work):
    folder = work / "files_frames"
    if not folder.exists():
        camera = work / "files_camera.yaml"
        camera.write_text("camera:\n" + "".join(f"  {k}: {v}\n" for k, v in CAMERA.items()))
        cli("scene", "--out", folder, "--frames", 1, "--camera", camera)
    rgb = sorted(p for p in os.listdir(folder) if p.endswith(".png"))[0]
    return folder / rgb, folder / (rgb[: -len(".png")] + "_depth.exr")


def cli_layers(asset_path, rgb, depth, out, *extra):
    cli("render", "--asset", asset_path, "--rgb", rgb, "--depth", depth, "--layers", out, *extra)
    return {name: np.stack([deepsea.read_frame(rgb, out, depth_channel=f"{name}.{c}")["depth"]
                            for c in "RGB"], axis=2) for name in ("final", "backscatter")}


def test_read_frame_renders_as_the_cli(asset_path, asset, frames, work):
    rgb, depth = frames
    frame = deepsea.read_frame(rgb, depth)
    assert frame["encoding"] == "srgb" and frame["rgb"].dtype == np.uint8
    assert frame["rgb"].shape == (H, W, 3) and frame["depth"].shape == (H, W)
    out = deepsea.Renderer(asset).render(**frame)
    cli_out = cli_layers(asset_path, rgb, depth, work / "files_cli.exr")
    for name, layer in cli_out.items():
        np.testing.assert_array_equal(out[name], layer, err_msg=name)
    # EXR colour (linear floats) and TIFF colour (OpenImageIO's module), 16-bit PNG depth in mm
    linear = out["final"] / out["final"].max()
    for ext in ("exr", "tif"):
        path = work / f"files_colour.{ext}"
        deepsea.write_image(path, linear, encoding="linear")
        mm = work / "files_depth_mm.png"
        deepsea.write_image(mm, np.repeat((frame["depth"] * 1000).astype(np.uint16)[..., None],
                                          3, axis=2))
        f = deepsea.read_frame(path, depth)
        assert f["encoding"] == ("linear" if ext == "exr" else "srgb" if f["rgb"].dtype != np.float32
                                 else "linear")
        mine = deepsea.Renderer(asset).render(**f)
        theirs = cli_layers(asset_path, path, depth, work / f"files_cli_{ext}.exr")
        np.testing.assert_array_equal(mine["final"], theirs["final"], err_msg=ext)


def test_read_frame_depth_scale(asset_path, asset, frames, work):
    rgb, depth = frames
    z = deepsea.read_frame(rgb, depth)["depth"]
    cm = np.round(z * 100).astype(np.uint16)
    path = work / "files_depth_cm.npy"
    np.save(path, cm)
    f = deepsea.read_frame(rgb, path, depth_scale=0.01)
    np.testing.assert_allclose(f["depth"], cm * 0.01, rtol=1e-6)
    mine = deepsea.Renderer(asset).render(**f)["final"]
    theirs = cli_layers(asset_path, rgb, path, work / "files_cli_cm.exr", "--depth-scale", 0.01)
    np.testing.assert_array_equal(mine, theirs["final"])


def test_read_frame_errors(frames, work):
    rgb, depth = frames
    with pytest.raises(deepsea.IoError, match="missing.png"):
        deepsea.read_frame(work / "missing.png", depth)
    small = work / "files_small.npy"
    np.save(small, np.ones((4, 4), np.float32))
    with pytest.raises(deepsea.InputError, match="sizes differ"):
        deepsea.read_frame(rgb, small)


def test_write_image_as_the_cli(asset_path, asset, frames, work):
    rgb, depth = frames
    out = deepsea.Renderer(asset).render(**deepsea.read_frame(rgb, depth), layers="final")
    zeros = work / "files_zeros.npy"
    np.save(zeros, np.zeros((H, W), np.float32))
    for ext, bits in (("png", 8), ("png", 16), ("jpg", 8)):
        theirs = work / f"files_cli_{bits}.{ext}"
        cli("render", "--asset", asset_path, "--rgb", rgb, "--depth", depth, "-o", theirs,
            "--exposure", 2.5, "--bits", bits)
        mine = work / f"files_mine_{bits}.{ext}"
        deepsea.write_image(mine, out["final"], encoding="linear", exposure=2.5, bits=bits)
        a, b = (deepsea.read_frame(p, zeros)["rgb"] for p in (mine, theirs))
        assert a.dtype == (np.uint16 if bits == 16 else np.uint8)
        np.testing.assert_array_equal(a, b, err_msg=f"{ext} {bits}")
        assert a.std() > 0
    # codes written as they are, and encoded floats as codes
    codes = tilted_plane()[0]
    deepsea.write_image(work / "files_codes.png", codes)
    np.testing.assert_array_equal(deepsea.read_frame(work / "files_codes.png", zeros)["rgb"], codes)
    deepsea.write_image(work / "files_enc.png", codes / 255.0, encoding="srgb")
    np.testing.assert_array_equal(deepsea.read_frame(work / "files_enc.png", zeros)["rgb"], codes)
    with pytest.raises(deepsea.InputError, match="image: float32 colour needs its encoding"):
        deepsea.write_image(work / "x.png", out["final"])
    with pytest.raises(deepsea.IoError):
        deepsea.write_image(work / "no" / "x.png", codes)
    assert not (work / "x.png").exists()


def test_layers_as_the_cli(asset_path, asset, frames, work):
    rgb, depth = frames
    frame = deepsea.read_frame(rgb, depth)
    r = deepsea.Renderer(asset)
    full = r.render(**frame)
    for spec in ("final", "final,depth", ["backscatter", "normal"], "all", "depth,all"):
        out = r.render(**frame, layers=spec)
        names = spec if isinstance(spec, list) else spec.split(",")
        expected = set(full) if "all" in names else set(names)
        assert set(out) == expected, spec
        for name in out:
            np.testing.assert_array_equal(out[name], full[name], err_msg=f"{spec} {name}")
    # write_layers writes what --layers --layer-set writes
    out = r.render(**frame, layers="final,backscatter")
    mine = work / "files_mine_layers.exr"
    deepsea.write_layers(mine, out)
    theirs = work / "files_cli_layers.exr"
    cli("render", "--asset", asset_path, "--rgb", rgb, "--depth", depth, "--layers", theirs,
        "--layer-set", "final,backscatter")
    for name in ("final", "backscatter"):
        for c in "RGB":
            a, b = (deepsea.read_frame(rgb, p, depth_channel=f"{name}.{c}")["depth"]
                    for p in (mine, theirs))
            np.testing.assert_array_equal(a, b, err_msg=name + c)
    with pytest.raises(deepsea.InputError):
        deepsea.read_frame(rgb, mine, depth_channel="depth.Z")
