"""deepsea: a physically based deep-sea camera simulator (docs/python.md).

Arrays in and out are NumPy, images (H, W, C) with rows top to bottom, colour R, G, B. The
library is the extension deepsea._deepsea; its names are re-exported here, with the stubs in
_deepsea.pyi (the package is typed: py.typed)."""

from ._deepsea import (
    AccuracyError as AccuracyError,
    Asset as Asset,
    AssetError as AssetError,
    Camera as Camera,
    Cancelled as Cancelled,
    ConfigError as ConfigError,
    Error as Error,
    InputError as InputError,
    IoError as IoError,
    OutOfMemoryError as OutOfMemoryError,
    Renderer as Renderer,
    __version__ as __version__,
    bake as bake,
    exposure_factor as exposure_factor,
    info as info,
    load_asset as load_asset,
    read_frame as read_frame,
    reference as reference,
    render as render,
    write_image as write_image,
    write_layers as write_layers,
)

__all__ = [
    "AccuracyError", "Asset", "AssetError", "Camera", "Cancelled", "ConfigError", "Error",
    "InputError", "IoError", "OutOfMemoryError", "Renderer", "bake", "exposure_factor", "info",
    "load_asset", "read_frame", "reference", "render", "write_image", "write_layers",
]

# The classes are deepsea.X to users, to repr() and to pickle (which imports them by name).
for _name in ("Asset", "Renderer", "Camera"):
    globals()[_name].__module__ = __name__
del _name
