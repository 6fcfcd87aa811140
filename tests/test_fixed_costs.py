"""No fixed cost counted as work: the command lines start without the heavy libraries, and the
compiled kernels a run calls are loaded before its clocks start.

What "loaded before" means is checked in a fresh process (in this one, earlier tests have loaded
everything): numba adds an overload to a kernel's dispatcher when it loads or compiles it, so a
kernel loaded inside a timed part shows as a dispatcher that gained an overload there. The
figures (start-up times, the first step before and after) are benchmarks/bench_fixed_costs.py's.
"""

import json
import subprocess
import sys

import pytest
from conftest import ROOT

from bearing_fmu.internals import registry
from bearing_fmu.physics.params import PAPER_BEARING

# Every numba dispatcher of the package's imported modules and its overload count.
SNAPSHOT = """
def snapshot():
    import sys
    from numba.core.dispatcher import Dispatcher
    out = {}
    for mod, m in list(sys.modules.items()):
        if m is None or not mod.startswith(("bearing_fmu", "rotor_host")):
            continue
        for name, obj in list(vars(m).items()):
            if isinstance(obj, Dispatcher) and obj.__module__ == mod:
                out[f"{mod}.{name}"] = len(obj.overloads)
    return out

def gained(before, after):
    return sorted(k for k, n in after.items() if n > before.get(k, 0))
"""


def _python(code: str, *args: str) -> dict:
    r = subprocess.run([sys.executable, "-c", code, *args], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_the_command_lines_build_their_parsers_without_the_heavy_libraries():
    # every subcommand's parser (what --help shows) from the registry and the option modules only
    code = """
import contextlib, io, json, sys
from rotor_host.cli import build_parser
from bearing_fmu.cli import main
build_parser()
with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
    main(["--help"])
heavy = ("numba", "scipy", "matplotlib", "dask", "distributed", "fmpy", "pythonfmu", "tqdm")
print(json.dumps(sorted({m.split(".")[0] for m in sys.modules} & set(heavy))))
"""
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.strip().splitlines()[-1]) == []


def test_every_internal_names_modules_that_hold_compiled_kernels():
    import importlib

    from numba.core.dispatcher import Dispatcher

    for spec in registry.REGISTRY.values():
        for ref in spec.kernels:
            module = importlib.import_module(f"bearing_fmu.{ref}")
            cached = [n for n, o in vars(module).items() if isinstance(o, Dispatcher) and not n.startswith("_")
                      and getattr(getattr(o, "_cache", None), "_cache_file", None) is not None]
            assert cached, f"{spec.name}: {ref} holds no public numba kernel with a disk cache (cache=True)"


@pytest.mark.slow
@pytest.mark.parametrize("name", registry.names())
def test_a_warmed_internal_evaluates_without_loading_a_kernel(name, contract_data):
    spec = registry.get(name)
    case = spec.contract_case(contract_data)
    internal = registry.create(name, case.params or PAPER_BEARING, case.options)  # its bore (tilting pads)
    internal.force_and_jacobian(*case.state, case.omega)  # compiled here if it was not: in the disk cache now
    code = SNAPSHOT + """
import json, sys
from pathlib import Path
from bearing_fmu.internals import registry
from bearing_fmu.internals.warmup import warm_internal
from bearing_fmu.physics.params import PAPER_BEARING
name = sys.argv[1]
case = registry.get(name).contract_case(Path(sys.argv[2]))
internal = registry.create(name, case.params or PAPER_BEARING, case.options)
s0 = snapshot()
warm_internal(name)
s1 = snapshot()
internal.force_and_jacobian(*case.state, case.omega)
print(json.dumps({"loaded": gained(s0, s1), "in_the_call": gained(s1, snapshot())}))
"""
    got = _python(code, name, str(contract_data))
    assert bool(got["loaded"]) == bool(spec.kernels), f"{name}: warm_internal loaded {got['loaded']}"
    assert got["in_the_call"] == [], f"{name}: kernels loaded at the first call, not by warm_internal: add their " \
                                     f"modules to its registry entry's kernels"


@pytest.mark.slow
def test_a_run_times_work_not_the_loading_of_kernels(paper_scene, map_file):
    scene = paper_scene(internal="map", t_end=0.002, map={"map": map_file})
    code = SNAPSHOT + """
import json, sys
from rotor_host.integrate import newmark
from rotor_host.scenes import run
from rotor_host.scenes.scene import load_scene
seen = {}
original = newmark.Newmark.run
def timed_part(self, *a, **k):
    seen["start"] = snapshot()
    try:
        return original(self, *a, **k)
    finally:
        seen["end"] = snapshot()
run.Newmark.run = timed_part
m = run.run_scene(load_scene(sys.argv[1]), None).meta
print(json.dumps({"status": m["status"], "kernels_time_s": m["kernels_time_s"], "setup_time_s": m["setup_time_s"],
                  "in_the_integration": gained(seen["start"], seen["end"])}))
"""
    got = _python(code, str(scene))
    assert got["status"] == "ok"
    assert got["in_the_integration"] == [], "kernels loaded inside the timed integration"
    assert 0.0 < got["kernels_time_s"] <= got["setup_time_s"]  # loaded, and counted as setup
