"""``rotor-host``: run scenes, compare internals, run the paper's main job, fit scene-trained surrogates,
find a rotor's stability threshold (Campbell diagram), sweep a scene over speeds or unbalances on Dask.

Every option of every command is parsed in this package, and nowhere else: ``transient`` (the
commands on scenes in time), ``linear`` (the commands on the linearised rotor), ``common`` (the options
they share). Each command hands plain values (or a ``SceneOverrides``) to a function of the package
(``rotor_host.analyses.*.command``, ``report.run_and_report``, ``compare.compare``), which a script may
call the same way."""

from __future__ import annotations

import argparse

from bearing_fmu.cli import Parser, add_debug_flag
from bearing_fmu.internals.warmup import announce_compiling
from bearing_fmu.io.exits import EXIT_CODES, run_command
from bearing_fmu.io.fixed_costs import command_line, watch_command

from . import linear, transient
from .common import bearing_swap, internal_choices, scene_from_args

__all__ = ["bearing_swap", "build_parser", "internal_choices", "main", "scene_from_args"]

# the commands in the order ``rotor-host --help`` lists them
COMMANDS = (transient.add_run, transient.add_compare, transient.add_paper, transient.add_fit, transient.add_dt_study,
            transient.add_waterfall, transient.add_limit_cycle, linear.add_stability, transient.add_sweep,
            linear.add_response, linear.add_ucs, linear.add_level1, linear.add_api_report,
            transient.add_linear_vs_runup)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="rotor-host", description=__doc__, epilog=EXIT_CODES,
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    for add in COMMANDS:
        add(sub)
    add_debug_flag(parser, sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    watch_command()  # the command's fixed costs (imports, kernels, FMUs) timed apart from its work
    args = build_parser().parse_args(argv)
    announce_compiling()  # an installation's first compilation of a kernel: one line on stderr
    code = run_command("rotor-host", args)  # exit codes, interrupts, --debug: bearing_fmu.io.exits
    if code == 0 and not getattr(args, "own_fixed_costs", False):  # (sweep prints its own, with its workers')
        print(command_line(), flush=True)
    return code
