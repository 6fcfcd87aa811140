"""Native bearing FMUs: the linear, map and Taylor internals as compiled C, no Python at run time.

``build_native_fmu`` (``build``) writes an FMI 2.0 FMU with Model Exchange and Co-Simulation,
its C sources in ``sources/`` and a binary compiled for this platform (``fmi_version=3``: FMI 3.0,
``fmi3``); ``codegen`` generates the internal's data as C; the hand-written C is in ``c/`` (FMI
layers, one file per internal).
"""

from .codegen import INTERNALS, NATIVE_OPTIONS

__all__ = ["INTERNALS", "NATIVE_OPTIONS", "build_native_fmu", "native_parameters"]


def build_native_fmu(*args, **kwargs):
    from .build import build_native_fmu as build

    return build(*args, **kwargs)


def native_parameters(*args, **kwargs):
    from .host import native_parameters as params

    return params(*args, **kwargs)
