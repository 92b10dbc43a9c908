# Stubs of the extension deepsea._deepsea (python/src/*.cpp): what each call takes and returns.
# python/tests/test_stubs.py checks that every public name of the module is here, and mypy's
# stubtest (where installed) that the signatures match.
import os
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, os.PathLike[str]]
# A setup: YAML text (a str with a line break), a YAML file, a dict of sections, or a list.
_Setup = Union[None, str, os.PathLike[str], Mapping[str, Any], Sequence[Any]]
_Section = Union[None, str, os.PathLike[str], Mapping[str, Any]]
_Encoding = Optional[Literal["srgb", "linear"]]
_DepthKind = Literal["z", "range"]
_Layers = Union[str, Sequence[str]]
_Array = npt.ArrayLike
_Float32 = npt.NDArray[np.float32]
# Marine snow: a preset's name, "off", or a dict as the setup's snow section.
_Snow = Union[None, str, Mapping[str, Any]]
_FrameKey = Union[int, str]

class Error(Exception): ...
class ConfigError(Error, ValueError): ...
class InputError(Error, ValueError): ...
class IoError(Error, OSError): ...
class AssetError(Error, ValueError): ...
class AccuracyError(Error, RuntimeError): ...
class Cancelled(Error, RuntimeError): ...
class OutOfMemoryError(Error, MemoryError): ...

class Asset:
    @property
    def path(self) -> Optional[str]: ...
    @property
    def camera(self) -> Dict[str, Any]: ...
    @property
    def bake_info(self) -> Dict[str, Any]: ...
    def save(self, path: _Path, *, half: bool = True, preview: bool = True) -> None: ...

def load_asset(path: _Path, *, threads: int = 0) -> Asset: ...

class Renderer:
    def __init__(
        self,
        asset: Asset,
        *,
        camera: _Section = None,
        forward: bool = True,
        threads: int = 0,
        snow: _Snow = None,
        snow_seed: int = 1,
    ) -> None: ...
    def render(
        self,
        rgb: _Array,
        depth: _Array,
        *,
        encoding: _Encoding = None,
        depth_kind: _DepthKind = "z",
        depth_scale: float = 0.001,
        layers: _Layers = "all",
        frame_key: _FrameKey = 0,
        pose: Optional[_Array] = None,
    ) -> Dict[str, _Float32]: ...
    @property
    def camera(self) -> Dict[str, Any]: ...
    @property
    def asset(self) -> Asset: ...
    @property
    def timing(self) -> Dict[str, float]: ...

def render(
    asset: Asset,
    rgb: _Array,
    depth: _Array,
    *,
    encoding: _Encoding = None,
    camera: _Section = None,
    depth_kind: _DepthKind = "z",
    depth_scale: float = 0.001,
    forward: bool = True,
    layers: _Layers = "all",
    threads: int = 0,
) -> Dict[str, _Float32]: ...
def info(path: _Path, *, threads: int = 0) -> Dict[str, Any]: ...
def bake(
    setup: _Setup = None,
    *,
    camera: _Section = None,
    rig: _Section = None,
    water: _Section = None,
    output: Optional[_Path] = None,
    xy_step: int = 0,
    depth_samples: int = 0,
    depth_scheme: str = "log",
    z_max: Union[float, Literal["auto"]] = "auto",
    tolerance: float = 5e-4,
    check: bool = True,
    strict: bool = False,
    scattering: str = "single",
    paths: int = 65536,
    ms_stride: int = 0,
    seed: int = 1,
    half: bool = True,
    preview: bool = True,
    threads: int = 0,
) -> Asset: ...
def reference(
    setup: _Setup,
    rgb: _Array,
    depth: _Array,
    *,
    encoding: _Encoding = None,
    camera: _Section = None,
    rig: _Section = None,
    water: _Section = None,
    depth_kind: _DepthKind = "z",
    depth_scale: float = 0.001,
    z_max: float = 0.0,
    rel_tol: float = 1e-7,
    threads: int = 0,
) -> Dict[str, _Float32]: ...
def exposure_factor(radiance: _Array, exposure: Union[str, float] = "auto") -> float: ...
def read_frame(
    rgb: _Path, depth: _Path, *, depth_channel: str = "", depth_scale: float = 0.001
) -> Dict[str, Any]: ...
def write_image(
    path: _Path,
    image: _Array,
    *,
    encoding: _Encoding = None,
    exposure: float = 1.0,
    bits: int = 8,
    metadata: Optional[Mapping[str, str]] = None,
    threads: int = 0,
) -> None: ...
def write_layers(
    path: _Path,
    layers: Mapping[str, _Array],
    *,
    half: bool = False,
    metadata: Optional[Mapping[str, str]] = None,
    threads: int = 0,
) -> None: ...

class Camera:
    def __init__(self, config: _Setup, *, threads: int = 0) -> None: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def intrinsics(self) -> Dict[str, Any]: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def black_level(self) -> float: ...
    @property
    def max_dn(self) -> float: ...
    def record(
        self,
        radiance: _Array,
        frame_key: Union[int, str],
        *,
        exposure: Union[None, Mapping[str, float], Tuple[float, float]] = None,
        layers: Union[str, Sequence[str]] = (),
    ) -> Dict[str, Any]: ...
    def first_exposure(self) -> Dict[str, float]: ...
    def next_exposure(self, recorded: Mapping[str, Any]) -> Dict[str, float]: ...
