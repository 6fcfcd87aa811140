"""Native bearing FMUs: the Reynolds, linear, map and Taylor internals as compiled C, no Python at run time.

``build_native_fmu`` (``build``) writes an FMI 2.0 FMU with Model Exchange and Co-Simulation,
its C sources in ``sources/`` and binaries for linux64, win64 and darwin64:

| module | what |
|---|---|
| build | stage the sources, the model description, the documentation; zip |
| catalogue | one ``NativeSpec`` per internal: what it compiles, its options, its generator, its refusals |
| generators/ | each internal's generator: its data and start values, its model_data.h |
| codegen | the variables, model_config.h; the model identifier and GUID (content hashes) |
| compile | the compilers (zig for every platform, cc, fmpy's CMake) and the platforms; each binary checked |
| objfile | ELF, PE and Mach-O exports and imports; the universal Mach-O writer |
| fmi3 | the FMI 3.0 FMU of the same internals: its model and build descriptions (``fmi_version=3``) |
| host | what a host sets on a native FMU (per bearing) |
| solver_lib | the C Reynolds solver alone, compiled and called through ctypes (tests, benchmarks) |

The hand-written C is in ``c/`` (the FMI 2 and FMI 3 layers, each function a check and one call
into the model layer ``bearing_calls.c``; one file per internal, a C host).
"""

from .catalogue import NATIVE, names

INTERNALS = names()  # what a native FMU can compute (the catalogue's)

__all__ = ["INTERNALS", "NATIVE", "build_native_fmu", "native_parameters"]


def build_native_fmu(*args, **kwargs):
    from .build import build_native_fmu as build

    return build(*args, **kwargs)


def native_parameters(*args, **kwargs):
    from .host import native_parameters as params

    return params(*args, **kwargs)
