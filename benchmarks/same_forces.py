"""Bit-identity check of the Taylor internal across code versions: Taylor.force and
force_and_jacobian of every shipped surrogate (rotor_host/bundled/surrogates/*.json) at 400 states inside
its fitted domain (the expansion point, then seeded random states over its position and
velocity discs), saved from one checkout and compared exactly (==, bytes) with another's.

Run ``save`` with the checkout to test as the working directory (its code is imported, also
an older one whose load_surrogate still lives in bearing_fmu.internals.taylor), e.g. against main:

    git worktree add --detach ../base main
    (cd ../base && python /path/to/benchmarks/same_forces.py save /tmp/base.npz)
    python benchmarks/same_forces.py save /tmp/new.npz
    python benchmarks/same_forces.py compare /tmp/base.npz /tmp/new.npz   # exit 0: all identical
"""
import math
import sys
from pathlib import Path

import numpy as np


def states(sur, tay, n, seed):
    """n states of the fitted domain: the expansion point, then seeded random ones inside it."""
    rng = np.random.default_rng(seed)
    d = sur.domain
    out = [(sur.y0, sur.z0, 0.0, 0.0)]
    while len(out) < n:
        a, b = rng.uniform(0, 2 * math.pi, 2)
        r, v = d.pos_radius * math.sqrt(rng.uniform()), d.v_max * math.sqrt(rng.uniform())
        y = sur.y0 + (d.pos_center[0] + r * math.cos(a)) * sur.pos_scale
        z = sur.z0 + (d.pos_center[1] + r * math.sin(a)) * sur.pos_scale
        x = (y, z, v * math.cos(b) * sur.vel_scale, v * math.sin(b) * sur.vel_scale)
        # the bounds (Taylor.domain_distance before the nearest-neighbour guard), so both checkouts draw the same states
        if getattr(tay, "bounds_distance", tay.domain_distance)(*x) <= 1e-12:
            out.append(x)
    return np.array(out)


def save(out):
    sys.path.insert(0, str(Path.cwd()))
    from bearing_fmu.internals.taylor import Taylor
    try:
        from bearing_fmu.surrogates.surrogate import load_surrogate
    except ImportError:  # a checkout before the split of bearing_fmu/internals/taylor.py
        from bearing_fmu.internals.taylor import load_surrogate
    import bearing_fmu
    print("code:", bearing_fmu.__file__)
    res = {}
    for f in sorted(Path("rotor_host/bundled/surrogates").glob("*.json")):
        sur = load_surrogate(f)
        tay = Taylor(sur)
        st = states(sur, tay, 400, 0)
        F = np.array([tay.force(*x, sur.omega) for x in st])
        J = []
        for x in st:
            f_, dq, dv = tay.force_and_jacobian(*x, sur.omega)
            J.append(np.concatenate([f_, dq.ravel(), dv.ravel()]))
        res[f.stem + "/states"] = st
        res[f.stem + "/force"] = F
        res[f.stem + "/jac"] = np.array(J)
        print(f.name, len(st), "states")
    np.savez(out, **res)


def compare(a, b):
    A, B = np.load(a), np.load(b)
    assert sorted(A.files) == sorted(B.files), (A.files, B.files)
    ok = True
    for k in sorted(A.files):
        same = A[k].shape == B[k].shape and np.array_equal(A[k], B[k]) and A[k].tobytes() == B[k].tobytes()
        ok &= same
        print(f"{k}: {A[k].shape} {'identical' if same else 'DIFFERENT'}")
    print("ALL BIT-IDENTICAL" if ok else "DIFFERENCES FOUND")
    return 0 if ok else 1


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "save":
        save(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        sys.exit(__doc__)
