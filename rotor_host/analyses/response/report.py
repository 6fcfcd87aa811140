"""The markdown report of an unbalance response (``unbalance.ResponseResult``): its inputs, the
stability threshold, the peaks with their AF and margins, the amplitudes at the probes per
speed, the figures."""

from __future__ import annotations

from .peaks import AF_CRITICAL, peak_words


def _um(v) -> str:
    return "-" if v != v else f"{v * 1e6:.4g}"


def markdown(res, inputs: list[str], figures=()) -> str:
    """The report; ``inputs`` lines name the rotor, bearings, oil and internal."""
    from ..tables import markdown_table

    lines = [f"# Unbalance response: {res.meta.get('rotor', '')}", "", "## Inputs", ""]
    lines += [f"- {x}" for x in inputs]
    lines += [f"- unbalance: {u.label()}" for u in res.unbalances]
    lines += [f"- speeds: {res.speeds_hz[0]:g}-{res.speeds_hz[-1]:g} Hz, {len(res.speeds_hz)} points; probes: nodes "
              f"{', '.join(map(str, res.probes))}",
              "- operating range: " + ("not given (no separation margins)" if res.operating_hz is None else
                                       f"{res.operating_hz[0]:g}-{res.operating_hz[1]:g} Hz"), ""]
    lines += ["## Stability", ""]
    if res.threshold_hz is not None:
        lines.append(f"Threshold of instability {res.threshold_hz:.2f} Hz: the speeds above it are computed and kept but "
                     "marked unstable (the free whirl grows there; the steady response is not what the machine does).")
    elif res.unstable_from_start:
        lines.append("Unstable from the first speed of the range: every speed is marked unstable.")
    else:
        lines.append("No threshold in the range: every speed with an equilibrium is stable.")
    n_bad = sum(1 for s in res.status if s not in ("ok", "unstable"))
    if n_bad:
        lines.append(f"{n_bad} speed(s) without a static equilibrium (no response there; see the json's status).")
    lines += ["", "## Peaks", "",
              "Half-power amplification factor AF = N_c / (N_2 - N_1) (API RP 684); AF < "
              f"{AF_CRITICAL:g}: critically damped, not a critical speed. Required margins: API 617 (docs/response.md).",
              ""]
    if not res.peaks:
        lines.append("No peak at the probes inside the range.")
    rows = []
    for p in res.peaks:
        af = p["amplification_factor"]
        n1, n2 = p["half_power_hz"]
        rows.append({"node": p["node"], "dir": p["direction"], "speed_hz": f"{p['speed_hz']:.3f}",
                     "amp_um": _um(p["amplitude_m"]), "N1-N2 Hz": "-" if n1 is None or n2 is None else f"{n1:.3f}-{n2:.3f}",
                     "AF": "?" if af is None else f"{af:.3g}",
                     "critical": "?" if p["critical"] is None else "yes" if p["critical"] else "no (AF < 2.5)",
                     "SM %": "-" if p["separation_margin_pct"] is None else f"{p['separation_margin_pct']:.3g}",
                     "required %": "-" if p["required_margin_pct"] is None else f"{p['required_margin_pct']:.3g}",
                     "met": "-" if p["meets_margin"] is None else "yes" if p["meets_margin"] else "NO",
                     "stable": "no" if p["unstable"] else "yes"})
    if rows:
        lines += [markdown_table(rows, [(k, k, "") for k in rows[0]]), ""]
        lines += [f"- {peak_words(p)}" for p in res.peaks]
    lines += ["", "## Amplitudes at the probes [um, 0-peak]", ""]
    curves = {n: res.node(n) for n in res.probes}
    rows = []
    for i, s in enumerate(res.speeds_hz):
        row = {"speed_hz": f"{s:g}", "status": res.status[i]}
        for n in res.probes:
            row[f"{n} y"] = _um(curves[n]["y_amplitude_m"][i])
            row[f"{n} z"] = _um(curves[n]["z_amplitude_m"][i])
        rows.append(row)
    lines += [markdown_table(rows, [(k, k, "") for k in rows[0]]), ""]
    if figures:
        lines += ["## Figures", ""] + [f"![{f.stem}]({f.name})" for f in figures] + [""]
    return "\n".join(lines)


__all__ = ["markdown"]
