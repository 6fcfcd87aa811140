"""``rotor-host api-report``: the design review's linear checks in one markdown file with its
figures: the Campbell diagram and the stability threshold (``linear.stability``), the
unbalance response with its peaks, AF and API separation margins (``unbalance``), the
undamped critical speed map (``ucs``) and, when the rotor file has ``[[stages]]``, API 617's
Level I stability (``level1``). One stability sweep serves the first three (the bearings' K, C
at each speed); each figure's title names its inputs (rotor, bearing files and bore, oil,
internal)."""

from __future__ import annotations

from pathlib import Path


def _demote(text: str) -> str:
    """Each markdown heading one level down (a section's report inside the whole)."""
    return "\n".join("#" + line if line.startswith("#") else line for line in text.splitlines())


def command(*, rotor_file, speeds_hz, unbalance, operating_hz, internal: str = "reynolds", data_files=None,
            grid=None, static_load=(), supply_c=None, probe=None, gas_density_kg_m3=None, out="out",
            no_plots: bool = False) -> int:
    """Writes ``api_report.md``, the json of each part and the figures into ``out``."""
    import numpy as np

    from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

    from ..linear.stability import Stability
    from ..linear.inputs import check_speeds, internal_options, read_rotor
    from ..linear.stability_report import to_json as stability_json
    from . import level1 as lv, ucs
    from ..computed_for import bearing_lines, internal_words
    from .report import markdown as response_markdown
    from .unbalance import check_inputs, response_from, to_json as response_json

    out = ensure_writable(out)
    options = internal_options(internal, data_files, grid)
    T = None if supply_c is None else supply_c + 273.15
    rotor, loads = read_rotor(rotor_file, static_load)
    check_inputs(rotor, rotor_file, unbalance, operating_hz, probe)
    analysis = Stability(rotor, internal, options, loads, where=str(rotor_file), T_supply_K=T)
    sweep = analysis.sweep(check_speeds(speeds_hz), rotor_name=rotor.name or Path(rotor_file).stem,
                           log=lambda msg: print(f"  {msg}"))
    res = response_from(analysis, sweep, rotor_file, unbalance, operating_hz, probe)
    line = res.meta["inputs"]
    ok = [p for p in sweep.points if p.ok]
    bearing_k = np.array([np.stack([p.K[:, 0, 0], p.K[:, 1, 1]], axis=1) for p in ok])
    m = ucs.build(rotor, ucs.DEFAULT_STIFFNESS, ucs.DEFAULT_POINTS, ucs.DEFAULT_CRITICALS, [p.speed_hz for p in ok],
                  bearing_k)
    m.meta = {"rotor": sweep.rotor, **{k: res.meta[k] for k in ("rotor_file", "internal", "options", "inputs")}}
    level = None
    if rotor.stages:
        point, _ = analysis.at(res.operating_hz[1])
        level = lv.level1(rotor, res.operating_hz[1], point.K, point.C)
        level.gas_density_kg_m3 = gas_density_kg_m3
        level.meta = dict(m.meta)

    figs: dict[str, list[Path]] = {"campbell": [], "response": [], "ucs": [], "level1": []}
    if not no_plots:
        from ..linear.campbell import plot_campbell, plot_log_dec
        from .figures import plot_bode, plot_polar

        figs["campbell"] = [plot_campbell(sweep, out / "campbell.png", f"Campbell diagram: {sweep.rotor}\n{line}"),
                            plot_log_dec(sweep, out / "logdec.png", f"Log decrement: {sweep.rotor}\n{line}")]
        for n in res.probes:
            figs["response"] += [plot_bode(res, n, out / f"bode_node{n}.png", line),
                                 plot_polar(res, n, out / f"polar_node{n}.png", line)]
        figs["ucs"] = [ucs.plot_map(m, rotor, out / "ucs_map.png", line),
                       ucs.plot_shapes(m, rotor, out / "ucs_modes.png", line)]
        if level is not None:
            figs["level1"] = [lv.plot_level1(level, out / "level1.png", line)]

    inputs = [f"rotor: {rotor_file} ({sweep.rotor})", *bearing_lines(rotor, rotor_file),
              f"internal: {internal_words(analysis.internal, analysis.options)}",
              "oil: " + ("each bearing's own viscosity" if T is None else f"supply {supply_c:g} C, mu_eff per speed"),
              f"operating range: {res.operating_hz[0]:g}-{res.operating_hz[1]:g} Hz (maximum continuous speed "
              f"{res.operating_hz[1]:g} Hz)"]
    parts = [f"# API 617 / API RP 684 linear rotordynamic report: {sweep.rotor}", "", "## Inputs", "",
             *[f"- {x}" for x in inputs], "", "## Campbell diagram and stability threshold", "",
             f"**{sweep.verdict()}**", ""]
    parts += [f"- critical speed {c['speed_hz']:.2f} Hz (log dec {c['log_dec']:.3f}, AF {c['amplification_factor']:.3g})"
              for c in sweep.criticals] + [f"- {n}" for n in sweep.notes()] + [""]
    parts += [f"![{f.stem}]({f.name})" for f in figs["campbell"]] + [""]
    parts += [_demote(response_markdown(res, [], figs["response"])), ""]
    parts += [_demote(ucs.markdown(m, [], figs["ucs"])), ""]
    if level is not None:
        parts += [_demote(lv.markdown(level, [], figs["level1"])), ""]
    else:
        parts += ["## API 617 Level I stability", "", f"Not run: {rotor_file} has no [[stages]] table (each stage's "
                  f"{lv.STAGE_KEYS_WORDS}; docs/file-formats.md).", ""]
    files = [write_text(out / "api_report.md", "\n".join(parts)),
             write_json(out / "stability.json", stability_json(sweep, rotor_file)),
             write_json(out / "response.json", response_json(res)), write_json(out / "ucs.json", ucs.to_json(m))]
    if level is not None:
        files.append(write_json(out / "level1.json", lv.to_json(level)))
    print(f"computed for: {line}")
    print(sweep.verdict())
    n_crit = sum(1 for p in res.peaks if p["critical"])
    print(f"unbalance response: {len(res.peaks)} peak(s) at the probes, {n_crit} with AF >= 2.5"
          + ("" if not res.peaks else f"; margins {'all met' if all(p['meets_margin'] in (True, None) for p in res.peaks) else 'NOT all met'}"))
    if level is not None:
        print(f"API 617 Level I: {level.verdict()[0]}")
    print("wrote " + ", ".join(str(f) for f in files) + f" and {sum(len(v) for v in figs.values())} figures")
    return 0


__all__ = ["command"]
