"""rtsdf: signed distance fields of triangle-mesh scenes.

The native extension (rtsdf._rtsdf) holds the bakes, queries and pipeline (docs/python.md); rtsdf.batch bakes
many meshes, or one scene by tiles, on a Dask cluster (`python3 -m rtsdf.batch --help`; imported on first use).
"""
import importlib

from . import _rtsdf
from ._rtsdf import *  # noqa: F401,F403  (the extension's functions and classes are the package's)
from ._rtsdf import Error, SettingError  # noqa: F401

__doc__ = __doc__ + "\n" + (_rtsdf.__doc__ or "")


def __getattr__(name):
    # rtsdf.batch imports Dask, which takes a second: only when asked for.
    if name == "batch":
        return importlib.import_module(".batch", __name__)
    raise AttributeError(f"module 'rtsdf' has no attribute '{name}'")
