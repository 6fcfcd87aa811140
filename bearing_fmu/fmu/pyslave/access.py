"""The slave's variables: registered with pythonfmu from the one table (``fmu.variables``), read
and set by value reference (fast paths for the host's per-iteration getReal / setReal), each
parameter checked alone when it is set."""

import math
import operator

from pythonfmu import Boolean, Fmi2Causality, Fmi2Variability, Integer, Real, String

from ...internals import registry
from .. import ports
from ..order import INIT
from ..resources import BEARING_FIELDS, bearing_defaults, default_file, port_defaults
from ..variables import ENUMERATIONS, INPUT, OUTPUT, PARAMETER, VARIABLES, enum_value

VAR_CLASS = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}
CAST = {"Real": float, "Integer": int, "Boolean": bool, "String": str}
FILE_OPTIONS = {o.name for o in registry.all_options() if o.file}
OPTIONS = {o.name: o for o in registry.all_options()}
UNITS = {v[0]: v[3] for v in VARIABLES}
_INF = math.inf


def real_getter(names):
    """A function of the slave giving its attributes ``names`` as a list of floats (one C call)."""
    get = operator.attrgetter(*names)
    if len(names) == 1:
        return lambda obj: [float(get(obj))]
    return lambda obj: list(map(float, get(obj)))


class VariableAccess:
    """The variables of ``slave.BearingFMU``."""

    def _register_variables(self) -> None:
        """Every variable of ``VARIABLES`` as an attribute with its start (the bundled files' and
        the built-in bearing's where given), registered with pythonfmu; the enumerations beside
        their Strings; the value-reference tables of the fast paths."""
        self._by_vr = {}  # value reference -> (name, type, causality)
        built_in = {**bearing_defaults(self.resources), **port_defaults(self.resources)}
        for name, typ, causality, _unit, default, desc in VARIABLES:
            if name in FILE_OPTIONS:
                default = default_file(self.resources, OPTIONS[name])
            elif name in built_in:
                default = built_in[name]
            setattr(self, name, default)
            var = VAR_CLASS[typ](
                name,
                causality=getattr(Fmi2Causality, causality),
                variability=(Fmi2Variability.fixed if causality == PARAMETER
                             else Fmi2Variability.discrete if typ != "Real"
                             else Fmi2Variability.continuous),
                description=desc,
                getter=(lambda n=name: getattr(self, n)),
                setter=(lambda v, n=name, c=CAST[typ]: setattr(self, n, c(v))),
            )
            self.register_variable(var)
            self._by_vr[var.value_reference] = (name, typ, causality)
        # the String choices' starts (a built-in bearing's oil law among them), their enumerations with them
        self._starts = {string: getattr(self, string) for string, _items in ENUMERATIONS.values()}
        for name, (string, _items) in ENUMERATIONS.items():
            setattr(self, name, enum_value(name, self._starts[string]))
        self._real_names = {vr: e[0] for vr, e in self._by_vr.items() if e[1] == "Real"}
        # getReal's fast path: outside Step Mode without the outputs, so reading them in
        # Initialization Mode takes the checked path, which computes them from the inputs
        self._real_no_outputs = {vr: n for vr, n in self._real_names.items() if self._by_vr[vr][2] != OUTPUT}
        self._all_inputs = {vr: e[0] for vr, e in self._by_vr.items() if e[1] == "Real" and e[2] == INPUT}

    def _get(self, vrs, typ, cast, bad):
        self._order(f"get{typ}")
        out, errors, computed = [], [], False
        for vr in vrs:
            entry = self._by_vr.get(vr)
            if entry is None or entry[1] != typ:
                errors.append(f"value reference {vr} is not a {typ} variable of this FMU")
                out.append(bad)
                continue
            if entry[2] == OUTPUT and self._mode is INIT and not computed:
                self._outputs_in_init(f"get{typ} {entry[0]}")  # raises when they cannot be computed
                computed = True
            try:
                out.append(cast(getattr(self, entry[0])))
            except Exception as exc:  # noqa: BLE001
                errors.append(f"{entry[0]}: {exc}")
                out.append(bad)
        if errors:
            self._fail(f"get{typ}: {'; '.join(errors)}")
        return out

    def _set(self, vrs, values, typ, cast):
        self._order(f"set{typ}")
        errors = []
        for vr, value in zip(vrs, values):
            entry = self._by_vr.get(vr)
            if entry is None or entry[1] != typ:
                errors.append(f"value reference {vr} is not a {typ} variable of this FMU")
                continue
            name, _, causality = entry
            if causality == OUTPUT:
                errors.append(f"{name} is an output and cannot be set")
                continue
            if causality == INPUT and typ == "Real" and not math.isfinite(cast(value)):
                errors.append(f"input {name} = {value!r} is not finite; it keeps {getattr(self, name)!r}")
                continue
            if causality == PARAMETER:
                if self._initialized:
                    errors.append(f"parameter {name} is fixed after initialisation (variability fixed); "
                                  f"it keeps {getattr(self, name)!r}")
                    continue
                try:
                    value = self._check_parameter(name, cast(value))
                except (ValueError, TypeError) as exc:
                    self._refused[name] = f"{exc} (refused when it was set)"
                    errors.append(f"{exc}; {name} keeps {getattr(self, name)!r}")
                    continue
                self._refused.pop(name, None)
            try:
                setattr(self, name, cast(value))
            except Exception as exc:  # noqa: BLE001
                errors.append(f"{name} = {value!r}: {exc}")
        if errors:
            self._fail(f"set{typ}: {'; '.join(errors)}")

    @staticmethod
    def _check_parameter(name: str, value):
        """The value of parameter ``name``, or ValueError naming it, the value and what is allowed.
        What one value can be checked alone is checked here; BearingParams and the internal
        check the whole set when it is built."""
        if name == "internal":
            registry.get(value)
        elif name in ENUMERATIONS:
            items = ENUMERATIONS[name][1]
            if not 1 <= value <= len(items):
                raise ValueError(f"{name} = {value!r} must be one of "
                                 + ", ".join(f"{k + 1} ({c})" for k, c in enumerate(items)))
        elif name in BEARING_FIELDS:  # BearingParams checks them together at initialisation
            if not (0.0 < value < _INF):
                raise ValueError(f"{name} = {value!r} {UNITS[name]} must be finite and > 0")
        elif name in OPTIONS:
            value = OPTIONS[name].check(value)
        elif name == "oil_law":
            if str(value).strip().lower() not in ports.OIL_LAWS:
                raise ValueError(f"oil_law = {value!r} must be one of {', '.join(ports.OIL_LAWS)}")
        elif name in ports.PARAMETER_NAMES:
            value = ports.check_value(name, value)
        return value

    def get_real(self, vrs):
        try:  # fast path: every reference a Real variable (the host's per-iteration call): one C call
            key = tuple(vrs)
            getter = self._real_getters.get(key)
            if getter is None:  # first time for this list (a KeyError takes the checked path)
                getter = self._real_getters[key] = real_getter([self._real_get[vr] for vr in vrs])
            return getter(self)
        except Exception:  # noqa: BLE001 - the checked path computes outputs in Initialization Mode, or refuses
            return self._get(vrs, "Real", float, math.nan)

    def get_integer(self, vrs):
        return self._get(vrs, "Integer", int, 0)

    def get_boolean(self, vrs):
        return self._get(vrs, "Boolean", bool, False)

    def get_string(self, vrs):
        return self._get(vrs, "String", str, "")

    def set_real(self, vrs, values):
        try:  # fast path: finite Real inputs only (the host's per-iteration call); idempotent on fallback
            names = self._real_inputs
            for vr, value in zip(vrs, values):
                value = float(value)
                if value - value != 0.0:  # inf or nan: the checked path refuses it by name
                    raise ValueError
                setattr(self, names[vr], value)
        except Exception:  # noqa: BLE001 - the checked path applies the rules and refuses
            self._set(vrs, values, "Real", float)

    def set_integer(self, vrs, values):
        self._set(vrs, values, "Integer", int)

    def set_boolean(self, vrs, values):
        self._set(vrs, values, "Boolean", bool)

    def set_string(self, vrs, values):
        self._set(vrs, values, "String", str)
