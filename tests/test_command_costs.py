"""Every rotor-host command prints its fixed costs (imports, kernels, its bearings' FMUs) in one line
apart from its work (bearing_fmu.io.fixed_costs.watch_command / command_line, called by the
command line's main for every command; sweep prints its own, which names its workers and cluster)."""

import argparse
import sys
import time

from conftest import ROOT

from bearing_fmu.io import fixed_costs
from rotor_host.cli import build_parser, main


def test_the_watch_times_imports_and_kernels_apart(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "meta_path", list(sys.meta_path))  # the watcher's finder goes with the test
    monkeypatch.setattr(fixed_costs, "_WATCH", [])
    monkeypatch.syspath_prepend(str(tmp_path))
    (tmp_path / "slow_to_import_37.py").write_text("import time\ntime.sleep(0.2)\n")
    # a module that compiles a kernel while it is imported: kernels, not imports too
    (tmp_path / "compiles_at_import_37.py").write_text("from numba import njit\nassert njit(lambda x: x + 1)(1) == 2\n")
    t0 = time.perf_counter()
    costs = fixed_costs.watch_command()
    assert fixed_costs.command_costs() is costs
    import slow_to_import_37  # noqa: F401  (0.2 s of import, by construction)

    from numba import njit

    @njit  # a kernel numba compiles now: the compiler lock held
    def twice(x):
        return 2.0 * x

    assert twice(1.5) == 3.0
    kernels = costs.parts["kernels"]
    import compiles_at_import_37  # noqa: F401
    assert costs.parts["kernels"] > kernels
    with costs.timed("bearings"):  # what a command adds by name (its FMUs built and loaded)
        time.sleep(0.05)
    time.sleep(0.1)  # work
    assert 0.2 <= costs.parts["imports"] < 5.0
    assert costs.parts["kernels"] > 0.0
    assert costs.total_s <= time.perf_counter() - t0  # nothing counted twice
    line = fixed_costs.command_line()
    assert line.startswith(f"fixed costs {costs.total_s:.2f} s (imports ") and "bearings 0.0" in line
    work = float(line.rpartition("; work ")[2].split()[0])
    assert 0.1 <= work < 60.0
    fresh = fixed_costs.watch_command()  # the next command starts afresh
    assert fresh is not costs and fresh.parts == {}


def test_every_command_but_sweep_leaves_its_line_to_main():
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    own = sorted(name for name, p in sub.choices.items() if p.get_default("own_fixed_costs"))
    assert own == ["sweep"]
    assert {"run", "paper", "stability", "compare", "response"} <= set(sub.choices)


def test_a_run_prints_its_fixed_costs_line_last(tmp_path, capsys):
    scene = ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"
    assert main(["run", str(scene), "--internal", "linear", "--via", "direct", "--t-end", "0.002", "--no-plots",
                 "--quiet", "--out", str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("fixed costs ") and "; work " in last, last
