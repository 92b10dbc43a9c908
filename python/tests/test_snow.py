"""Marine snow through the module (docs/snow-shadows.md, "Marine snow"): Renderer(snow=...) adds the
snow and snow_id layers and the snow's light to final; frame_key and pose place the particles
(fixed in the world with a pose); bad values are one-line ConfigErrors."""

import pickle

import numpy as np
import pytest

import deepsea

from conftest import tilted_plane


def pose(x=0.0):
    """Camera to world: the camera at (x, 0, 0), axes as the world's."""
    m = np.eye(4)
    m[0, 3] = x
    return m


def test_snow_layers_and_final(asset):
    rgb, depth = tilted_plane(z0=6.0)
    plain = deepsea.Renderer(asset).render(rgb, depth)
    out = deepsea.Renderer(asset, snow="plume", snow_seed=3).render(rgb, depth, frame_key=5)
    assert "snow" not in plain and "snow_id" not in plain
    assert out["snow"].shape == rgb.shape and out["snow_id"].shape == depth.shape
    assert out["snow"].sum() > 0
    ids = out["snow_id"]
    assert np.array_equal(ids, np.round(ids)) and ids.max() >= 1
    assert np.array_equal(ids > 0, out["snow"].sum(axis=2) > 0)
    # final = the frame without snow + the snow layer, to float rounding
    np.testing.assert_allclose(out["final"], plain["final"] + out["snow"], rtol=1e-5, atol=1e-9)


def test_frame_key_pose_and_seed(asset):
    rgb, depth = tilted_plane(z0=6.0)
    r = deepsea.Renderer(asset, snow={"preset": "plume", "albedo": 0.3})
    a = r.render(rgb, depth, frame_key=1, layers="snow")["snow"]
    assert np.array_equal(a, r.render(rgb, depth, frame_key=1, layers="snow")["snow"])
    assert not np.array_equal(a, r.render(rgb, depth, frame_key=2, layers="snow")["snow"])
    assert np.array_equal(r.render(rgb, depth, frame_key="f_0001", layers="snow")["snow"],
                          r.render(rgb, depth, frame_key="f_0001", layers="snow")["snow"])
    # With a pose the particles are the world's: the frame key does not matter, the pose does.
    p1 = r.render(rgb, depth, frame_key=1, pose=pose(), layers="snow")["snow"]
    p2 = r.render(rgb, depth, frame_key=2, pose=pose(), layers="snow")["snow"]
    assert np.array_equal(p1, p2)
    moved = r.render(rgb, depth, frame_key=1, pose=pose(0.3), layers="snow")["snow"]
    assert not np.array_equal(p1, moved)
    other_seed = deepsea.Renderer(asset, snow={"preset": "plume", "albedo": 0.3}, snow_seed=2)
    assert not np.array_equal(p1, other_seed.render(rgb, depth, pose=pose(), layers="snow")["snow"])
    # off, and pickling keeps the snow
    assert "snow" not in deepsea.Renderer(asset, snow="off").render(rgb, depth)
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.render(rgb, depth, frame_key=1, layers="snow")["snow"], a)


@pytest.mark.parametrize("snow, words", [
    ("blizzard", "blizzard"),
    ({"preset": "plume", "albedo": 1.5}, "snow.albedo"),
    ({"albedo": 0.5}, "snow.concentration"),
    (3, "snow"),
])
def test_bad_snow(asset, snow, words):
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.Renderer(asset, snow=snow)
    assert words in str(e.value) and "\n" not in str(e.value)


@pytest.mark.parametrize("bad, words", [
    (np.eye(3), "4x4 or 3x4"),
    (np.diag([1.0, 1.0, 2.0, 1.0]), "rotation"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), "reflection"),
    ("up", "4x4 or 3x4"),
])
def test_bad_pose(asset, bad, words):
    rgb, depth = tilted_plane()
    r = deepsea.Renderer(asset, snow="abyssal")
    with pytest.raises(deepsea.ConfigError) as e:
        r.render(rgb, depth, pose=bad)
    assert words in str(e.value) and e.value.args[0].startswith("pose:")


def test_motion_streaks(asset):
    """shutter=(open, close) with the snow's streaks on: the particles drawn as streaks, their
    light kept (the snow layer's sum as the still one's, apart from light at the image's edges);
    off without the switch or a pose; a bad shutter names it."""
    rgb, depth = tilted_plane(z0=6.0)
    snow = {"preset": "abyssal", "streaks": True}
    r = deepsea.Renderer(asset, snow=snow)
    shutter = (pose(-0.02), pose(0.02))  # 4 cm sideways while the shutter is open
    still = r.render(rgb, depth, pose=pose(), layers="snow")["snow"]
    streaks = r.render(rgb, depth, pose=pose(), shutter=shutter, layers="snow")["snow"]
    assert not np.array_equal(still, streaks)
    assert (streaks > 0).sum() > (still > 0).sum()  # spread over more pixels
    np.testing.assert_allclose(streaks.sum(), still.sum(), rtol=0.05)
    # off: streaks not switched on, or no pose
    off = deepsea.Renderer(asset, snow="abyssal")
    assert np.array_equal(off.render(rgb, depth, pose=pose(), shutter=shutter, layers="snow")["snow"],
                          still)
    assert np.array_equal(r.render(rgb, depth, frame_key=4, shutter=shutter, layers="snow")["snow"],
                          r.render(rgb, depth, frame_key=4, layers="snow")["snow"])
    for bad in ((pose(),), "up", (pose(), np.eye(3))):
        with pytest.raises(deepsea.ConfigError) as e:
            r.render(rgb, depth, pose=pose(), shutter=bad)
        assert e.value.args[0].startswith("shutter:") and "\n" not in str(e.value)
