"""What the pythonfmu slave (``slave.py``) reads around it: the FMU's resources folder and
pythonfmu's C++ logger.

* the bundled data files (``default_file``: the one file of a format is a file option's default),
  the built-in bearing (``bearing_defaults``), the notes of the binary's patches
  (``status_patched``: do exceptions give fmi2Error?), the names of those files;
* ``LoggingFlag``: whether the master has logging on, read from pythonfmu's logger object.

Bundled into the FMU with the rest of the package; nothing here imports pythonfmu.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..internals import registry

SURROGATE_DIR = "surrogates"  # inside the FMU's resources folder: the files of file options
PATCH_NOTES = "pythonfmu_patches.json"  # written by build.py into resources/
BEARING_DEFAULTS = "bearing.json"  # in resources/: D, L, CR, mu of `bearing-fmu build --bearing FILE`
PORT_DEFAULTS = "parameters.json"  # in resources/: the bore and oil parameters of `bearing-fmu build --bearing FILE`
BUILD_INFO = "build_info.json"  # in resources/: what the FMU was built from (bearing, data files, hashes)
# fmu_binary.STATUS_PATCHES (build tooling, not bundled in the FMU; a test keeps the two equal)
STATUS_PATCHES = ("keep-instance", "error-status", "error-message", "step-terminated", "restore-terminated")
BEARING_FIELDS = ("D", "L", "CR", "mu")  # BearingParams fields: the parameters a built-in bearing sets

_BUNDLED_FORMATS: dict[str, dict[str, str]] = {}  # resources folder -> {file name: JSON "format"}, read once


def default_file(resources, option) -> str:
    """The default of a file option the internal needs (``Option.required``): the one bundled file of
    its format (surrogate, force map), else "" (none, or several to choose from). An optional one
    (the tilting pads' ``pad_map``: empty, the Reynolds pads) defaults to "": a force map bundled
    for the map internal must not switch the pads to it."""
    if not resources or not option.required:
        return ""
    folder = Path(resources) / SURROGATE_DIR
    key = str(folder)
    if key not in _BUNDLED_FORMATS:
        formats = {}
        try:
            for p in sorted(folder.iterdir()):
                if p.is_file():
                    try:
                        formats[p.name] = registry.file_format(p)
                    except ValueError:  # not JSON: the option's loader names it if it is chosen
                        formats[p.name] = ""
        except OSError:
            pass
        _BUNDLED_FORMATS[key] = formats
    names = [n for n, f in _BUNDLED_FORMATS[key].items() if not option.file_format or f == option.file_format]
    return names[0] if len(names) == 1 else ""


def status_patched(resources) -> bool:
    """True when the build applied every FMI status patch to this platform's binary."""
    import json
    import sys

    if not resources:
        return False
    if sys.platform.startswith("linux"):
        platform = "linux64" if sys.maxsize > 2 ** 32 else "linux32"
    else:
        platform = {"win32": "win64", "darwin": "darwin64"}.get(sys.platform, sys.platform)
    try:
        notes = json.loads((Path(resources) / PATCH_NOTES).read_text(encoding="utf-8")).get(platform, {})
    except (OSError, ValueError, AttributeError):
        return False
    return all(str(notes.get(n, "")).endswith("patched") for n in STATUS_PATCHES)


class LoggingFlag:
    """Whether the master receives this instance's log: pythonfmu's C++ logger's flag.

    pythonfmu keeps ``loggingOn`` (and fmi2SetDebugLogging's later changes) in its C++
    ``PyLogger`` and passes only that object's address to Python (keyword ``logger``). Its
    0.7.0 layout: vtable pointer, ``bool debugLogging_`` at +8, ``std::string instanceName_``
    at +16 (data pointer, then length; a short name sits in the object itself at +32). The
    layout is trusted only when that string reads back as this instance's name; otherwise
    ``off`` answers False (nothing is echoed)."""

    def __init__(self, address, instance_name: str):
        self._flag = None
        if not isinstance(address, int) or address <= 0 or not isinstance(instance_name, str):
            return
        try:
            import ctypes

            name = instance_name.encode("utf-8")
            size = ctypes.c_size_t.from_address(address + 24).value
            data = ctypes.c_void_p.from_address(address + 16).value
            if size != len(name) or (size < 16 and data != address + 32) or not data:
                return
            if ctypes.string_at(data, size) != name:
                return
            self._flag = ctypes.c_bool.from_address(address + 8)
        except Exception:  # noqa: BLE001 - unknown layout: echo nothing
            self._flag = None

    def off(self) -> bool:
        """True when the master has logging off (read live: fmi2SetDebugLogging changes it)."""
        return self._flag is not None and not self._flag.value


def bearing_defaults(resources) -> dict:
    """The built-in bearing's D, L, CR, mu [SI] when the FMU was built for one, else {}. A damaged
    file fails the instantiation naming it and the key (it used to give the paper bearing)."""
    from ..physics.params import BearingParams

    path = Path(resources) / BEARING_DEFAULTS if resources else None
    if path is None or not path.is_file():
        return {}
    return BearingParams.from_json(path).as_dict()


def port_defaults(resources) -> dict:
    """The built-in bearing's bore and oil parameters (``ports.port_defaults``) when the FMU was
    built for one, else {}; every name and value checked (``ports.check_value``), a damaged file
    fails the instantiation naming it and the parameter."""
    import json

    from . import ports

    path = Path(resources) / PORT_DEFAULTS if resources else None
    if path is None or not path.is_file():
        return {}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(data, dict):
            raise ValueError("not a JSON object")
        for name, value in data.items():
            if name == "internal":  # a tilting-pad bearing's: the internal that takes pads (build_fmu)
                registry.get(value)
                continue
            if name in ports.START_NAMES:  # a thermal port's start (ports.supply_starts)
                if isinstance(value, (str, bool)) or value is None or not 0.0 < value < math.inf:
                    raise ValueError(f"{name} = {value!r} must be a finite number > 0")
                continue
            if name not in ports.PARAMETER_NAMES:
                raise ValueError(f"{name!r} is not a bore or oil parameter of the FMU")
            if name == "oil_law" and value not in ports.OIL_LAWS:
                raise ValueError(f"oil_law = {value!r} must be one of {', '.join(ports.OIL_LAWS)}")
            if name != "oil_law" and (isinstance(value, str) or value is None):
                raise ValueError(f"{name} = {value!r} must be a number or a Boolean")
            if name != "oil_law":
                ports.check_value(name, value)
    except (OSError, ValueError) as exc:
        raise ValueError(f"FMU resource {path}: {exc}") from None
    return data
