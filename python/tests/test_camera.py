"""deepsea.Camera: the camera stage from Python. Deterministic per frame key, the same codes as
`deepsea render --camera`, the auto-exposure controller, and one-line errors for bad input."""

import pathlib
import threading

import numpy as np
import pytest

import deepsea
from conftest import CAMERA, cli, tilted_plane

# A camera section with a camera stage: a preset's sensor, f/2, grey-world white balance.
STAGE = {"lens": {"f_number": 2.0},
         "sensor": {"preset": "mvbluefox3-2051c", "exposure_time_ms": 20.0, "seed": 7},
         "processing": {"white_balance": "grey_world"}}
CAMERA_LAYERS = ("raw", "linear_dn", "noise_free")


def yaml_map(d, indent):
    """A dict as block YAML (what the test needs: maps, numbers, strings, flat lists)."""
    out = ""
    for k, v in d.items():
        if isinstance(v, dict):
            out += " " * indent + f"{k}:\n" + yaml_map(v, indent + 2)
        else:
            out += " " * indent + f"{k}: {v}\n"
    return out


@pytest.fixture(scope="module")
def camera_yaml(work):
    path = work / "stage_camera.yaml"
    path.write_text("camera:\n" + yaml_map(dict(CAMERA, **STAGE), 2))
    return path


@pytest.fixture(scope="module")
def camera(camera_yaml):
    return deepsea.Camera(str(camera_yaml))


@pytest.fixture(scope="module")
def radiance(asset):
    return deepsea.Renderer(asset).render(*tilted_plane(), layers="final")["final"]


def srgb_to_linear(codes):
    v = codes.astype(np.float64) / 255
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def fnv1a64(text):
    h = 1469598103934665603
    for b in text.encode():
        h = ((h ^ b) * 1099511628211) % 2**64
    return h


def test_record(camera, radiance):
    assert (camera.width, camera.height) == (CAMERA["width"], CAMERA["height"])
    assert camera.intrinsics == CAMERA
    assert camera.settings["sensor"]["full_well"] == 10715.0  # the preset's
    assert camera.settings["lens"]["f_number"] == 2.0
    assert camera.black_level == 64.0 and camera.max_dn == 4095.0
    out = camera.record(radiance, 1)
    assert sorted(out) == ["exposure_time_ms", "frame_key", "image", "system_gain",
                           "white_balance"]
    img = out["image"]
    assert img.shape == radiance.shape and img.dtype == np.float32 and img.flags.writeable
    assert 0.0 <= img.min() and img.max() <= 1.0 and img.std() > 0.01
    assert out["exposure_time_ms"] == 20.0 and out["frame_key"] == 1
    assert out["system_gain"] == pytest.approx((4095 - 64) / 10715.0)  # ISO 100
    assert out["white_balance"][1] == 1.0 and out["white_balance"] != (1.0, 1.0, 1.0)
    full = camera.record(radiance, 1, layers=CAMERA_LAYERS)
    assert sorted(full) == sorted(list(out) + list(CAMERA_LAYERS))
    np.testing.assert_array_equal(full["image"], img)
    raw = full["raw"]
    assert (raw == np.round(raw)).all() and 0 <= raw.min() and raw.max() <= 4095
    assert (np.abs(full["linear_dn"] - raw) <= 0.5 + 1e-3).mean() > 0.99  # below saturation
    # the noise-free image is the mean of the noisy one
    assert abs(float(full["noise_free"].mean() - img.mean())) < 0.01
    assert camera.record(radiance, 1, layers="noise_free").keys() == \
        set(out) | {"noise_free"}


def test_same_key_same_bits_other_key_other_noise(camera, radiance):
    a = camera.record(radiance, 5, layers=CAMERA_LAYERS)
    b = camera.record(radiance, 5, layers=CAMERA_LAYERS)
    c = camera.record(radiance, 6, layers=CAMERA_LAYERS)
    for name in ("image",) + CAMERA_LAYERS:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    assert (a["raw"] != c["raw"]).mean() > 0.5
    # no noise in it, but grey world's gains are the noisy frame's: G's (1) is the same
    np.testing.assert_array_equal(a["noise_free"][..., 1], c["noise_free"][..., 1])
    # any thread count, float64 input, and a str key: the FNV-1a of the name, as the CLI's
    one = deepsea.Camera(camera.intrinsics | camera.settings, threads=1)
    np.testing.assert_array_equal(one.record(radiance.astype(np.float64), 5)["image"], a["image"])
    named = camera.record(radiance, "frame_0001")
    assert named["frame_key"] == fnv1a64("frame_0001")
    np.testing.assert_array_equal(named["image"],
                                  camera.record(radiance, fnv1a64("frame_0001"))["image"])
    assert camera.record(radiance, np.uint64(2**64 - 1))["frame_key"] == 2**64 - 1


def test_settings_read_back_to_the_same_camera(camera, camera_yaml, radiance):
    want = camera.record(radiance, 3, layers=CAMERA_LAYERS)
    same = [deepsea.Camera({"camera": dict(CAMERA, **camera.settings)}),
            deepsea.Camera(dict(CAMERA, **STAGE)),          # the section's own dict
            deepsea.Camera(camera_yaml.read_text()),         # YAML text
            deepsea.Camera(pathlib.Path(camera_yaml)),       # os.PathLike
            deepsea.Camera([str(camera_yaml), {"water": {"preset": "jerlov:IB"}}])]  # a list
    for other in same:
        assert other.settings == camera.settings
        got = other.record(radiance, 3, layers=CAMERA_LAYERS)
        for name in ("image",) + CAMERA_LAYERS:
            np.testing.assert_array_equal(got[name], want[name], err_msg=name)


def test_same_codes_as_the_cli(asset_path, camera, camera_yaml, work):
    """`deepsea render --camera` keys a frame by its colour file's stem: a str key in Python.
    The 8-bit PNG holds floor(image * 255 + 0.5) of the same display values."""
    oiio = pytest.importorskip("OpenImageIO")
    rgb, depth = tilted_plane()
    lin = srgb_to_linear(rgb)
    h, w = depth.shape
    with open(work / "cam_frame.pfm", "wb") as f:  # linear colour, exactly as Python's
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(np.ascontiguousarray(lin[::-1]).astype("<f4").tobytes())
    np.save(work / "cam_frame_depth.npy", depth)
    cli("render", "--asset", asset_path, "--rgb", work / "cam_frame.pfm", "--depth",
        work / "cam_frame_depth.npy", "--camera", camera_yaml, "-o", work / "cam_frame.png")
    inp = oiio.ImageInput.open(str(work / "cam_frame.png"))
    codes = inp.read_image("uint8")
    spec = inp.spec()
    inp.close()
    final = deepsea.Renderer(deepsea.load_asset(asset_path)).render(lin, depth, encoding="linear")["final"]
    out = camera.record(final, "cam_frame")
    mine = np.floor(out["image"] * np.float32(255) + np.float32(0.5)).astype(np.uint8)
    assert codes.std() > 5
    np.testing.assert_array_equal(mine, codes)
    assert spec.getattribute("deepsea:frame_key") == "%016x" % out["frame_key"]
    assert float(spec.getattribute("deepsea:system_gain")) == out["system_gain"]
    wb = [float(x) for x in spec.getattribute("deepsea:white_balance").split()]
    assert wb == list(out["white_balance"])


def test_exposure_override(camera, radiance):
    base = camera.record(radiance, 9, layers="raw")
    e = {"exposure_time_ms": 5.0, "system_gain": 0.2}
    for given in (e, (5.0, 0.2), [5, 0.2]):
        out = camera.record(radiance, 9, exposure=given)
        assert (out["exposure_time_ms"], out["system_gain"]) == (5.0, 0.2)
    half = camera.record(radiance, 9, exposure={"exposure_time_ms": 10.0}, layers="raw")
    assert half["system_gain"] == base["system_gain"]  # the sensor's
    ratio = (half["raw"].mean() - 64) / (base["raw"].mean() - 64)
    assert ratio == pytest.approx(0.5, rel=0.02)


def test_auto_exposure_sequence(radiance):
    """The controller of docs/camera.md: record, then next_exposure; the raw layer the meter
    reads comes with every frame; a brighter scene gets less exposure, within the limits."""
    stage = dict(STAGE, auto_exposure={"target": 0.4, "damping": 0.5,
                                       "max_exposure_time_ms": 40.0})
    cam = deepsea.Camera(dict(CAMERA, **stage))
    assert cam.settings["auto_exposure"]["enabled"] is True

    def run(scale, frames=12):
        e, seen = cam.first_exposure(), []
        for k in range(frames):
            out = cam.record(radiance * scale, k, exposure=e)
            assert "raw" in out and out["exposure_time_ms"] == e["exposure_time_ms"]
            seen.append(e)
            e = cam.next_exposure(out)
        return seen, out

    seen, last = run(1.0)
    assert seen[0] == {"exposure_time_ms": 20.0, "system_gain": pytest.approx(0.37620158)}
    assert all(0.01 <= s["exposure_time_ms"] <= 40.0 for s in seen)
    level = (np.percentile(last["raw"].max(axis=2), 99) - 64) / (4095 - 64)
    assert level == pytest.approx(0.4, rel=0.05)
    again, _ = run(1.0)
    assert again == seen  # deterministic
    bright, _ = run(20.0, 4)
    assert bright[-1]["exposure_time_ms"] < seen[-1]["exposure_time_ms"]
    # without the controller: the sensor's settings, no raw layer needed
    fixed = deepsea.Camera(dict(CAMERA, **STAGE))
    out = fixed.record(radiance, 0)
    assert fixed.next_exposure(out) == fixed.first_exposure() == {
        "exposure_time_ms": 20.0, "system_gain": out["system_gain"]}
    with pytest.raises(deepsea.InputError, match="recorded: no 'raw'"):
        cam.next_exposure({"exposure_time_ms": 1.0, "system_gain": 0.5})


def test_records_from_threads(camera, radiance):
    want = camera.record(radiance, 4)["image"]
    results, errors = [], []

    def work():
        try:
            for _ in range(5):
                results.append(camera.record(radiance, 4)["image"])
        except Exception as e:  # pragma: no cover
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(results) == 15
    for got in results:
        np.testing.assert_array_equal(got, want)


def _bad(radiance):
    nan = radiance.copy()
    nan[2, 5, 1] = np.nan
    neg = radiance.copy()
    neg[3, 4, 0] = -1.0
    return [
        (dict(radiance=radiance.astype(np.uint8)), deepsea.InputError,
         "radiance: dtype uint8 is not supported; give float32 or float64 linear radiance"),
        (dict(radiance=radiance.astype(np.float16)), deepsea.InputError,
         "radiance: dtype float16 is not supported"),
        (dict(radiance=radiance[:, :-1]), deepsea.InputError,
         "radiance: shape (48, 63, 3) is not the camera's (48, 64, 3)"),
        (dict(radiance=radiance[..., 0]), deepsea.InputError, "radiance: shape (48, 64) is not"),
        (dict(radiance=nan), deepsea.InputError,
         "radiance: pixel (5, 2) G is NaN: radiance must be finite and >= 0"),
        (dict(radiance=neg), deepsea.InputError, "radiance: pixel (4, 3) R is -1:"),
        (dict(frame_key=-1), deepsea.ConfigError, "frame_key: expected an integer from 0 to"),
        (dict(frame_key=2**64), deepsea.ConfigError, "frame_key: expected an integer"),
        (dict(frame_key=1.5), deepsea.ConfigError, "frame_key: expected an integer"),
        (dict(exposure={"exposure_time_ms": 0.0}), deepsea.ConfigError,
         "exposure.exposure_time_ms: must be > 0"),
        (dict(exposure=(10.0, -0.5)), deepsea.ConfigError, "exposure.system_gain: must be > 0"),
        (dict(exposure={"exposure_time_ms": float("nan")}), deepsea.ConfigError,
         "exposure.exposure_time_ms: must be > 0"),
        (dict(exposure={"gain": 1.0}), deepsea.ConfigError, "exposure: unknown key 'gain'"),
        (dict(exposure={"system_gain": "high"}), deepsea.ConfigError,
         "exposure.system_gain: expected a number, got str"),
        (dict(exposure=(1.0,)), deepsea.ConfigError, "exposure: expected a dict"),
        (dict(layers=("raw", "final")), deepsea.ConfigError, "layers: unknown layer 'final'"),
    ]


def test_bad_inputs_raise_one_line(camera, radiance):
    for change, kind, message in _bad(radiance):
        args = dict(radiance=radiance, frame_key=1) | change
        with pytest.raises(kind) as e:
            camera.record(args.pop("radiance"), args.pop("frame_key"), **args)
        text = str(e.value)
        assert text.startswith(message) and "\n" not in text, (change.keys(), text)


def test_bad_configs(work, camera_yaml):
    plain = work / "plain_camera.yaml"
    plain.write_text("camera:\n" + yaml_map(CAMERA, 2))
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.Camera(str(plain))
    assert str(e.value) == (str(plain) + ": the camera section has no camera stage: give it "
                            "lens, sensor, processing or auto_exposure keys (docs/camera.md)")
    with pytest.raises(deepsea.ConfigError, match="<setup text>: no camera section"):
        deepsea.Camera("water:\n  preset: jerlov:IB\n")
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.Camera(dict(CAMERA, lens={"f_number": 0}))
    assert str(e.value).endswith("camera.lens.f_number: must be > 0, got 0"), str(e.value)
    with pytest.raises(deepsea.ConfigError) as e:
        deepsea.Camera(dict(CAMERA, sensor={"bits": 17}))
    assert "camera.sensor.bits" in str(e.value) and "\n" not in str(e.value)
    with pytest.raises(deepsea.IoError):
        deepsea.Camera(str(work / "none.yaml"))
    with pytest.raises(deepsea.ConfigError, match="threads"):
        deepsea.Camera(str(camera_yaml), threads=-1)
    with pytest.raises(deepsea.ConfigError, match="recorded: expected the dict"):
        deepsea.Camera(str(camera_yaml)).next_exposure(None)


def test_a_port_scales_the_signal_by_its_radiance_factor(radiance):
    # docs/ports.md, "Radiance across the interfaces": behind a flat port on the axis the lens
    # receives (n_air / n_water)^2 of the water-side radiance (the n^2 law), noise off.
    quiet = dict(CAMERA, lens={"f_number": 4.0}, sensor={"noise": False})
    port = {"flat": {"normal": [0, 0, 1], "distance": 0.03, "glass_thickness": 0.012,
                     "n_water": 1.34}}
    plain = deepsea.Camera({"camera": quiet}).record(radiance, 1, layers="linear_dn")
    through = deepsea.Camera({"camera": dict(quiet, port=port)}).record(radiance, 1,
                                                                         layers="linear_dn")
    dark = deepsea.Camera({"camera": quiet}).record(np.zeros_like(radiance), 1,
                                                     layers="linear_dn")["linear_dn"]
    h, w = CAMERA["height"] // 2, CAMERA["width"] // 2
    a = plain["linear_dn"][h - 1:h + 1, w - 1:w + 1] - dark[h - 1:h + 1, w - 1:w + 1]
    b = through["linear_dn"][h - 1:h + 1, w - 1:w + 1] - dark[h - 1:h + 1, w - 1:w + 1]
    np.testing.assert_allclose(b / a, 1 / 1.34**2, rtol=1e-4)
