"""Side by side, in one run (issue 15): mx's Python bindings against
Pinocchio's (PyPI `pin`) and `bvhio`.

    target/pyenv/bin/pip install pin bvhio     # the peers (not test dependencies)
    target/pyenv/bin/python python/bench/bench.py [--states 10000]

1. Inverse dynamics on the shared human44 and UR5 URDFs for N random states:
   pin.rnea in a Python loop, mx per call in a loop, mx batched (one call).
2. The 1,901-frame shared dance BVH into a [frames, channels] array:
   mx.load(...).sample(frame times) against bvhio.
3. A 60-DOF x 7,200-frame motion to NumPy: time, and how many bytes the
   result owns beyond the array itself (0 = written once, no copy).

Median of 5 repetitions; µs per state. Reads $MX_SHARED/data (default ../shared).
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

# NumPy's OpenBLAS starts worker threads at import that spin waiting for work
# (12 % of the samples of a per-call loop under perf); on a 2-core machine
# they take a core from whatever is timed (pin per call on UR5: 2.8 µs with
# them, 1.75 µs without). Nothing timed here uses BLAS, so one thread is the
# fair setting for every peer.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import mx  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
DATA = Path(os.environ.get("MX_SHARED", REPO.parent / "shared")) / "data"


def median_time(f, reps=5):
    ts = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts)


def states(nq, n, seed):
    rng = np.random.default_rng(seed)
    return (
        rng.uniform(-1.0, 1.0, (n, nq)),
        rng.uniform(-2.0, 2.0, (n, nq)),
        rng.uniform(-5.0, 5.0, (n, nq)),
    )


def bench_dynamics(n, reps=9):
    """pin in a loop, mx per call and mx batched, timed in turn within each
    repetition, so that the ratios compare runs under the same machine load:
    the table gives the median time of each and the median of the per-repetition ratios."""
    try:
        import pinocchio as pin
    except ImportError:
        pin = None
        print("pin is not installed: Pinocchio columns left out (pip install pin)")
    rows = []
    for name in ("human44.urdf", "ur5_robot.urdf"):
        urdf = DATA / "reference" / name
        body = mx.Body.from_urdf(urdf)
        q, v, a = states(body.nq, n, 1)

        def timed(f):
            t = time.perf_counter()
            f()
            return (time.perf_counter() - t) / n * 1e6

        mx_call = lambda: [body.inverse_dynamics(q[k], v[k], a[k]) for k in range(n)]
        mx_batch = lambda: body.inverse_dynamics(q, v, a)
        row = {"model": name, "nq": body.nq}
        if pin is not None:
            model = pin.buildModelFromUrdf(str(urdf))
            data = model.createData()
            names = [model.names[j] for j in range(1, model.njoints)]
            # mx's coordinates in Pinocchio's order (the same here, checked)
            perm = [body.coordinates.index(nm) for nm in names]
            qp, vp, ap = q[:, perm], v[:, perm], a[:, perm]
            pin_call = lambda: [pin.rnea(model, data, qp[k], vp[k], ap[k]) for k in range(n)]
            tau_pin = np.array([pin.rnea(model, data, qp[k], vp[k], ap[k]) for k in range(min(n, 200))])
            tau_mx = body.inverse_dynamics(q[:200], v[:200], a[:200])[:, perm]
            row["max_rel_diff"] = float(np.max(np.abs(tau_pin - tau_mx)) / max(1.0, np.max(np.abs(tau_pin))))
        times = {"pin_call": [], "mx_call": [], "mx_batch": []}
        for _ in range(reps):
            if pin is not None:
                times["pin_call"].append(timed(pin_call))
            times["mx_call"].append(timed(mx_call))
            times["mx_batch"].append(timed(mx_batch))
        for k, ts in times.items():
            if ts:
                row[k] = statistics.median(ts)
        if pin is not None:
            for k in ("mx_call", "mx_batch"):
                ratios = [p / m for p, m in zip(times["pin_call"], times[k])]
                row["ratio_" + k] = (statistics.median(ratios), min(ratios), max(ratios))
        rows.append(row)
    print(f"\n## Inverse dynamics, {n} random states, µs per state (median of {reps} repetitions, each timing all three in turn)\n")
    print("| model | pin per call | mx per call | mx batched | pin/mx per call (min–max) | pin/mx batched (min–max) | max rel. diff |")
    print("|---|---|---|---|---|---|---|")
    fmt = lambda x: f"{x:.2f}" if x is not None else "—"
    rfmt = lambda r: f"{r[0]:.2f} ({r[1]:.2f}–{r[2]:.2f})" if r else "—"
    for r in rows:
        print(
            f"| {r['model']} (nq {r['nq']}) | {fmt(r.get('pin_call'))} | {r['mx_call']:.2f} | {r['mx_batch']:.2f} | "
            f"{rfmt(r.get('ratio_mx_call'))} | {rfmt(r.get('ratio_mx_batch'))} | "
            f"{r.get('max_rel_diff', float('nan')):.1e} |"
        )


def bench_bvh():
    path = DATA / "mocap" / "bandai1_dance-short_normal_001.bvh"

    def with_mx():
        m = mx.load(path)
        return m.sample(m.frame_times())

    arr = with_mx()
    t_mx = median_time(with_mx)
    print(f"\n## {path.name} ({arr.shape[0]} frames x {arr.shape[1]} channels) into an array\n")
    print(f"mx.load(...).sample(frame times): {t_mx * 1e3:.1f} ms")
    try:
        import bvhio
    except ImportError:
        print("bvhio is not installed (pip install bvhio)")
        return

    def with_bvhio():
        bvh = bvhio.readAsBvh(str(path))
        cols = []
        for joint, _, _ in bvh.Root.layout():
            cols.append(np.array([[*k.Position, *k.Rotation] for k in joint.Keyframes]))
        return np.concatenate(cols, axis=1)

    ref = with_bvhio()
    t_b = median_time(with_bvhio, reps=3)
    print(f"bvhio.readAsBvh + keyframes to an array ({ref.shape}): {t_b * 1e3:.1f} ms")
    print(f"ratio bvhio / mx: {t_b / t_mx:.1f}x")


def bench_copy():
    rng = np.random.default_rng(3)
    t = np.arange(7200) / 120.0
    v = rng.normal(size=(7200, 60))
    m = mx.Motion.from_array([f"c{k}" for k in range(60)], t, v)
    x = m.sample(t)
    t_s = median_time(lambda: m.sample(t))
    owner = x
    while isinstance(owner.base, np.ndarray):
        owner = owner.base  # the 1-D array over mx's own buffer (its base is that Vec)
    extra = owner.nbytes - x.nbytes
    print("\n## 60 DOFs x 7,200 frames to NumPy\n")
    print(f"sample: {t_s * 1e3:.1f} ms; result {x.nbytes} bytes, owning buffer {owner.nbytes} bytes "
          f"(extra {extra}); F-contiguous view of the one buffer mx wrote: {x.flags.f_contiguous}")
    assert np.array_equal(x, v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--states", type=int, default=10000)
    args = ap.parse_args()
    print(
        f"python {sys.version.split()[0]}, numpy {np.__version__}, {os.cpu_count()} cores, "
        f"OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}"
    )
    bench_dynamics(args.states)
    bench_bvh()
    bench_copy()


if __name__ == "__main__":
    main()
