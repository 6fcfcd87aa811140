"""Closed loop: a scene run (via direct) with an internal injected by monkeypatching
rotor_host.scene._direct_internal, compared with the saved Reynolds run of the same scene."""
import time
from pathlib import Path
import numpy as np
import rotor_host.scene as RS
from rotor_host.report import errors_against
from rotor_host.compare import late_max_eccentricity, envelope_error
from sbasis import ROOT, SCENES, SURR

REF = ROOT / "out" / "shape_basis" / "ref"


def reference(scene_name, ref_dir=REF):
    """The Reynolds run of the scene (called directly), saved once in ref_dir."""
    path = Path(ref_dir) / f"{scene_name}_reynolds.npz"
    if not path.is_file():
        sc = RS.load_scene(SCENES / f"{scene_name}.toml").with_internal("reynolds", via="direct")
        run = RS.run_scene(sc, None, progress=False)
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(path, **run.arrays)
    return dict(np.load(path))


def run_with(scene_name, make_internal, tend=None, ref_dir=REF):
    sc = RS.load_scene(SCENES / f'{scene_name}.toml')
    kw = dict(via='direct', surrogate=SURR / 'paper_22hz_16.7N.json')  # any existing file; never loaded
    if tend is not None:
        kw['t_end_s'] = tend
    sc = sc.with_internal('taylor', **kw)
    made = []
    orig = RS._direct_internal
    def inj(scene, params, load):
        i = make_internal(params, load)
        made.append(i)
        return i
    RS._direct_internal = inj
    t0 = time.perf_counter()
    try:
        run = RS.run_scene(sc, None, progress=False, work_dir=ROOT / 'out' / 'shape_basis' / 'fmu')
    finally:
        RS._direct_internal = orig
    wall = time.perf_counter() - t0
    ref = reference(scene_name, ref_dir)
    a = run.arrays
    e = errors_against(ref, a)
    m = run.meta
    out = {'status': m['status'], 't_reached': m['t_reached_s'], 'msg': m['message'][:200], 'wall_s': wall,
           'orbit_rms_pct_cr': e['orbit_rms_pct_cr'], 'orbit_max_pct_cr': e['orbit_max_pct_cr'],
           'force_nrmse_pct': e['force_nrmse_pct'], 'max_ecc': max(m['max_eccentricity']),
           'late_ecc': late_max_eccentricity(a), 'evals': sum(getattr(i, 'n_eval', 0) for i in made)}
    try:
        out['envelope_rms_pct_cr'] = envelope_error(ref, a, sc.speed_hz)
    except Exception as exc:  # noqa
        out['envelope_rms_pct_cr'] = None
    return out


def fmt(o):
    s = f"{o['status']} t={o['t_reached']:.4f}s orbit RMS {o['orbit_rms_pct_cr']:.3f} % CR (max {o['orbit_max_pct_cr']:.2f}), "
    s += f"force NRMSE {o['force_nrmse_pct']:.2f} %, max ecc {o['max_ecc']:.4f}, late ecc {o['late_ecc'] or float('nan'):.4f}, wall {o['wall_s']:.1f}s"
    s += f", envelope {o.get('envelope_rms_pct_cr') or float('nan'):.3f}"
    if o['status'] != 'ok':
        s += f" [{o['msg']}]"
    return s
