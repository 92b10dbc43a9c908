"""Shared fixtures: a small asset baked once per session (64x48 camera, coarse lattice, no
check: about a second), small RGB-D frames made with numpy, and the deepsea CLI."""

import os
import subprocess

import numpy as np
import pytest

import deepsea

SRC = os.environ.get("DEEPSEA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.environ.get("DEEPSEA_CLI", "")
RIG = os.path.join(SRC, "volumes", "rigs", "authors-testset.yaml")
CAMERA = {"width": 64, "height": 48, "fx": 48.0, "fy": 48.0, "cx": 31.5, "cy": 23.5}


def cli(*args, check=True):
    """Runs the deepsea command; returns the CompletedProcess (text)."""
    if not CLI:
        pytest.skip("DEEPSEA_CLI is not set")
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, check=check)


def cli_error(*args):
    """The one-line message of a failing command, without the "deepsea: error: " prefix."""
    r = cli(*args, check=False)
    assert r.returncode != 0, r.stdout
    line = r.stderr.strip().splitlines()[-1]
    assert line.startswith("deepsea: error: "), line
    return line[len("deepsea: error: "):]


@pytest.fixture(scope="session")
def work(tmp_path_factory):
    return tmp_path_factory.mktemp("deepsea")


@pytest.fixture(scope="session")
def asset_path(work):
    path = str(work / "small.vdb")
    deepsea.bake(camera=CAMERA, rig=RIG, water="jerlov:IB", xy_step=8, depth_samples=16,
                 check=False, output=path)
    return path


@pytest.fixture(scope="session")
def asset(asset_path):
    return deepsea.load_asset(asset_path)


def tilted_plane(camera=CAMERA, z0=3.0, a=0.3):
    """(rgb uint8 (H, W, 3), planar depth float32 (H, W)): a tilted plane, a checker albedo."""
    h, w = camera["height"], camera["width"]
    v, u = np.mgrid[0:h, 0:w]
    x = (u - camera["cx"]) / camera["fx"]
    depth = (z0 / (1.0 - a * x)).astype(np.float32)
    rgb = np.zeros((h, w, 3), np.uint8)
    rgb[..., 0] = np.where((u // 8 + v // 8) % 2, 200, 60)
    rgb[..., 1] = 120
    rgb[..., 2] = (40 + 2 * u).astype(np.uint8)
    return rgb, depth


@pytest.fixture
def frame():
    return tilted_plane()
