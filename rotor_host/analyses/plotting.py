"""The one place figures are made and saved: matplotlib without a screen (Agg), one dpi,
the folder made, the figure closed so long sweeps do not hold hundreds of them."""

from __future__ import annotations

from pathlib import Path

DPI = 110


def pyplot():
    """matplotlib.pyplot on the Agg backend (imported on first use: a run that plots nothing
    never imports matplotlib)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path) -> Path:
    """Lay out, write and close ``fig``; returns the path written (atomically, and to the rescue
    folder when the one asked refuses it: ``bearing_fmu.io.outputs``)."""
    from bearing_fmu.io.outputs import write_with

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    try:
        return write_with(path, lambda f: fig.savefig(f, dpi=DPI, format=path.suffix[1:] or "png"))
    finally:
        pyplot().close(fig)
