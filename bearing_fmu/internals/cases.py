"""Contract cases of the built-in internals: what tests/test_internals.py needs to build a
working instance of each, for the paper bearing at 22 Hz.

A case is cheap and made up where data is needed (a coarse force map, an order-2 surrogate
with arbitrary coefficients): the contract checks that an internal keeps its promises (its
Jacobian, its refusals, the FMU equal to the direct call), not its accuracy, which each
internal's own tests measure against something independent. Each case writes its data files
into the folder it is given, under fixed names, so the test suite's FMU can bundle the same
files (tests/conftest.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

OMEGA_22HZ = 2.0 * math.pi * 22.0
COARSE_GRID = {"n_theta": 32, "n_x": 4}  # Reynolds: the contract, not the accuracy
COARSE_MAP = {"n_theta": 32, "n_x": 4, "n_eps": 12, "n_beta": 16, "n_phase": 1}
SURROGATE_NAME = "paper_22hz.json"
MAP_NAME = "paper_map.json"


@dataclass(frozen=True)
class ContractCase:
    """What the contract tests need of one internal.

    options     : option values that build a working instance for the paper bearing
    state       : (y, z, vy, vz) [m, m/s] inside what the internal answers for
    omega       : shaft speed [rad/s] of the checks
    beyond_wall : "refuses" (BearingStateError past the clearance circle) or "evaluates"
                  (finite values there: a model that means nothing physical past it, e.g. linear)
    files       : the data files the case wrote, option name -> path
    params      : the bearing to build it for (None: the paper bearing); an internal of a bore the
                  paper bearing lacks (tilting pads) brings the paper bearing with that bore
    """

    options: dict = field(default_factory=dict)
    state: tuple[float, float, float, float] = (10e-6, -40e-6, 1e-3, -2e-4)  # eccentricity 0.46
    omega: float = OMEGA_22HZ
    beyond_wall: str = "refuses"
    files: dict = field(default_factory=dict)
    params: object = None


def default_case(data_dir: Path) -> ContractCase:
    """An internal that brings no case: its defaults, the moving state above."""
    return ContractCase()


def reynolds_case(data_dir: Path) -> ContractCase:
    return ContractCase(dict(COARSE_GRID))


def linear_case(data_dir: Path) -> ContractCase:
    # linearised at the paper bearing's static load; the paper's linear orbits cross the wall:
    # it evaluates there
    return ContractCase({**COARSE_GRID, "load_z": -16.7, "omega_lin": OMEGA_22HZ}, beyond_wall="evaluates")


def map_file(data_dir: Path) -> Path:
    """A coarse force map of the paper bearing (Reynolds 32 x 4, table 12 x 16), made once per folder."""
    from ..physics.params import PAPER_BEARING
    from .map.tablefile import save_map
    from .map.tables import tabulate

    path = Path(data_dir) / MAP_NAME
    if not path.is_file():
        save_map(tabulate(PAPER_BEARING, **COARSE_MAP), path)
    return path


def map_case(data_dir: Path) -> ContractCase:
    path = map_file(data_dir)
    return ContractCase({"map": str(path)}, files={"map": path})


def surrogate_file(data_dir: Path) -> Path:
    """An order-2 surrogate of the paper bearing at 22 Hz with made-up coefficients, expansion
    point (0.1, -0.4) CR: an FMU must reproduce the Taylor internal exactly, whatever they are."""
    import numpy as np

    from ..physics.params import PAPER_BEARING as P
    from ..surrogates.basis import exponents
    from ..surrogates.surrogate import Domain, Surrogate, save_surrogate

    path = Path(data_dir) / SURROGATE_NAME
    if path.is_file():
        return path
    exps = exponents(2)
    coef = np.random.default_rng(1).normal(size=(2, len(exps))) * 0.1
    coef[:, 0] = (0.0, 1.0)
    dom = Domain(ecc_max=0.8, pos_center=(0.0, 0.0), pos_radius=0.3, v_max=0.3, box_lo=(-0.3,) * 4,
                 box_hi=(0.3,) * 4)
    sur = Surrogate(params=P, omega=OMEGA_22HZ, y0=0.1 * P.CR, z0=-0.4 * P.CR, order=2, exponents=exps, coef=coef,
                    force_scale=20.0, domain=dom)
    return save_surrogate(sur, path)


def taylor_case(data_dir: Path) -> ContractCase:
    from ..physics.params import PAPER_BEARING as P

    path = surrogate_file(data_dir)
    return ContractCase({"surrogate": str(path), **COARSE_GRID}, state=(0.15 * P.CR, -0.35 * P.CR, 1e-3, -2e-3),
                        files={"surrogate": path})


def tilting_pad_case(data_dir: Path) -> ContractCase:
    # the paper bearing's D, L, CR, mu on 4 pads, load between pads, offset pivots (0.6) and
    # preload 0.3: asymmetric enough that no derivative vanishes by symmetry; 24 cells a pad
    from dataclasses import replace

    from ..physics.bore.geometry import Geometry
    from ..physics.bore.pads import PadGeometry
    from ..physics.params import PAPER_BEARING

    pads = PadGeometry(pivots=tuple(math.radians(a) for a in (45.0, 135.0, 225.0, 315.0)), arc=math.radians(80.0),
                       offset=0.6, preload=0.3)
    return ContractCase({"n_theta": 24, "n_x": 4}, params=replace(PAPER_BEARING, geometry=Geometry(pads=pads)))


__all__ = ["ContractCase", "tilting_pad_case", "default_case", "reynolds_case", "linear_case", "map_case", "taylor_case", "map_file",
           "surrogate_file", "COARSE_GRID", "COARSE_MAP", "OMEGA_22HZ"]
