"""Bad input gives a clear exception (a deepsea.Error subclass with the CLI's one-line
message), never a crash."""

import numpy as np
import pytest

import deepsea
from conftest import CAMERA, RIG, cli_error, tilted_plane


def test_exception_types():
    assert issubclass(deepsea.ConfigError, deepsea.Error)
    assert issubclass(deepsea.ConfigError, ValueError)
    assert issubclass(deepsea.InputError, ValueError)
    assert issubclass(deepsea.AssetError, ValueError)
    assert issubclass(deepsea.IoError, OSError)
    assert issubclass(deepsea.AccuracyError, RuntimeError)
    assert issubclass(deepsea.Error, Exception)


@pytest.mark.parametrize("rgb, message", [
    (np.zeros((48, 64, 3), np.int32), "rgb: dtype int32 is not supported"),
    (np.zeros((48, 64, 3), np.bool_), "rgb: dtype bool is not supported"),
    (np.zeros((48, 64, 3), np.float16), "rgb: dtype float16 is not supported"),
    (np.zeros((48, 64, 3), ">f4"), "rgb: dtype >f4 is not supported"),
    (np.zeros((48, 64, 2), np.uint8), "rgb: shape (48, 64, 2) is not an image"),
    (np.zeros((64 * 48 * 3,), np.uint8), "rgb: shape (9216,) is not an image"),
    (np.zeros((1, 48, 64, 3), np.uint8), "rgb: shape (1, 48, 64, 3) is not an image"),
    (np.zeros((0, 64, 3), np.uint8), "rgb: "),
    (np.zeros((24, 32, 3), np.uint8), "rgb and depth"),
    ([[1, 2], [3, 4]], "rgb: dtype int64 is not supported"),
])
def test_bad_colour(asset, frame, rgb, message):
    with pytest.raises(deepsea.InputError) as e:
        deepsea.Renderer(asset).render(rgb, frame[1])
    assert str(e.value).startswith(message), str(e.value)


@pytest.mark.parametrize("depth, message", [
    (np.zeros((48, 64), np.uint8), "depth: dtype uint8 is not supported"),
    (np.zeros((48, 64), np.int16), "depth: dtype int16 is not supported"),
    (np.zeros((48, 64), np.complex64), "depth: dtype complex64 is not supported"),
    (np.zeros((48, 64, 3), np.float32), "depth: shape (48, 64, 3) is not an image"),
    (np.zeros((48, 65), np.float32), "rgb and depth"),
])
def test_bad_depth(asset, frame, depth, message):
    with pytest.raises(deepsea.InputError) as e:
        deepsea.Renderer(asset).render(frame[0], depth)
    assert str(e.value).startswith(message), str(e.value)


def test_bad_options(asset, frame):
    with pytest.raises(deepsea.ConfigError, match="depth_kind"):
        deepsea.render(asset, *frame, depth_kind="planar")
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.render(asset, *frame, layers="some")
    assert str(e.value).startswith("layers: unknown layer 'some' (layers: final, direct"), e.value
    with pytest.raises(deepsea.ConfigError, match="layers: layer 'depth' named twice"):
        deepsea.render(asset, *frame, layers=["depth", "final", "depth"])
    with pytest.raises(deepsea.ConfigError, match="depth_scale"):
        deepsea.render(asset, *frame, depth_scale=0.0)
    with pytest.raises(deepsea.ConfigError, match="threads"):
        deepsea.Renderer(asset, threads=-1)
    with pytest.raises(TypeError):
        deepsea.Renderer(asset).render(frame[0])


def test_asset_for_another_camera(asset_path, asset, frame, work):
    rgb, depth = frame
    # another aspect ratio: cannot be the asset's view resampled
    with pytest.raises(deepsea.AssetError) as e:
        deepsea.render(asset, rgb[:40], depth[:40])
    assert "camera" in str(e.value)
    # another field of view, given explicitly
    other = dict(CAMERA, fx=60.0, fy=60.0)
    with pytest.raises(deepsea.AssetError) as e:
        deepsea.Renderer(asset, camera=other).render(rgb, depth)
    np.save(work / "err_depth.npy", depth[:40])
    with open(work / "err_rgb.pfm", "wb") as f:
        f.write(b"PF\n64 40\n-1.0\n" + np.zeros((40, 64, 3), "<f4").tobytes())
    cli_msg = cli_error("render", "--asset", asset_path, "--rgb", work / "err_rgb.pfm",
                        "--depth", work / "err_depth.npy", "-o", work / "err.png")
    with pytest.raises(deepsea.AssetError) as e:
        deepsea.render(asset, rgb[:40], depth[:40])
    # the CLI's line names the frame's file first, then says the same
    assert cli_msg == str(work / "err_rgb.pfm") + ": " + str(e.value)


def test_missing_and_corrupt_assets(work):
    missing = str(work / "none.vdb")
    with pytest.raises(deepsea.IoError) as e:
        deepsea.load_asset(missing)
    assert isinstance(e.value, OSError)
    assert str(e.value) == cli_error("info", missing)
    bad = work / "bad.vdb"
    bad.write_bytes(b"not a vdb file at all" * 10)
    with pytest.raises(deepsea.AssetError) as e:
        deepsea.load_asset(str(bad))
    assert str(e.value) == cli_error("info", bad)
    with pytest.raises(deepsea.AssetError):
        deepsea.info(str(bad))


def test_bad_setups(work):
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.bake("camera:\n  width: 64\n  hieght: 48\n", rig=RIG, water="jerlov:IB")
    assert str(e.value).startswith("<setup text>:3:"), str(e.value)
    assert "hieght" in str(e.value)
    (work / "typo.yaml").write_text("camera:\n  width: 64\n  hieght: 48\n")
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.bake(str(work / "typo.yaml"), rig=RIG, water="jerlov:IB")
    assert str(e.value) == cli_error("bake", "--camera", work / "typo.yaml", "--rig", RIG,
                                     "--water", "jerlov:IB", "-o", work / "typo.vdb")
    with pytest.raises(deepsea.ConfigError, match="water"):
        deepsea.bake({"camera": CAMERA}, rig=RIG)  # no water
    with pytest.raises(deepsea.ConfigError, match="given twice"):
        deepsea.bake({"camera": CAMERA, "water": {"preset": "jerlov:IB"}}, rig=RIG,
                     water="jerlov:II")
    with pytest.raises(deepsea.ConfigError):
        deepsea.bake(camera=dict(CAMERA, width=-3), rig=RIG, water="jerlov:IB")
    with pytest.raises(deepsea.ConfigError):
        deepsea.bake(camera=CAMERA, rig=RIG, water="jerlov:XX")
    with pytest.raises(deepsea.ConfigError, match="z_max"):
        deepsea.bake(camera=CAMERA, rig=RIG, water="jerlov:IB", z_max="far")
    with pytest.raises(deepsea.ConfigError):
        deepsea.bake(camera=CAMERA, rig=RIG, water="jerlov:IB", depth_scheme="cubic")
    with pytest.raises(deepsea.IoError):
        deepsea.bake(camera=CAMERA, rig=RIG, water="jerlov:IB", output="/nonexistent/a.vdb")
    with pytest.raises(deepsea.IoError):
        deepsea.bake(str(work / "no-such-setup.yaml"))
    with pytest.raises(deepsea.ConfigError, match="setup"):
        deepsea.bake(42)
    with pytest.raises(TypeError):
        deepsea.bake({"camera": dict(CAMERA, fx=object())}, rig=RIG, water="jerlov:IB")


def test_non_finite_colour_names_the_pixel(asset, frame):
    rgb = np.full(frame[0].shape, 0.3, np.float32)
    rgb[5, 7, 1] = np.nan
    with pytest.raises(deepsea.InputError) as e:
        deepsea.Renderer(asset).render(rgb, frame[1], encoding="linear")
    assert str(e.value).startswith("rgb: pixel (7, 5) G is NaN"), str(e.value)
    rgb[5, 7, 1] = 0.3
    rgb[40, 2, 2] = np.inf
    with pytest.raises(deepsea.InputError, match=r"pixel \(2, 40\) B is \+inf"):
        deepsea.render(asset, rgb.astype(np.float64), frame[1], encoding="srgb")


def test_float_colour_needs_its_encoding(asset, frame):
    """sRGB values taken as linear albedo would be silently wrong: float colour must say."""
    rgb = frame[0].astype(np.float32) / 255
    for call in (lambda: deepsea.render(asset, rgb, frame[1]),
                 lambda: deepsea.Renderer(asset).render(rgb.astype(np.float64), frame[1]),
                 lambda: deepsea.reference({"camera": asset.camera}, rgb, frame[1], rig=RIG,
                                           water="jerlov:IB")):
        with pytest.raises(deepsea.InputError) as e:
            call()
        message = str(e.value)
        assert message.startswith("rgb: float") and "encoding='srgb'" in message, message
        assert "\n" not in message
    with pytest.raises(deepsea.ConfigError, match="encoding: expected 'srgb' or 'linear'"):
        deepsea.render(asset, rgb, frame[1], encoding="sRGB")
    # the two encodings give two frames (the rule is not a formality)
    a = deepsea.render(asset, rgb, frame[1], encoding="srgb", layers="final")["final"]
    b = deepsea.render(asset, rgb, frame[1], encoding="linear", layers="final")["final"]
    assert (b > a).mean() > 0.9


def test_paths_with_nul_and_thread_counts_beyond_the_limit(asset, work):
    with pytest.raises(deepsea.ConfigError, match="NUL"):
        deepsea.load_asset(str(work / "a.vdb") + "\0.png")
    with pytest.raises(ValueError):
        deepsea.info("x\0y")
    with pytest.raises(deepsea.ConfigError, match="threads"):
        deepsea.Renderer(asset, threads=1025)
    with pytest.raises(deepsea.ConfigError, match="threads"):
        deepsea.load_asset(str(work / "a.vdb"), threads=10**6)


def test_out_of_memory_is_a_deepsea_error(asset_path, work):
    # A child process with its address space capped just above what it holds: the render's
    # allocations fail, and the error is deepsea.OutOfMemoryError (a MemoryError), not a bare
    # MemoryError from std::bad_alloc.
    import subprocess, sys, textwrap
    code = textwrap.dedent(f"""
        import resource, numpy as np, deepsea
        asset = deepsea.load_asset({str(asset_path)!r})
        rgb = np.zeros((3000, 4000, 3), np.uint8)
        depth = np.full((3000, 4000), 3.0, np.float32)
        vm = [int(l.split()[1]) for l in open('/proc/self/status') if l.startswith('VmSize')][0]
        limit = vm * 1024 + (200 << 20)
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        try:
            deepsea.Renderer(asset, threads=1).render(rgb, depth)
        except deepsea.OutOfMemoryError as e:
            assert isinstance(e, MemoryError) and isinstance(e, deepsea.Error)
            print("OOM:", e)
        """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("OOM: out of memory"), out.stdout + out.stderr
