"""The Reynolds internal's parts that sit with the internals: its compiled force (``force``: the
solver's kernel for a host's compiled loop). The solver itself is ``physics.solver.reynolds``."""
