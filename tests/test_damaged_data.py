"""Issue 22, item 4: damaged data refused by name.

A surrogate file (the FMU bundles it and loads it with the same ``load_surrogate``) whose
numbers are not finite, or disagree with each other, is refused at load with one line naming
the file, the key, what was expected and what was given; so is the FMU's resources/bearing.json.
A huge but finite input to the Taylor internal itself (not only behind its guard, see
tests/test_internals.py) is refused by name instead of returning inf or NaN.

The damage is made here from a file the writer produced (``save_surrogate``), so every case
starts from a file that loads.
"""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.internals.registry import BearingStateError
from bearing_fmu.internals.taylor import Taylor
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.surrogates.basis import exponents, natural_force_scale
from bearing_fmu.surrogates.surrogate import Domain, Surrogate, load_surrogate, save_surrogate

P = PAPER_BEARING
OMEGA = 2 * math.pi * 22.0
ROOT = Path(__file__).resolve().parents[1]


def _surrogate() -> Surrogate:
    rng = np.random.default_rng(5)
    exps = exponents(2)
    coef = rng.normal(size=(2, len(exps))) * 0.1
    kept = np.ones_like(coef, bool)
    coef[0, 3] = 0.0
    kept[0, 3] = False  # one pruned term: coefficient 0
    dom = Domain(ecc_max=0.6, pos_center=(0.0, 0.0), pos_radius=0.3, v_max=0.3, box_lo=(-0.3,) * 4,
                 box_hi=(0.3,) * 4)
    return Surrogate(P, OMEGA, 0.05 * P.CR, -0.1 * P.CR, 2, exps, coef, natural_force_scale(P, OMEGA), dom,
                     kept=kept, errors={"rms_Fy": 0.01}, provenance={"truth": "made up"})


def _set(path, value):
    def damage(d):
        *parents, last = path
        for k in parents:
            d = d[k]
        d[last] = value
    return damage


def _duplicate_row(d):
    d["exponents"][5] = d["exponents"][4]


def _pruned_but_nonzero(d):
    d["coef"]["Fy"][3] = 0.25


@pytest.mark.parametrize("damage, expected", [
    # non-finite numbers, wherever they sit (Python's json reads NaN and Infinity)
    (_set(("omega",), math.nan), r"key 'omega' must be a finite number, got nan"),
    (_set(("wall_power",), math.inf), r"key 'wall_power' must be a finite number, got inf"),
    (_set(("coef", "Fz", 2), math.nan), r"coef: key 'Fz' must be a list of 15 numbers, each finite; entry 2 is nan"),
    (_set(("domain", "box_hi", 1), -math.inf), r"domain: key 'box_hi' must be a list of 4 numbers, each finite"),
    (_set(("errors", "rms_Fy"), math.nan), r"key 'errors.rms_Fy' is not a finite number .* expected finite numbers"),
    (_set(("provenance", "train"), {"n": [1.0, math.inf]}), r"key 'provenance.train.n\[1\]' is not a finite number"),
    # consistency
    (_set(("order",), 3), r"key 'order' = 3 but the highest degree in 'exponents' is 2; expected equal"),
    (_duplicate_row, r"key 'exponents' has the row \[0, 0, 0, 1\] twice; expected each monomial once"),
    (_pruned_but_nonzero, r"coef: key 'Fy' entry 3 = 0.25 belongs to a term that 'kept' marks pruned \(0\)"),
    (_set(("expansion_point", "vy0"), 0.1), r"expansion_point: key 'vy0' = 0.1 must be 0"),
    (_set(("domain", "box_lo", 2), 0.5), r"domain: box_lo\[2\] = 0.5 > box_hi\[2\] = 0.3; the box needs box_lo <= box_hi"),
    (_set(("shape",), {"order": 10 ** 6, "coef": {}}), r"shape: coef: missing key 'Fy_Sy'"),
])
def test_damaged_surrogate_file_is_refused_naming_file_and_key(tmp_path, damage, expected):
    good = save_surrogate(_surrogate(), tmp_path / "good.json")
    load_surrogate(good)
    d = json.loads(good.read_text())
    damage(d)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))  # allow_nan (the default): writes NaN and Infinity as a damaged file has them
    with pytest.raises((ValueError, KeyError)) as err:
        load_surrogate(bad)
    text = str(err.value)
    assert text.startswith(f"surrogate file '{bad}': ") and "\n" not in text, text
    assert re.search(expected, text), text


def test_the_shipped_surrogates_pass_the_new_checks():
    for path in sorted((ROOT / "rotor_host" / "bundled" / "surrogates").glob("*.json")):
        load_surrogate(path)


@pytest.mark.parametrize("var, value", [("vy", 1e308), ("vz", -1e308)])
def test_taylor_itself_refuses_a_huge_velocity_by_name(var, value):
    # unguarded (a Taylor built by hand, or the guard's domain_limit set high): the polynomial
    # in vy / (omega CR) overflows; no finite value is the surrogate's answer
    t = Taylor(_surrogate())
    x = {"y": 0.05 * P.CR, "z": -0.1 * P.CR, "vy": 0.0, "vz": 0.0, var: value}
    for call in (t.force, t.force_and_jacobian):
        with pytest.raises(BearingStateError, match=rf"bearing input {var} = {re.escape(repr(value))} m/s is too large"):
            call(x["y"], x["z"], x["vy"], x["vz"], OMEGA)
    assert np.all(np.isfinite(t.force(x["y"], x["z"], 1e-3, 0.0, OMEGA)))


@pytest.mark.parametrize("text, expected", [
    ('{"D": NaN, "L": 0.02, "CR": 9e-05, "mu": 0.05}', r"bearing.json: D = nan must be a finite number"),
    ('{"D": 0.031, "L": 0.02, "CR": 9e-05, "mu": 0.05, "grooves": 2}', r"bearing.json: unknown key\(s\) grooves"),
    ('{"D": 0.031, "L": 0.02, "CR": 0.09, "mu": 0.05}', r"bearing.json: CR = 90 mm is outside the physical range"),
    ('{"D": 0.031, "L": 0.02', r"bearing file .*bearing.json cannot be read as JSON"),
])
def test_damaged_fmu_bearing_resource_is_refused_not_replaced(tmp_path, text, expected):
    # the slave read this file with a bare json.loads and fell back to the paper bearing on any
    # fault (a NaN passed); it now reads it with BearingParams.from_json
    f = tmp_path / "bearing.json"
    f.write_text(text)
    with pytest.raises(ValueError, match=expected) as err:
        BearingParams.from_json(f)
    assert "\n" not in str(err.value)
    f.write_text(json.dumps({**P.as_dict(), "source": "rotor_host/bundled/bearing_paper.toml"}))
    assert BearingParams.from_json(f) == P
