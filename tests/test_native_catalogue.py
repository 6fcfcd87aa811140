"""The native FMU's catalogue (bearing_fmu/fmu/native/catalogue.py, issue 32 item 2): one
``NativeSpec`` per internal with a C model, beside its registry entry, and the one refusal of an
internal without one, giving the reason wherever a native FMU is asked for it (the build, the
model generator, an FMU of several, a host's parameters). No FMU is compiled here.
"""

from pathlib import Path

import pytest

from bearing_fmu.fmu.native import INTERNALS
from bearing_fmu.fmu.native.catalogue import NATIVE, companions, native_spec, refused_choices
from bearing_fmu.internals import registry
from bearing_fmu.physics.params import PAPER_BEARING

C_DIR = Path(__file__).resolve().parents[1] / "bearing_fmu" / "fmu" / "native" / "c"


def test_every_native_internal_of_the_registry_has_its_entry_and_files():
    """The registry's capability native (what the host and the docs ask) and the catalogue agree,
    and each entry's C files and options exist."""
    package = [n for n in registry.names() if not callable(registry.get(n).factory)]
    assert sorted(n for n in package if registry.get(n).can.native) == sorted(NATIVE) == sorted(INTERNALS)
    for name, spec in NATIVE.items():
        assert spec.sources[0] == f"internal_{name}.c"
        for f in (*spec.sources, *spec.headers, *spec.flow_sources):
            assert (C_DIR / f).is_file(), (name, f)
        own = {o.name for o in registry.get(name).all_options()}
        assert set(spec.options) <= own, (name, set(spec.options) - own)
        assert spec.bore in ("full", "compiled", "data") and bool(spec.speed_start) != bool(spec.speed_why)
        assert spec.film_report == registry.get(name).can.film_flow  # its C film report, where Python has one


def test_companions_and_the_choices_refused_without_them():
    """Taylor's domain_action = fallback holds the Reynolds internal too; without it the choice is refused."""
    taylor = native_spec("taylor")
    assert companions(taylor, {"domain_action": "fallback"}) == ("reynolds",)
    assert companions(taylor, {"domain_action": "warn"}) == ()
    assert refused_choices(("taylor",))["domain_action"][0] == "fallback"
    assert refused_choices(("taylor", "reynolds")) == {}


@pytest.fixture
def outsider():
    """An internal registered from outside the package that even claims a native model."""
    spec = registry.InternalSpec("outsider", lambda p, o, c: None, "test only",
                                 can=registry.Capabilities(native=True))
    registry.register(spec)
    yield spec
    registry.unregister("outsider")


def test_an_internal_from_outside_is_refused_with_its_reason_everywhere(outsider, tmp_path):
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.codegen import native_model
    from bearing_fmu.fmu.native.host import fmu_internals, native_parameters
    from bearing_fmu.fmu.native.several import parse_internals

    why = "registered from outside the package"
    calls = [lambda: native_spec(outsider),
             lambda: native_model("outsider", PAPER_BEARING),
             lambda: build_native_fmu(tmp_path / "x.fmu", "outsider", compiler="cc"),
             lambda: build_native_fmu(tmp_path / "x.fmu", "map,outsider", compiler="cc"),
             lambda: parse_internals("reynolds,outsider"),
             lambda: native_parameters("outsider", PAPER_BEARING, {}, where="scene.toml"),
             lambda: fmu_internals("outsider", {})]
    for call in calls:
        with pytest.raises(ValueError, match=why):
            call()
    assert not list(tmp_path.iterdir())  # refused before anything was built
    with pytest.raises(ValueError, match="scene.toml: internal 'outsider' is registered from outside"):
        native_parameters("outsider", PAPER_BEARING, {}, where="scene.toml")


def test_an_unknown_internal_is_named():
    with pytest.raises(ValueError, match="no internal 'nosuch': a native FMU computes one of linear, map"):
        native_spec("nosuch")
