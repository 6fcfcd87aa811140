"""The parts of a rotor file: its keys per table (with the kind of value each takes), the shaft's
material, its Timoshenko elements and rigid disks, and the checks of node numbers and diameters
that ``rotor.Rotor.from_mapping`` applies while it reads a file."""

from __future__ import annotations

from dataclasses import dataclass

from bearing_fmu.io.schema import Choice, FileName, Key, List, Number, Table, Tables, Text

from . import fe

# the keys of a rotor file, per table, with the kind of value each takes (docs/file-formats.md
# shows these lists; Rotor.from_mapping checks a file against them once)
POSITIVE = Number(0.0, exclusive_minimum=True)
NODE = Number(integer=True, words="an integer node number")  # its range: the loader, against the rotor
MATERIAL_KEYS = (
    # upper bounds past every solid (diamond 1220 GPa, osmium 22 590 kg/m^3), with room for a
    # smeared-on mass: a value beyond is a unit slip, named here, not an eccentricity of 1e291
    Key("E_GPa", "elastic modulus [GPa]", kind=Number(0.0, 1e4, exclusive_minimum=True)),
    Key("density_kg_m3", "density [kg/m^3]", kind=Number(0.0, 1e5, exclusive_minimum=True)),
    Key("poisson", "Poisson's ratio (shear modulus and shear coefficient)",
        kind=Number(-1.0, 0.5, exclusive_minimum=True, exclusive_maximum=True)),
    Key("damping_beta_s", "stiffness-proportional damping C = beta K [s]", 0.0, kind=Number(0.0)),
)
ELEMENT_KEYS = (
    Key("od_mm", "outer diameter [mm]", kind=POSITIVE),
    Key("length_mm", "length [mm]", kind=POSITIVE),
    Key("id_mm", "inner diameter [mm]", 0.0, "a finite number >= 0 and < od_mm", kind=Number(0.0)),
    Key("nodes", "the nodes it joins, 1-based", None, "[i, i + 1] for element i", kind=List(NODE, 2)),
    Key("name", "label", None, kind=Text()),
)
DISK_KEYS = (
    Key("node", "node it sits on, 1-based", allowed="1..number of nodes", kind=NODE),
    Key("od_mm", "outer diameter [mm]", kind=POSITIVE),
    Key("width_mm", "axial width [mm]", kind=POSITIVE),
    Key("id_mm", "bore diameter [mm]", 0.0, "a finite number >= 0 and < od_mm", kind=Number(0.0)),
    Key("name", "label", None, kind=Text()),
)
BEARING_ENTRY_KEYS = (
    Key("node", "node the journal is at, 1-based; one bearing per node", allowed="1..number of nodes", kind=NODE),
    Key("bearing", "bearing file, relative to the rotor file (keys: [bearing] below)", kind=FileName()),
    Key("name", "label", None, kind=Text()),
)
STAGE_KEYS = (  # API 617's anticipated aerodynamic cross-coupling (rotor_host.analyses.response.level1)
    Key("node", "node the stage (impeller or blade row) sits on, 1-based", allowed="1..number of nodes", kind=NODE),
    Key("power_kw", "the stage's rated power [kW]", kind=POSITIVE),
    Key("density_ratio", "discharge over suction gas density of the stage (centrifugal)", kind=POSITIVE),
    Key("diameter_mm", "impeller diameter (axial: blade pitch diameter) [mm]", kind=POSITIVE),
    Key("restrictive_mm", "the smaller of diffuser and impeller discharge width (axial: effective blade height) [mm]",
        kind=POSITIVE),
    Key("kind", "centrifugal (B_c = 3) or axial (B_t = 1.5)", "centrifugal", kind=Choice(("centrifugal", "axial"))),
    Key("name", "label", None, kind=Text()),
)
ROTOR_KEYS = (
    Key("elements", "the shaft's beam elements, in order ([[elements]] or an array of inline tables)",
        kind=Tables(ELEMENT_KEYS, nonempty=True)),
    Key("material", "shaft and disk material ([material])", kind=Table(MATERIAL_KEYS)),
    Key("name", "label", None, kind=Text()),
    Key("description", "free text", None, kind=Text()),
    Key("disks", "rigid disks ([[disks]])", None, kind=Tables(DISK_KEYS)),
    Key("bearings", "bearings ([[bearings]]): where they sit and which bearing file", None,
        kind=Tables(BEARING_ENTRY_KEYS)),
    Key("stages", "compressor or turbine stages ([[stages]]) for API 617's Level I stability check", None,
        kind=Tables(STAGE_KEYS)),
)


class RotorFileError(ValueError):
    """A rotor file (or mapping) is malformed; the message names the file, entry and key."""


@dataclass(frozen=True)
class Material:
    """Isotropic shaft/disk material. E [Pa], density [kg/m^3], Poisson ratio, beta [s] (C = beta K)."""

    E: float
    density: float
    poisson: float
    beta: float = 0.0


@dataclass(frozen=True)
class ShaftElement:
    """Hollow circular Timoshenko element between nodes ``node`` and ``node + 1`` (0-based). SI units."""

    length: float
    od: float
    id: float = 0.0


@dataclass(frozen=True)
class Disk:
    """Rigid hollow disk at a node (0-based): bore ``id``, outer diameter ``od``, width [m]."""

    node: int
    od: float
    id: float
    width: float


def element_mass(e: ShaftElement, density: float) -> float:
    return density * fe.area(e.od, e.id) * e.length




def node_index(value: int, n_nodes: int, what: str) -> int:
    """A 1-based node number (its type checked by the schema) against the rotor's nodes, 0-based."""
    if not 1 <= value <= n_nodes:
        raise RotorFileError(f"{what} = {value} is outside the rotor's nodes 1..{n_nodes}")
    return value - 1


def diameters_m(table: dict, what: str) -> tuple[float, float]:
    """(od, id) [m] of a checked element or disk table; the bore must be smaller than the outside."""
    od, idm = table["od_mm"], table["id_mm"]
    if idm >= od:
        raise RotorFileError(f"{what} id_mm = {idm:g} must be < od_mm = {od:g}")
    return od / 1e3, idm / 1e3

