"""Renderers in worker processes: a Renderer used in the parent renders in a forked child, an
Asset and a Renderer pickle (spawn), and docs/python.md's dataset gives `deepsea render`'s
frames pixel for pixel with two workers under fork and under spawn."""

import multiprocessing
import os
import pickle
import re
import sys

import numpy as np
import pytest

import deepsea
from conftest import CAMERA, SRC, cli

WAIT_S = 120  # a hung child (a thread pool broken by fork) fails the test instead of CTest's


def render_in_child(renderer, rgb, depth, queue):
    queue.put(renderer.render(rgb, depth)["final"])


def test_renderer_survives_fork(asset, frame):
    r = deepsea.Renderer(asset, threads=2)
    mine = r.render(*frame)["final"]  # the parent's thread pool has run
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=render_in_child, args=(r, *frame, queue))
    child.start()
    theirs = queue.get(timeout=WAIT_S)
    child.join(WAIT_S)
    assert child.exitcode == 0
    np.testing.assert_array_equal(theirs, mine)


def test_pickles(asset, asset_path, frame):
    r = deepsea.Renderer(asset, camera=CAMERA, forward=False, threads=1)
    again = pickle.loads(pickle.dumps(r))
    assert type(again) is deepsea.Renderer and again.asset.path == asset_path
    np.testing.assert_array_equal(again.render(*frame)["final"], r.render(*frame)["final"])
    assert pickle.loads(pickle.dumps(asset)).camera == asset.camera
    baked = deepsea.bake(camera=CAMERA, rig=os.path.join(SRC, "volumes", "rigs",
                                                         "authors-testset.yaml"),
                         water="jerlov:IB", xy_step=16, depth_samples=8, check=False)
    with pytest.raises(deepsea.InputError, match="baked in memory.*save"):
        pickle.dumps(baked)


@pytest.fixture(scope="module")
def dataset_module(tmp_path_factory):
    """docs/python.md's deepsea_frames.py, written where workers import it."""
    text = open(os.path.join(SRC, "docs", "python.md")).read()
    blocks = [b for b in re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
              if b.startswith("# deepsea_frames.py\n")]
    assert len(blocks) == 1
    folder = tmp_path_factory.mktemp("dataset")
    (folder / "deepsea_frames.py").write_text(blocks[0])
    sys.path.insert(0, str(folder))
    yield folder
    sys.path.remove(str(folder))


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_dataset_workers_match_the_cli(dataset_module, asset_path, work, method):
    from deepsea_frames import DeepSeaFrames

    frames_dir = work / "dataset_frames"
    if not frames_dir.exists():
        camera = work / "dataset_camera.yaml"
        camera.write_text("camera:\n" + "".join(f"  {k}: {v}\n" for k, v in CAMERA.items()))
        cli("scene", "--out", frames_dir, "--frames", 4, "--camera", camera)
    frames = DeepSeaFrames(str(frames_dir), asset_path, layers=("final", "depth"), threads=1)
    with multiprocessing.get_context(method).Pool(2) as pool:
        items = pool.map_async(frames.__getitem__, range(len(frames))).get(WAIT_S)
    assert len(items) == 4
    out = work / f"dataset_cli_{method}"
    exposure = "%.17g" % frames.exposure
    cli("render", "--asset", asset_path, "--rgb", str(frames_dir / "frame_*[0-9].png"),
        "--depth", str(frames_dir / "frame_*_depth.exr"), "-o", out / "images",
        "--layers", out / "layers", "--layer-set", "final,depth", "--exposure", exposure)
    zeros = work / "dataset_zeros.npy"
    np.save(zeros, np.zeros((CAMERA["height"], CAMERA["width"]), np.float32))
    for path, item in zip(frames.rgb, items):
        stem = os.path.splitext(os.path.basename(path))[0]
        layer_file = out / "layers" / f"{stem}.exr"
        for k, channel in enumerate("RGB"):  # the CLI's layers, read a channel at a time
            cli_final = deepsea.read_frame(path, layer_file, depth_channel=f"final.{channel}")
            np.testing.assert_array_equal(item["final"][..., k], cli_final["depth"], err_msg=stem)
        cli_depth = deepsea.read_frame(path, layer_file, depth_channel="depth.Z")["depth"]
        np.testing.assert_array_equal(item["depth"], cli_depth, err_msg=stem)
        # The exposed image as -o writes it: the same 8-bit codes.
        mine = work / f"dataset_{method}_{stem}.png"
        deepsea.write_image(mine, item["final"], encoding="linear", exposure=frames.exposure)
        np.testing.assert_array_equal(deepsea.read_frame(mine, zeros)["rgb"],
                                      deepsea.read_frame(out / "images" / f"{stem}.png",
                                                         zeros)["rgb"], err_msg=stem)
        assert item["final"].std() > 0 and item["depth"].max() > 0
