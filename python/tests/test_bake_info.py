"""Bakes from YAML text, files and dicts; info as `deepsea info --json` gives it."""

import json
import threading
import time

import numpy as np
import pytest

import deepsea
from conftest import CAMERA, RIG, cli, tilted_plane

BAKE = dict(xy_step=8, depth_samples=16, check=False)


def test_info_is_the_clis(asset_path):
    got = deepsea.info(asset_path)
    want = json.loads(cli("info", "--json", asset_path).stdout)
    assert got == want
    assert got["bake"]["camera"] == CAMERA


def test_asset_properties(asset, asset_path, work):
    assert asset.path == asset_path
    assert asset.camera == CAMERA
    assert asset.bake_info == deepsea.info(asset_path)["bake"]
    assert "64x48" in repr(asset)
    again = work / "saved.vdb"  # paths may be os.PathLike
    asset.save(again, preview=False)
    loaded = deepsea.load_asset(again)
    assert loaded.path == str(again)
    assert deepsea.info(again)["bake"] == asset.bake_info
    with pytest.raises(TypeError):
        deepsea.load_asset(42)
    frame = tilted_plane()
    np.testing.assert_array_equal(deepsea.render(asset, *frame)["final"],
                                  deepsea.render(loaded, *frame)["final"])


def test_setup_forms_bake_the_same(asset, work):
    yaml_text = ("camera:\n" + "".join(f"  {k}: {v}\n" for k, v in CAMERA.items()) +
                 open(RIG).read() + "water:\n  preset: jerlov:IB\n")
    (work / "setup.yaml").write_text(yaml_text)
    want = asset.bake_info["input_hash"]
    forms = [
        yaml_text,
        str(work / "setup.yaml"),
        work / "setup.yaml",  # os.PathLike
        {"camera": CAMERA, "rig": asset.bake_info["rig"], "water": {"preset": "jerlov:IB"}},
        [{"camera": {k: np.asarray(v)[()] for k, v in CAMERA.items()}}, RIG],  # numpy scalars
    ]
    for form in forms:
        kw = {} if not isinstance(form, list) else {"water": "jerlov:IB"}
        a = deepsea.bake(form, **kw, **BAKE)
        assert a.bake_info["input_hash"] == want, form
        assert a.path is None
    written = deepsea.bake(forms[0], output=work / "from_text.vdb", **BAKE)
    assert written.path == str(work / "from_text.vdb")
    assert deepsea.load_asset(written.path).bake_info["input_hash"] == want
    # the same inputs as `deepsea bake` on the command line
    cli("bake", "--config", work / "setup.yaml", "--xy-step", 8, "--depth-samples", 16,
        "--no-check", "-o", work / "cli.vdb")
    assert deepsea.info(str(work / "cli.vdb"))["bake"]["input_hash"] == want


def test_bake_releases_the_gil():
    """Another Python thread runs while a bake computes."""
    ticks = 0
    done = threading.Event()

    def bake():
        deepsea.bake(camera=dict(CAMERA, width=128, height=96, fx=96.0, fy=96.0, cx=63.5,
                                 cy=47.5), rig=RIG, water="jerlov:IB", xy_step=4,
                     depth_samples=32, check=False, threads=1)
        done.set()

    t = threading.Thread(target=bake)
    start = time.perf_counter()
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    if elapsed < 0.05:
        pytest.skip(f"the bake took {elapsed:.3f} s: too quick to tell")
    assert ticks > 10, (ticks, elapsed)


def test_bake_through_a_port_records_it_and_renders_only_through_it():
    # docs/port-bake.md, "Baking through a port": the columns follow the water-side rays, the asset
    # records the port, and a renderer without it (or with another) is refused in one line.
    port = {"flat": {"normal": [0, 0, 1], "distance": 0.03, "glass_thickness": 0.012}}
    camera = dict(CAMERA, port=port)
    asset = deepsea.bake(camera=camera, rig=RIG, water="jerlov:IB", xy_step=8, depth_samples=16)
    info = asset.bake_info
    assert info["port"]["flat"]["distance"] == 0.03
    assert info["port"]["flat"]["n_water"] == [1.34, 1.34, 1.34]
    rgb, depth = tilted_plane()
    out = deepsea.Renderer(asset, camera=camera).render(rgb, depth)
    assert out["backscatter"].min() > 0 and "mask" in out
    with pytest.raises(deepsea.AssetError, match="baked through a flat port .* has no port"):
        deepsea.Renderer(asset)
    other = dict(CAMERA, port={"dome": {"centre": [0, 0, 0], "radius": 0.05,
                                        "glass_thickness": 0.01}})
    with pytest.raises(deepsea.AssetError, match="looks through a dome port"):
        deepsea.Renderer(asset, camera=other)
