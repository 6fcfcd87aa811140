"""A 2000-element shaft on the paper bearing at both ends (issue 38: nothing printed for 400 s,
7.2 GB): `rotor-host run` and `rotor-host stability` through the command line, each in its own
process, with wall time and peak RSS (ru_maxrss of the child).

    python benchmarks/bench_big_rotor.py [--elements 2000] [--t-end 0.05] [--internal map]

Prints one line per command; the run's own line says its setup, equilibrium and integration
times. Run it on an idle machine (state the load: `uptime`)."""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "rotor_host" / "bundled"


def shaft(folder: Path, n: int) -> Path:
    """A uniform 20 mm steel shaft, 1 m long, of n elements, the paper bearing at both ends."""
    le = 1000.0 / n
    els = "\n".join(f"  {{ nodes = [{i + 1}, {i + 2}], od_mm = 20.0, length_mm = {le!r} }}," for i in range(n))
    path = folder / f"shaft_{n}.toml"
    path.write_text(f"elements = [\n{els}\n]\n[material]\nE_GPa = 200.0\ndensity_kg_m3 = 7850.0\npoisson = 0.3\n"
                    f'[[bearings]]\nnode = 1\nbearing = "{MODELS / "bearing_paper.toml"}"\n'
                    f'[[bearings]]\nnode = {n + 1}\nbearing = "{MODELS / "bearing_paper.toml"}"\n')
    return path


def timed(argv: list[str]) -> tuple[float, float, str]:
    """(wall [s], peak RSS [MB], output) of ``rotor-host argv`` in a child process."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "rotor_host.cli", *argv], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    if done.returncode != 0:
        raise SystemExit(f"rotor-host {' '.join(argv)} failed ({done.returncode}): {done.stderr[-2000:]}")
    return wall, max(rss, before) / 1024.0, done.stdout


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--elements", type=int, default=2000)
    ap.add_argument("--t-end", type=float, default=0.05)
    ap.add_argument("--internal", default="map", choices=("map", "reynolds"))
    a = ap.parse_args()
    print(f"load: {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        rotor = shaft(folder, a.elements)
        scene = folder / "big.toml"
        scene.write_text(f'name = "big"\nrotor = "{rotor}"\ninternal = "{a.internal}"\nvia = "direct"\n'
                         f'speed_hz = 22.0\n[map]\nmap = "{MODELS / "maps" / "paper_bearing.json"}"\n'
                         f"[time]\nt_end_s = {a.t_end!r}\ndt_s = 1e-4\n[record]\nnodes = [1, {a.elements // 2 + 1}]\n")
        wall, rss, out = timed(["run", str(scene), "--out", str(folder / "out"), "--no-plots", "--quiet"])
        print(f"run, {a.elements} elements, {a.t_end:g} s: {wall:.1f} s wall, peak RSS {rss:.0f} MB")
        print("  " + out.splitlines()[0])
        wall, rss, out = timed(["stability", str(rotor), "--internal", a.internal, "--speeds-hz", "20:24:2",
                                "--no-plots", "--out", str(folder / "out")])
        print(f"stability, 3 speeds: {wall:.1f} s wall, peak RSS {rss:.0f} MB")
        print("  " + out.splitlines()[0])


if __name__ == "__main__":
    main()
