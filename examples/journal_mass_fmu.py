"""A rigid journal of mass m as a pythonfmu FMI 2.0 co-simulation slave: the partner of the
bearing FMU in a two-FMU co-simulation (tests/test_libcosim.py, docs/libcosim.md).

The journal centre (y, z) moves under a static external load (Wy, Wz) (weight: (0, -m g)),
the film force (Fy, Fz) from the bearing FMU and, only if asked for, a linear damping to
ground ``c`` (default 0: the only damping is the physical film damping of the bearing):

    m y'' = Fy + Wy - c y',   m z'' = Fz + Wz - c z'

``do_step`` holds the input force constant over the communication step (what an explicit
master gives it) and integrates with ``n_sub`` substeps of semi-implicit (symplectic) Euler;
the outputs y, z, vy, vz are the state at the end of the step. At rest the state is fixed
exactly where F + W = 0, so the settled position does not depend on the integrator, only the
way there does. Parameters: m, Wy, Wz, c, n_sub and the initial state y0, z0, vy0, vz0.

Build (plain pythonfmu, no bearing_fmu code goes into the FMU):

    pythonfmu build -f examples/journal_mass_fmu.py            # -> JournalMass.fmu
    python examples/journal_mass_fmu.py -o JournalMass.fmu     # same, plus the exit-crash fix

``build()`` (the second form) calls pythonfmu's ``FmuBuilder.build_FMU`` and then applies
``bearing_fmu.fmu.build.patch_linux_binary`` to the Linux binary: pythonfmu 0.7.0's library
releases its interpreter state twice at process exit (see docs/fmu.md), and a host that
loads this FMU as well as the bearing FMU would otherwise abort at exit in some runs.
"""

from __future__ import annotations

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status


class JournalMass(Fmi2Slave):
    """Rigid journal (point mass) under a static load and the bearing's film force."""

    description = "Rigid journal of mass m under a static load (Wy, Wz) and the bearing film force (Fy, Fz)"
    author = "bearing_fmu examples"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=0.2, step_size=1e-5)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        # parameters (SI). Default: the paper rotor's bearing load 16.7 N carried by its own mass
        self.m = 16.7 / 9.81
        self.Wy = 0.0
        self.Wz = -16.7
        self.c = 0.0
        self.n_sub = 4
        self.y0 = self.z0 = self.vy0 = self.vz0 = 0.0
        # inputs: the film force on the journal
        self.Fy = self.Fz = 0.0
        # outputs: the journal state
        self.y = self.z = self.vy = self.vz = 0.0
        self._stepped = False

        par = dict(causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed)
        for name, desc in (("m", "journal mass [kg]"),
                           ("Wy", "static external load on the journal, horizontal [N]"),
                           ("Wz", "static external load on the journal, vertical (weight < 0) [N]"),
                           ("c", "linear damping to ground [N.s/m] (0: film damping only)"),
                           ("y0", "initial y [m]"), ("z0", "initial z [m]"),
                           ("vy0", "initial vy [m/s]"), ("vz0", "initial vz [m/s]")):
            self.register_variable(Real(name, description=desc, **par))
        self.register_variable(Integer("n_sub", description="semi-implicit Euler substeps per step", **par))
        for name in ("Fy", "Fz"):
            self.register_variable(Real(name, causality=Fmi2Causality.input, variability=Fmi2Variability.continuous,
                                        description=f"film force on the journal, {name[1]} [N]"))
        for name, desc in (("y", "journal centre displacement, horizontal [m]"),
                           ("z", "journal centre displacement, vertical (up) [m]"),
                           ("vy", "journal centre velocity, horizontal [m/s]"),
                           ("vz", "journal centre velocity, vertical [m/s]")):
            self.register_variable(Real(name, causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
                                        description=desc))

    def _initial_state(self):
        if not self._stepped:  # outputs at the start time = the initial-state parameters
            self.y, self.z, self.vy, self.vz = self.y0, self.z0, self.vy0, self.vz0

    def enter_initialization_mode(self):
        self._initial_state()

    def exit_initialization_mode(self):
        self._initial_state()

    def do_step(self, current_time, step_size):
        if not (self.m > 0.0 and self.n_sub >= 1 and step_size > 0.0):
            self.log(f"journal mass: bad m = {self.m!r}, n_sub = {self.n_sub!r} or step {step_size!r}",
                     Fmi2Status.error)
            return False
        self._stepped = True
        n = int(self.n_sub)
        dt = step_size / n
        inv_m = 1.0 / self.m
        fy, fz = self.Fy + self.Wy, self.Fz + self.Wz  # held over the step
        c = self.c
        y, z, vy, vz = self.y, self.z, self.vy, self.vz
        for _ in range(n):
            vy += dt * (fy - c * vy) * inv_m
            vz += dt * (fz - c * vz) * inv_m
            y += dt * vy
            z += dt * vz
        self.y, self.z, self.vy, self.vz = y, z, vy, vz
        return True


def build(output="JournalMass.fmu"):
    """Build this file into an FMU with pythonfmu and fix pythonfmu 0.7.0's exit crash in the
    Linux binary (``bearing_fmu.fmu.build.patch_linux_binary``). Returns the FMU path."""
    import os
    import sys
    import zipfile
    from pathlib import Path

    from pythonfmu import FmuBuilder

    from bearing_fmu.fmu.build import patch_linux_binary

    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    before, old_path = set(sys.modules), list(sys.path)
    try:
        FmuBuilder.build_FMU(Path(__file__).resolve(), dest=output)
    finally:
        # pythonfmu imported this file as the module 'journal_mass_fmu' and put its folder on
        # sys.path; an FMU loaded later in this process must import its own bundled copy
        for name in set(sys.modules) - before:
            if name == "journal_mass_fmu":
                del sys.modules[name]
        sys.path[:] = old_path
    tmp = output.with_name(output.name + ".tmp")
    with zipfile.ZipFile(output) as zin, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename.startswith("binaries/linux64/") and item.filename.endswith(".so"):
                data, note = patch_linux_binary(data)
                if not note.startswith(("patched", "already")):
                    raise RuntimeError(f"{item.filename}: {note}")
            zout.writestr(item.filename, data)
    os.replace(tmp, output)
    return output


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description="build the journal-mass FMU")
    ap.add_argument("-o", "--output", default="JournalMass.fmu")
    print("wrote", build(ap.parse_args().output))
