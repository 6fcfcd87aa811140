"""The finite-element rotor: reads a rotor file, assembles M, C, G, K, builds loads, modes.

Equation of motion (SI units, 4 DOFs per node ordered (y, z, theta_y, theta_z))::

    M qdd + (C + Omega G) qd + K q = F

``Omega > 0`` is a right-handed spin about the shaft axis x (y -> z); ``C = beta K`` is the
shaft's proportional damping (paper, section 3). Bearings are not in ``K`` or ``C``: the
host adds their forces (or, for modal analysis, their Lund coefficients: the bearing force
is ``-K_b q - C_b qd``, so ``+K_b`` and ``+C_b`` enter at (y, z) of the bearing node).

Nodes are 0-based in this API; rotor files number nodes and elements from 1 (Table 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Mapping

import numpy as np

from bearing_fmu.io.schema import check_table, read_toml
from bearing_fmu.physics.params import BearingParams

from . import fe
from .assembly import DENSE_MAX_DOF, assemble_bands
from .eigen import OSCILLATORY, modal_table, state_eig, state_eigvals, zero_tol
from .parts import (ROTOR_KEYS, Disk, Material, RotorFileError, ShaftElement, diameters_m, element_mass,
                    node_index)

DIRECTIONS = {"y": fe.Y, "z": fe.Z, "ty": fe.TY, "tz": fe.TZ}


@dataclass
class Rotor:
    """Assembled FE rotor. Build with :meth:`from_toml`, or directly from elements (SI units).

    ``M, K, G, C`` are dense ``(n_dof, n_dof)`` arrays, ``n_dof = 4 * n_nodes``, made on first use
    from the band storage ``bands`` (``assemble_bands``); ``sparse()`` gives them as scipy.sparse
    matrices and ``matrices()`` in the form a solve of this size wants (a big rotor never needs
    an n x n array);
    ``node_x`` [m] are the node positions along the axis (node 0 at x = 0);
    ``bearing_nodes`` are 0-based, ``bearings[i]`` is the BearingParams of bearing i.
    """

    elements: list[ShaftElement]
    material: Material
    disks: list[Disk] = field(default_factory=list)
    bearing_nodes: list[int] = field(default_factory=list)
    bearings: list[BearingParams] = field(default_factory=list)
    name: str = ""
    stages: list[dict] = field(default_factory=list)  # [[stages]] as read (STAGE_KEYS), node 0-based
    bands: dict = field(init=False, repr=False, compare=False)
    node_x: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not self.elements:
            raise ValueError("a rotor needs at least one shaft element")
        if len(self.bearings) != len(self.bearing_nodes):
            raise ValueError(f"{len(self.bearing_nodes)} bearing nodes but {len(self.bearings)} bearing parameter sets")
        for node in [d.node for d in self.disks] + list(self.bearing_nodes):
            self._check_node(node)
        self.bands = assemble_bands(self.elements, self.disks, self.material)
        self._dense: dict[str, np.ndarray] = {}
        self.node_x = np.concatenate([[0.0], np.cumsum([e.length for e in self.elements])])

    # ------------------------------------------------------------------ matrices
    def _full(self, name: str) -> np.ndarray:
        A = self._dense.get(name)
        if A is None:
            from ..integrate.banded import from_band  # numba's import only when a matrix is asked for

            A = self._dense[name] = from_band(self.bands[name])
        return A

    @property
    def M(self) -> np.ndarray:
        """Mass matrix [kg, kg m^2], dense."""
        return self._full("M")

    @property
    def K(self) -> np.ndarray:
        """Stiffness matrix [N/m, N, N m], dense."""
        return self._full("K")

    @property
    def G(self) -> np.ndarray:
        """Gyroscopic matrix (times Omega in the equation of motion) [kg m^2], dense."""
        return self._full("G")

    @property
    def C(self) -> np.ndarray:
        """The shaft's proportional damping beta K, dense."""
        return self._full("C")

    def sparse(self) -> tuple:
        """(M, K, G, C) as scipy.sparse CSR matrices, the same entries, without an n x n array."""
        from ..integrate.banded import band_to_sparse  # numba's import only when a matrix is asked for

        return tuple(band_to_sparse(self.bands[k]) for k in ("M", "K", "G", "C"))

    def matrices(self) -> tuple:
        """(M, K, G, C) for the solvers (the equilibrium, the integrator, the loads): dense up to
        DENSE_MAX_DOF DOFs, where dense products cost nothing, scipy.sparse above."""
        return (self.M, self.K, self.G, self.C) if self.n_dof <= DENSE_MAX_DOF else self.sparse()

    # ------------------------------------------------------------------ reading
    @classmethod
    def from_toml(cls, path: str | Path) -> "Rotor":
        """Read a rotor file (see rotor_host/bundled/rotor_paper.toml); bearing paths are relative to it."""
        path = Path(path)
        data = read_toml(path, "rotor file", RotorFileError)
        return cls.from_mapping(data, base_dir=path.parent, where=str(path))

    @classmethod
    def from_mapping(cls, data: Mapping, *, base_dir: str | Path = ".", where: str = "rotor") -> "Rotor":
        """Build from the parsed TOML mapping, checked against ROTOR_KEYS at once; every error is a
        RotorFileError of one line naming ``where``, the table and key ('[[elements]] 2 od_mm')."""
        d = check_table(data, ROTOR_KEYS, where, RotorFileError)
        mat = d["material"]
        material = Material(E=mat["E_GPa"] * 1e9, density=mat["density_kg_m3"], poisson=mat["poisson"],
                            beta=mat["damping_beta_s"])

        elements = []
        for i, t in enumerate(d["elements"]):
            ew = f"{where}: [[elements]] {i + 1}"
            if t["nodes"] is not None and t["nodes"] != [i + 1, i + 2]:
                raise RotorFileError(f"{ew} nodes = {t['nodes']!r} must be [{i + 1}, {i + 2}] (element i joins "
                                     "nodes i and i+1)")
            od, idm = diameters_m(t, ew)
            elements.append(ShaftElement(length=t["length_mm"] / 1e3, od=od, id=idm))
        n_nodes = len(elements) + 1

        disks = []
        for i, t in enumerate(d["disks"]):
            dw = f"{where}: [[disks]] {i + 1}"
            od, idm = diameters_m(t, dw)
            disks.append(Disk(node=node_index(t["node"], n_nodes, f"{dw} node"), od=od, id=idm, width=t["width_mm"] / 1e3))

        bearing_nodes, bearings = [], []
        for i, t in enumerate(d["bearings"]):
            bw = f"{where}: [[bearings]] {i + 1}"
            node = node_index(t["node"], n_nodes, f"{bw} node")
            if node in bearing_nodes:
                raise RotorFileError(f"{bw} node = {node + 1}: that node already has a bearing")
            bpath = Path(base_dir) / t["bearing"]
            try:
                params = BearingParams.from_toml(bpath)
            except ValueError as exc:  # the bearing file's own one-line error (not found, key, value)
                raise RotorFileError(f"{bw} bearing = {t['bearing']!r}: {exc}") from None
            bearing_nodes.append(node)
            bearings.append(params)

        stages = []
        for i, t in enumerate(d["stages"]):
            stages.append({**t, "node": node_index(t["node"], n_nodes, f"{where}: [[stages]] {i + 1} node")})

        return cls(elements=elements, material=material, disks=disks,
                   bearing_nodes=bearing_nodes, bearings=bearings, name=d["name"] or "", stages=stages)

    def refined(self, k: int) -> "Rotor":
        """The same rotor with each shaft element cut into ``k`` equal elements (disks and
        bearings at the same places): 4 (k n_elements + 1) DOFs, for convergence and scaling
        studies."""
        k = int(k)
        if k < 1:
            raise ValueError(f"refined(k): k = {k} must be an integer >= 1")
        elements = [ShaftElement(e.length / k, e.od, e.id) for e in self.elements for _ in range(k)]
        disks = [Disk(d.node * k, d.od, d.id, d.width) for d in self.disks]
        return Rotor(elements=elements, material=self.material, disks=disks,
                     bearing_nodes=[nd * k for nd in self.bearing_nodes], bearings=list(self.bearings),
                     name=f"{self.name} x{k}" if self.name else "",
                     stages=[{**st, "node": st["node"] * k} for st in self.stages])

    # ------------------------------------------------------------------ sizes and indexing
    @property
    def n_nodes(self) -> int:
        return len(self.elements) + 1

    @property
    def n_dof(self) -> int:
        return fe.DOFS_PER_NODE * self.n_nodes

    @property
    def mass(self) -> float:
        """Total mass [kg] of shaft and disks (from the geometry, equal to u^T M u for a unit translation u)."""
        rho = self.material.density
        return sum(element_mass(e, rho) for e in self.elements) + sum(
            fe.disk_properties(d.od, d.id, d.width, rho)[0] for d in self.disks
        )

    def _check_node(self, node: int) -> int:
        if isinstance(node, bool) or not isinstance(node, (int, np.integer)) or not 0 <= node < self.n_nodes:
            raise ValueError(f"node must be a 0-based integer in 0..{self.n_nodes - 1}, got {node!r}")
        return int(node)

    def dof(self, node: int, direction: str) -> int:
        """Global DOF index of ``direction`` in ('y', 'z', 'ty', 'tz') at 0-based ``node``."""
        node = self._check_node(node)
        if direction not in DIRECTIONS:
            raise ValueError(f"direction must be one of {', '.join(DIRECTIONS)}, got {direction!r}")
        return fe.DOFS_PER_NODE * node + DIRECTIONS[direction]

    def rigid_modes(self) -> np.ndarray:
        """The shaft's rigid-body motions, (n_dof, 4): unit translations along y and z, and unit
        slopes about x = 0 (node 0) in the x-y and x-z planes (y = x, theta_z = 1; z = x,
        theta_y = -1: the elements' dy/dx = theta_z, dz/dx = -theta_y). K has them as its null
        space (a free shaft), so ``rigid_modes().T @ f`` is a load's resultant: forces [N] along
        y, z and moments [N m] about x = 0 (the static equilibrium's balance check)."""
        x = self.node_x
        phi = np.zeros((self.n_dof, 4))
        d = fe.DOFS_PER_NODE
        phi[fe.Y::d, 0] = 1.0
        phi[fe.Z::d, 1] = 1.0
        phi[fe.Y::d, 2] = x
        phi[fe.TZ::d, 2] = 1.0
        phi[fe.Z::d, 3] = x
        phi[fe.TY::d, 3] = -1.0
        return phi

    # ------------------------------------------------------------------ loads
    def weight_vector(self, g: float = 9.81) -> np.ndarray:
        """Gravity load [N, N m] along -z: ``-g M u_z`` with u_z a unit z translation of every node.

        Uses the consistent mass, so the element-end moments of the distributed weight come out
        right; the z forces sum to ``-mass * g``.
        """
        u = np.zeros(self.n_dof)
        u[fe.Z::fe.DOFS_PER_NODE] = 1.0
        return -g * (self.matrices()[0] @ u)

    def unbalance_force(self, t: float, speed: float, mass: float, radius: float, node: int,
                        phase: float = 0.0) -> np.ndarray:
        """Unbalance force [N] at constant ``speed`` [rad/s]: ``m r Omega^2 (cos, sin)(Omega t + phase)``.

        ``mass`` [kg] at ``radius`` [m] on 0-based ``node``; at t = 0, phase = 0 it points
        along +y and turns toward +z (forward, Omega > 0).
        """
        F = np.zeros(self.n_dof)
        a = speed * t + phase
        amp = mass * radius * speed**2
        F[self.dof(node, "y")] = amp * math.cos(a)
        F[self.dof(node, "z")] = amp * math.sin(a)
        return F

    def point_load_vector(self, loads) -> np.ndarray:
        """Static point loads [N]: ``{node: (Fy, Fz)}`` or an iterable of ``(node, Fy, Fz)``; 0-based nodes."""
        items: Iterable
        if isinstance(loads, Mapping):
            items = ((n, *f) for n, f in loads.items())
        else:
            items = loads
        F = np.zeros(self.n_dof)
        for item in items:
            node, fy, fz = item
            F[self.dof(node, "y")] += float(fy)
            F[self.dof(node, "z")] += float(fz)
        return F

    # ------------------------------------------------------------------ bearings in matrices
    def _per_bearing(self, value, name: str) -> np.ndarray:
        """Broadcast a 2x2 matrix (or None) to one 2x2 per bearing: shape (n_bearings, 2, 2)."""
        nb = len(self.bearing_nodes)
        if value is None:
            return np.zeros((nb, 2, 2))
        a = np.asarray(value, dtype=float)
        if a.shape == (2, 2):
            return np.broadcast_to(a, (nb, 2, 2))
        if a.shape == (nb, 2, 2):
            return a
        raise ValueError(f"{name} must be one 2x2 matrix or {nb} of them (one per bearing), got shape {a.shape}")

    def bearing_matrix(self, per_bearing) -> np.ndarray:
        """n_dof x n_dof matrix with each bearing's 2x2 block at (y, z) of its node (Lund sign: added)."""
        out = np.zeros((self.n_dof, self.n_dof))
        for node, k in zip(self.bearing_nodes, self._per_bearing(per_bearing, "bearing matrix")):
            idx = [self.dof(node, "y"), self.dof(node, "z")]
            out[np.ix_(idx, idx)] += k
        return out

    # ------------------------------------------------------------------ eigen-analysis
    def natural_frequencies(self, k_bearing, speed: float = 0.0, n: int = 6) -> np.ndarray:
        """Lowest ``n`` undamped natural frequencies [Hz] on isotropic bearing springs.

        ``k_bearing`` [N/m]: one value for all bearings or one per bearing, on y and z.
        ``speed`` [rad/s]: with gyroscopics (state-space form) when non-zero; each whirl
        branch appears once (forward and backward split). Rigid-body modes give 0.0 (anything
        below 1e-6 times the highest natural frequency is numerically zero).
        """
        kb = np.broadcast_to(np.asarray(k_bearing, dtype=float), (len(self.bearing_nodes),))
        K = self.K + self.bearing_matrix([np.eye(2) * k for k in kb]) if len(kb) else self.K
        tol = zero_tol(self.M, K)
        if speed == 0.0:
            import scipy.linalg  # here: a scene or a --help that never asks for modes skips scipy

            w = np.sqrt(np.clip(scipy.linalg.eigh(K, self.M, eigvals_only=True), 0.0, None))
            w[w < tol] = 0.0
            return w[:n] / (2.0 * math.pi)
        lam = state_eigvals(self.M, K, speed * self.G)
        n_zero = int(np.sum(np.abs(lam) < tol)) // 2
        w = np.sort(lam.imag[(lam.imag > 0.0) & (np.abs(lam) >= tol)])
        return np.concatenate([np.zeros(n_zero), w])[:n] / (2.0 * math.pi)

    def modes(self, speed: float, bearing_K=None, bearing_C=None, n: int | None = None):
        """Damped modes in state space at ``speed`` [rad/s] with linear bearings.

        ``bearing_K`` [N/m], ``bearing_C`` [N s/m]: one 2x2 for all bearings or one per bearing
        (Lund sign: bearing force = -K q - C qd at (y, z) of the node). Includes the shaft's
        proportional damping ``C = beta K`` and the gyroscopic term ``speed * G``.

        Returns ``(freq_hz, log_dec, shapes)``: damped natural frequencies [Hz] (> 0, sorted),
        logarithmic decrements ``-2 pi Re(lam) / Im(lam)`` (negative = unstable), and complex
        displacement shapes (columns, n_dof x n_modes, largest entry 1). Only oscillatory
        modes are kept: ``Im(lam) > 1e-3 |lam|`` (log_dec below about 6000). That drops real
        (overdamped) eigenvalues and the slow-turning nearly real pairs into which speed * G
        splits two equal overdamped roots. Rigid-body modes of an unsupported rotor (|lam| below
        1e-6 times the highest undamped natural frequency, numerically zero) are dropped too.
        ``n`` keeps the lowest n.
        """
        Kt = self.K + self.bearing_matrix(bearing_K)
        Ct = self.C + self.bearing_matrix(bearing_C) + speed * self.G
        lam, vec = state_eig(self.M, Kt, Ct)
        keep = (lam.imag > OSCILLATORY * np.abs(lam)) & (np.abs(lam) >= zero_tol(self.M, Kt))
        lam, vec = lam[keep], vec[: self.n_dof, keep]
        return modal_table(lam, vec, n)

    def whirl(self, shape: np.ndarray, node: int, *, tilt: bool = False) -> float:
        """Whirl direction of a complex mode shape at 0-based ``node``, in [-1, 1].

        With y = Re(Y e^{lam t}), z = Re(Z e^{lam t}), Im(lam) > 0, the orbit splits into a
        forward circle of radius |Y + iZ|/2 (from +y toward +z) and a backward one of radius
        |Y - iZ|/2; returns (f - b) / (f + b): +1 pure forward, -1 pure backward, 0 straight line.
        ``tilt=True`` uses the tip of the tilted axis instead, (dy/dx, dz/dx) = (theta_z, -theta_y).
        """
        if tilt:
            Y, Z = shape[self.dof(node, "tz")], -shape[self.dof(node, "ty")]
        else:
            Y, Z = shape[self.dof(node, "y")], shape[self.dof(node, "z")]
        f, b = abs(Y + 1j * Z), abs(Y - 1j * Z)
        return float((f - b) / (f + b)) if f + b > 0 else 0.0

