"""The rotor's matrices M, K, G, C assembled from its elements and disks: in band storage at any
size (O(n) memory), dense when a caller asks for them."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from . import fe
from .parts import Disk, Material, ShaftElement

BAND = 7  # half-bandwidth of every assembled matrix: an element couples two nodes' 4 DOFs each
DENSE_MAX_DOF = 1000  # Rotor.matrices(): dense up to this size (8 MB a matrix), sparse above


def assemble_bands(elements: Sequence[ShaftElement], disks: Sequence[Disk], material: Material) -> dict:
    """M, K, G, C of a chain of elements (element i joins nodes i, i+1) in row-wise band storage
    (``rotor_host.integrate.banded``: B[i, j - i + BAND] = A[i, j]), O(n) memory at any size. Each
    entry sums its element and disk terms in the order a dense assembly adds them, so the dense
    matrices made from these are the same to the last bit."""
    n_nodes = len(elements) + 1
    n = fe.DOFS_PER_NODE * n_nodes
    w = BAND
    B = {k: np.zeros((n, 2 * w + 1)) for k in ("M", "K", "G")}
    # the band column of an element's entry (a, b) at rows 4i + a: b - a + w
    cols8 = np.arange(8)[None, :] - np.arange(8)[:, None] + w
    rows8 = np.arange(8)[:, None] + np.zeros((1, 8), dtype=int)
    for i, e in enumerate(elements):
        m = fe.beam_matrices(e.length, e.od, e.id, material.E, material.density, material.poisson)
        for k in ("M", "K", "G"):
            B[k][4 * i + rows8, cols8] += m[k]
    cols4 = cols8[:4, :4]
    rows4 = rows8[:4, :4]
    for d in disks:
        mass, Id, Ip = fe.disk_properties(d.od, d.id, d.width, material.density)
        m = fe.disk_matrices(mass, Id, Ip)
        for k in ("M", "G"):
            B[k][4 * d.node + rows4, cols4] += m[k]
    B["C"] = material.beta * B["K"]
    return B


def assemble(elements: Sequence[ShaftElement], disks: Sequence[Disk], material: Material):
    """Global dense (M, K, G, C) for a chain of elements (element i joins nodes i, i+1)."""
    B = assemble_bands(elements, disks, material)
    from ..integrate.banded import from_band  # numba's import only when a matrix is asked for (not for --help)

    return tuple(from_band(B[k]) for k in ("M", "K", "G", "C"))

