"""The surrogate and its file (bearing_fmu/surrogates/surrogate.py): the round trip, the bearing
it belongs to, damaged files named by key, files of older forms (no wall factor, no shape
columns), bad settings refused.

Expected values come from the surrogate before saving, from reference values written next to
each test (computed by the code preceding a format change) and from the shipped files.
"""

import json
from pathlib import Path

import numpy as np
import pytest
from surrogate_cases import (
    BOX,
    OMEGA,
    Y0,
    Z0,
    P,
    R,
    Smooth,
    poly_surrogate,
    random_states,
    shape_surrogate,
    wall_surrogate,
)

from bearing_fmu import fitting as F
from bearing_fmu.internals.registry import BearingStateError
from bearing_fmu.internals.taylor import Taylor
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.surrogates.basis import n_terms
from bearing_fmu.surrogates.surrogate import Surrogate, load_surrogate, save_surrogate

# ----------------------------------------------------------------------------- files

def test_file_round_trip(tmp_path):
    states = random_states(300, 15)
    forces = F.sample_forces(Smooth(), states, OMEGA)
    res = F.fit_surrogate(states, forces, P, OMEGA, Y0, Z0, R(3, prune=True), domain=BOX, load=(0.0, -16.7),
                          provenance={"training_source": "unit test"})
    path = save_surrogate(res.surrogate, tmp_path / "s.json")
    back = load_surrogate(path, P)
    a, b = res.surrogate, back
    assert (b.omega, b.y0, b.z0, b.order, b.force_scale, b.lam, b.load) == \
           (a.omega, a.y0, a.z0, a.order, a.force_scale, a.lam, a.load)
    np.testing.assert_array_equal(b.coef, a.coef)
    np.testing.assert_array_equal(b.kept, a.kept)
    np.testing.assert_array_equal(b.exponents, a.exponents)
    assert b.domain == a.domain
    assert b.provenance["training_source"] == "unit test" and "package_version" in b.provenance
    x = (Y0 + 1e-6, Z0, 1e-4, -1e-4, OMEGA)
    assert Taylor(b).force(*x) == Taylor(a).force(*x)


@pytest.mark.parametrize("field,value", [("D", 0.032), ("L", 0.025), ("CR", 100e-6), ("mu", 0.04)])
def test_mismatched_bearing_refused(tmp_path, field, value):
    path = save_surrogate(poly_surrogate(2), tmp_path / "s.json")
    other = BearingParams(**{**P.as_dict(), field: value})
    with pytest.raises(ValueError, match=rf"{field} = {getattr(P, field)!r}.*{field} = {value!r}"):
        load_surrogate(path, other)
    with pytest.raises(ValueError, match=rf"{field} = "):
        Taylor(load_surrogate(path), other)


def test_malformed_files(tmp_path):
    good = poly_surrogate(2).to_dict()
    with pytest.raises(FileNotFoundError, match="nope.json"):
        load_surrogate(tmp_path / "nope.json")
    p = tmp_path / "bad.json"
    p.write_text("{not json")
    with pytest.raises(ValueError, match="bad.json.*not valid JSON"):
        load_surrogate(p)
    for key in ("omega", "exponents", "domain", "params"):
        d = dict(good)
        del d[key]
        p.write_text(json.dumps(d))
        with pytest.raises(KeyError, match=rf"bad.json.*{key}"):
            load_surrogate(p)
    d = json.loads(json.dumps(good))
    d["coef"]["Fz"] = d["coef"]["Fz"][:-1]
    p.write_text(json.dumps(d))
    with pytest.raises(ValueError, match=r"bad.json.*coef.*'Fz'"):
        load_surrogate(p)
    d = json.loads(json.dumps(good))
    del d["domain"]["v_max"]
    p.write_text(json.dumps(d))
    with pytest.raises(KeyError, match=r"bad.json.*domain.*v_max"):
        load_surrogate(p)


def test_wall_factor_file_round_trip(tmp_path):
    s = wall_surrogate(4, seed=5, p=1.5, scale=0.1)
    path = save_surrogate(s, tmp_path / "w.json")
    assert json.loads(path.read_text())["wall_power"] == 1.5
    b = load_surrogate(path, P)
    assert b.wall_power == 1.5
    x = (0.5 * P.CR, -0.6 * P.CR, 1e-3, -2e-3, OMEGA)
    assert Taylor(b).force(*x) == Taylor(s).force(*x)
    f1, q1, v1 = Taylor(b).force_and_jacobian(*x)
    f2, q2, v2 = Taylor(s).force_and_jacobian(*x)
    np.testing.assert_array_equal(np.hstack([f1, q1.ravel(), v1.ravel()]), np.hstack([f2, q2.ravel(), v2.ravel()]))


def test_file_without_wall_power_is_the_plain_polynomial(tmp_path):
    # files written before the wall factor have no "wall_power": they load with 0 and evaluate
    # bit-identically to before (reference values computed by the code preceding the wall factor)
    s = poly_surrogate(5, seed=21, scale=0.1)
    d = s.to_dict()
    d.pop("wall_power")
    path = tmp_path / "old.json"
    path.write_text(json.dumps(d))
    old = load_surrogate(path, P)
    assert old.wall_power == 0.0
    t = Taylor(old)
    x = (Y0 + 0.13 * P.CR, Z0 - 0.21 * P.CR, 0.07 * OMEGA * P.CR, -0.11 * OMEGA * P.CR)
    assert t.force(*x, OMEGA) == (7.028154553611349, 8.06106590285221)
    _, dq, dv = t.force_and_jacobian(*x, OMEGA)
    assert dq.tolist() == [[100467.41512799545, -145866.78687215986], [96851.54093510313, -143477.28148423057]]
    assert dv.tolist() == [[713.4018390362481, -299.50785184428264], [-442.9496819711803, -350.1029993473691]]
    # and the shipped files load (with or without the key)

    for f in sorted((Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "surrogates").glob("*.json")):
        sur = load_surrogate(f)
        assert sur.wall_power == json.loads(f.read_text()).get("wall_power", 0.0)


def test_shape_columns_file_round_trip_and_bad_files(tmp_path):
    s = shape_surrogate(3, 3, seed=39)
    path = save_surrogate(s, tmp_path / "s.json")
    d = json.loads(path.read_text())
    assert d["shape"]["order"] == 3 and len(d["shape"]["coef"]["Fz_Sy"]) == n_terms(3)
    b = load_surrogate(path, P)
    x = (0.5 * P.CR, -0.6 * P.CR, 1e-3, -2e-3, OMEGA)
    assert Taylor(b).force(*x) == Taylor(s).force(*x)
    # a file without the key has no shape columns
    assert "shape" not in poly_surrogate(3).to_dict()
    d["shape"]["coef"]["Fy_Sz"] = d["shape"]["coef"]["Fy_Sz"][:-1]
    (tmp_path / "bad.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match="shape: coef: key 'Fy_Sz' must be a list of 35 numbers"):
        load_surrogate(tmp_path / "bad.json")
    d["shape"]["order"] = -1
    (tmp_path / "bad.json").write_text(json.dumps(d))
    with pytest.raises(ValueError, match="shape: key 'order' must be a non-negative integer"):
        load_surrogate(tmp_path / "bad.json")
    # at the wall the closed form is undefined: a clear error, not a NaN
    with pytest.raises(BearingStateError, match="shape columns are undefined"):
        Taylor(shape_surrogate(2, 1, p=0.0)).force(0.0, -P.CR, 0.0, 0.0, OMEGA)


@pytest.mark.parametrize("bad", ["abc", 2.5, -1, True])
def test_bad_shape_order_named(bad):
    s = poly_surrogate(2)
    with pytest.raises(ValueError, match="Surrogate.shape_order = .* must be an integer >= 0"):
        Surrogate(P, OMEGA, Y0, Z0, 2, s.exponents, s.coef, s.force_scale, BOX, shape_order=bad,
                  shape_coef=np.zeros((4, 5)))
    with pytest.raises(ValueError, match="fit: shape_order = .* must be an integer >= 0"):
        F.fit_surrogate(random_states(100, 1), np.zeros((100, 2)), P, OMEGA, Y0, Z0, R(2, shape_order=bad),
                        domain=BOX)
