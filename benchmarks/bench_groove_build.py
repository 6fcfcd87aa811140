"""What a grooved map's flow tables cost a native map FMU: build time and size, with and without.

The native map FMU of a shipped grooved map (default rotor_host/bundled/maps/paper_2groove.json) for its
bearing with the ISO VG 46 oil law (rotor_host/bundled/bearing_paper_vg46.toml's [oil]; without an oil law the
build leaves the flow tables out, fmu/native/generators/map.py GROOVED_NO_OIL_WHY), built from the version 4 file (its
flow spline over one period in phi and the edges' renumbering compiled in, c/map_flows.c) and from
a version 2 copy (the force alone): the build's wall time, model_data.h, each platform's binary and
the FMU, side by side with their ratio. Figures in docs/forcemap.md, "Cost".

    .venv/bin/python benchmarks/bench_groove_build.py [--map FILE] [--platforms linux64 win64 ...] [--cc]
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def bearing_with_oil(map_path: Path, folder: Path):
    """The map's bearing file (rotor_host/bundled/bearing_<stem>.toml) with the VG 46 [oil] instead of mu_Pa_s."""
    from bearing_fmu.physics.params import BearingParams

    oil = (ROOT / "rotor_host" / "bundled" / "bearing_paper_vg46.toml").read_text().split("[oil]")[1]
    text = (ROOT / "rotor_host" / "bundled" / f"bearing_{map_path.stem}.toml").read_text()
    path = folder / "bearing.toml"
    path.write_text("\n".join(line for line in text.splitlines() if not line.startswith("mu_Pa_s")) + "\n[oil]" + oil)
    return BearingParams.from_toml(path)


def measure(map_path: Path, params, out: Path, platforms, cc: bool) -> dict:
    from bearing_fmu.fmu.native.build import build_native_fmu

    t0 = time.perf_counter()
    build_native_fmu(out, "map", map=map_path, bearing=params, platforms=platforms, **({"compiler": "cc"} if cc else {}))
    row = {"build s": time.perf_counter() - t0, "FMU MB": out.stat().st_size / 1e6}
    with zipfile.ZipFile(out) as z:
        for i in z.infolist():
            if i.filename == "sources/model_data.h":
                row["model_data.h MB"] = i.file_size / 1e6
            elif i.filename.startswith("binaries/") and not i.filename.endswith("/"):
                row[f"{i.filename.split('/')[1]} MB"] = i.file_size / 1e6
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--map", type=Path, default=ROOT / "rotor_host" / "bundled" / "maps" / "paper_2groove.json")
    ap.add_argument("--platforms", nargs="*", default=None, help="zig targets (default: every platform)")
    ap.add_argument("--cc", action="store_true", help="this machine's C compiler, this platform only")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        params = bearing_with_oil(args.map, folder)
        data = json.loads(args.map.read_text())
        for key in ("Q", "flow_edges_deg", "flow_meaning"):
            data.pop(key)
        v2 = folder / "v2" / args.map.name
        v2.parent.mkdir()
        v2.write_text(json.dumps({**data, "version": 2}))
        rows = {name: measure(path, params, folder / f"{name}.fmu", args.platforms, args.cc)
                for name, path in (("version 2 (force)", v2), ("version 4 (flows)", args.map))}
    a, b = rows.values()
    print(f"{args.map.name}, the bearing with VG 46 ({'cc' if args.cc else 'zig'}):")
    print(f"| | {' | '.join(rows)} | ratio |\n|---|---:|---:|---:|")
    for key in b:
        print(f"| {key} | {a.get(key, 0.0):.2f} | {b[key]:.2f} | {b[key] / a[key] if a.get(key) else float('nan'):.2f} |")


if __name__ == "__main__":
    main()
