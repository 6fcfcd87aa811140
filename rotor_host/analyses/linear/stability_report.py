"""The tables and the json of a stability sweep (``stability_result.StabilityResult``): one row per speed,
the markdown report, everything a later reader needs without NaN."""

from __future__ import annotations

from .stability_result import SpeedPoint, StabilityResult, direction


def table_rows(res: StabilityResult) -> list[dict]:
    """One row per speed: eccentricities, the least stable mode, the status."""
    rows = []
    for p in res.points:
        row = {"speed_hz": p.speed_hz, "status": p.status if p.ok else f"{p.status}: {p.message}"}
        if p.ok and p.least is None:
            row["direction"] = f"no mode up to {p.band_hz:.4g} Hz"
        elif p.ok:
            i = p.least
            if p.T_eff_K.size:
                row["t_eff"] = ", ".join(f"{t - 273.15:.2f}" for t in p.T_eff_K)
            row.update({"ecc": ", ".join(f"{e:.3f}" for e in p.eccentricity), "f_hz": float(p.freq_hz[i]),
                        "ratio": float(p.freq_hz[i] / p.speed_hz), "log_dec": float(p.log_dec[i]),
                        "direction": f"{direction(p.whirl[i])} ({p.whirl[i]:+.2f})"})
        rows.append(row)
    return rows


def markdown(res: StabilityResult, title: str = "") -> str:
    from ..tables import markdown_table

    tm = res.timings
    n_ok = len(res.ok_points)
    head = [f"# Stability: {title or res.rotor} [{res.internal}]", "",
            *([f"Computed for: {res.inputs}", ""] if getattr(res, "inputs", "") else []),
            f"**{res.verdict()}**", "", *(f"- {line}" for line in res.notes()), "",
            f"{len(res.points)} speeds ({n_ok} with an equilibrium), bearings at nodes "
            f"{', '.join(map(str, res.bearing_nodes))}, static loads "
            f"{'; '.join(f'({w[0] + 0.0:.4g}, {w[1] + 0.0:.4g}) N' for w in res.loads_N)}; run time "
            f"{tm['equilibrium'] + tm['eigen']:.2f} s (equilibria {tm['equilibrium']:.2f} s, linearisation and "
            f"modes {tm['eigen']:.2f} s), threshold refinement {tm['refine']:.2f} s, setup {tm['setup']:.2f} s.",
            ""]
    if res.threshold is not None:
        t = res.threshold
        head += [f"Threshold between {t.bracket[0]:g} and {t.bracket[1]:g} Hz ({t.how}): {t.speed_hz:.4f} Hz, "
                 f"least stable mode {t.whirl_hz:.4f} Hz, whirl ratio {t.ratio:.4f}, {direction(t.whirl)} whirl "
                 f"({t.whirl:+.2f}); bearing eccentricity {', '.join(f'{e:.3f}' for e in t.point.eccentricity)}.", ""]
    if res.criticals:
        head += ["Critical speeds (the 1x line crosses a damped natural frequency with AF = pi / log dec >= 2.5):", ""]
        head += [markdown_table(res.criticals, [("speed_hz", "speed [Hz]", ".2f"), ("mode", "mode (rank)", "d"),
                                                ("log_dec", "log dec", ".3f"), ("amplification_factor", "AF", ".3g"),
                                                ("whirl", "whirl (+1 fwd, -1 bwd)", "+.2f")]), ""]
    if res.damped_crossings:
        head += ["1x crossings of heavily damped modes (AF < 2.5, critically damped: no resonance, no critical speed): "
                 + ", ".join(f"{c['speed_hz']:.2f} Hz (log dec {c['log_dec']:.3g})" for c in res.damped_crossings), ""]
    if res.T_supply_K is not None:
        head += [f"Oil supplied at {res.T_supply_K - 273.15:.4g} C: every bearing at the viscosity of its film's effective "
                 "temperature T_eff at each speed (docs/thermal.md).", ""]
    head += ["Least stable mode at each speed:", "", ""]
    table = markdown_table(table_rows(res), [
        ("speed_hz", "speed [Hz]", "g"), ("ecc", "eccentricity", ""),
        *([("t_eff", "T_eff [C]", "")] if res.T_supply_K is not None else []), ("f_hz", "least stable: f [Hz]", ".3f"),
        ("ratio", "f / speed", ".3f"), ("log_dec", "log dec", ".4f"), ("direction", "whirl", ""),
        ("status", "status", "")])
    return "\n".join(head) + table + "\n"


def to_json(res: StabilityResult, rotor_path=None) -> dict:
    """Everything a later reader needs, without NaN: per speed the equilibrium, K and C and
    the lowest ``n_modes`` modes; the threshold with the least stable mode's shape."""
    from ...scenes.run_record import package_versions

    def point(p: SpeedPoint) -> dict:
        d = {"speed_hz": p.speed_hz, "status": p.status, "message": p.message}
        if p.ok:
            n = min(res.n_modes, p.freq_hz.size)
            d.update({"journal_m": p.journal.tolist(), "eccentricity": p.eccentricity.tolist(),
                      "K_N_m": p.K.tolist(), "C_N_s_m": p.C.tolist(),
                      "least_stable": None if p.least is None else {
                          "freq_hz": float(p.freq_hz[p.least]), "log_dec": p.least_log_dec,
                          "whirl": float(p.whirl[p.least])},
                      "freq_hz": p.freq_hz[:n].tolist(), "log_dec": p.log_dec[:n].tolist(),
                      "whirl": p.whirl[:n].tolist()})
            if p.T_eff_K.size:
                d.update({"T_eff_K": p.T_eff_K.tolist(), "mu_eff_Pa_s": p.mu_eff_Pa_s.tolist()})
        return d

    thr = None
    if res.threshold is not None:
        t = res.threshold
        s = t.point.shapes[:, t.point.least]
        thr = {"speed_hz": t.speed_hz, "whirl_hz": t.whirl_hz, "whirl_ratio": t.ratio, "whirl": t.whirl,
               "bracket_hz": list(t.bracket), "how": t.how,
               "shape": {"y_re": s[0::4].real.tolist(), "y_im": s[0::4].imag.tolist(),
                         "z_re": s[1::4].real.tolist(), "z_im": s[1::4].imag.tolist()}}
    return {"rotor": res.rotor, "rotor_file": None if rotor_path is None else str(rotor_path),
            "internal": res.internal, "options": {k: str(v) for k, v in res.options.items()},
            "bearing_nodes": res.bearing_nodes, "bearing_loads_N": res.loads_N, "status": res.status,
            "verdict": res.verdict(), "threshold": thr, "unstable_from_start": res.unstable_from_start,
            "critical_speeds": res.criticals, "damped_crossings": res.damped_crossings,
            "ranking": {"rank_up_to": res.rank_up_to, "band_hz": res.band_hz, "notes": res.notes()},
            "timings_s": res.timings, "n_modes": res.n_modes, "T_supply_K": res.T_supply_K,
            "inputs": getattr(res, "inputs", ""),
            "points": [point(p) for p in res.points], "versions": package_versions()}


__all__ = ["table_rows", "markdown", "to_json"]
