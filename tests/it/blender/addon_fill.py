"""The mx add-on in real Blender (bpy 5 from PyPI), run by
tests/it/blender_addon.rs with a Python that has `bpy`.

    python addon_fill.py ZIP MOCAP_DIR check   # install, fill walk -> run, check it
    python addon_fill.py ZIP MOCAP_DIR timing  # the operator against mx.sp on 1 s gaps of walks

Prints `CHECK name value` lines (the Rust side asserts on them) and `TIME`
lines; exits non-zero on an exception. Frames are Blender's (1 = a BVH's
first frame); the add-on's own seconds are (frame - first) / fps.
"""

import cProfile
import io
import math
import os
import pstats
import sys
import time

import bpy
import numpy as np

ZIP, MOCAP, MODE = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:4]
WALK, RUN = "bandai2_walk_normal_001.bvh", "bandai2_run_normal_001.bvh"
GAP = 30  # frames: 1 s at the Bandai clips' 30 Hz
TIMING_CLIPS = ["bandai1_walk_normal_001.bvh", "bandai2_walk_normal_001.bvh", "cmu_131_01_start_walk_stop.bvh"]


def check(name, value):
    print("CHECK", name, repr(float(value)), flush=True)


def install():
    """The zip through Blender's extension system, as a user installs it."""
    bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
    import importlib

    addon = importlib.import_module("bl_ext.user_default.mx_transitions")
    assert hasattr(bpy.ops.mx, "fill_transition"), "the operator did not register"
    import mx  # the bundled wheel

    return addon, mx


def units(mx, path):
    """mx's metres per file unit for the clip (so Blender imports in metres)."""
    return mx.Interpreter().eval(f"bvh_info({path!r}).metres_per_unit")


def import_bvh(mx, name):
    path = os.path.join(MOCAP, name)
    bpy.ops.import_anim.bvh(
        filepath=path, global_scale=units(mx, path), update_scene_fps=True, rotate_mode="NATIVE"
    )
    ob = bpy.context.view_layer.objects.active
    return ob, ob.animation_data.action


def keys(action):
    """{(path, index): (frames, values)} of every curve (float64 of float32)."""
    from bpy_extras import anim_utils

    bag = anim_utils.action_get_channelbag_for_slot(action, action.slots[0])
    out = {}
    for c in bag.fcurves:
        co = np.empty(2 * len(c.keyframe_points), dtype=np.float32)
        c.keyframe_points.foreach_get("co", co)
        out[(c.data_path, c.array_index)] = (co[0::2].astype(float), co[1::2].astype(float))
    return out


def fps():
    s = bpy.context.scene
    return s.render.fps / s.render.fps_base


def fresh():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def run_check():
    addon, mx = install()
    rig_mod = addon.rig
    fresh()
    walk_ob, walk = import_bvh(mx, WALK)
    run_ob, run = import_bvh(mx, RUN)
    # The run's armature is the walk's skeleton again: keep one.
    bpy.data.objects.remove(run_ob)
    bpy.context.view_layer.objects.active = walk_ob
    walk_ob.select_set(True)
    f = fps()
    kw, kr = keys(walk), keys(run)

    # The rig mapping gives back the files' values (float32 apart): the
    # add-on's motion is mx's clip.
    paths = {p for (p, _) in kw}
    rig = rig_mod.Rig(walk_ob, paths)
    wf = kw[next(iter(kw))][0].astype(int)
    get = lambda p, i: kw[(p, i)][1] if (p, i) in kw else None
    mapped = rig.to_mx(get)
    clip = mx.load(os.path.join(MOCAP, WALK))
    ref = clip.sample((wf - wf[0]) * clip.frame_time())
    cols = [clip.dofs.index(d) for d in rig.dofs]
    diff = mapped - ref[:, cols]
    rot = rig.rotation_columns()
    diff[:, rot] -= 2 * np.pi * np.round(diff[:, rot] / (2 * np.pi))
    check("rig_vs_file_max", np.abs(diff).max())

    t0 = time.perf_counter()
    res = bpy.ops.mx.fill_transition(source="ACTIONS", first=walk.name, second=run.name, gap=GAP, root="AUTO")
    check("operator_seconds", time.perf_counter() - t0)
    assert res == {"FINISHED"}, res
    new = walk_ob.animation_data.action
    assert new.name not in (walk.name, run.name), new.name
    kn = keys(new)
    a0, a1 = int(wf[0]), int(wf[-1])
    rf = kr[next(iter(kr))][0].astype(int)
    b0 = a1 + GAP
    b1 = b0 + int(rf[-1] - rf[0])
    fr = new.frame_range
    check("frame_start", fr[0] - a0)
    check("frame_end", fr[1] - b1)
    check("curves_missing", len(set(kw) - set(kn)))

    # Outside the gap: the actions' own keys (the root may move as a whole under "shift").
    worst_a = worst_b = worst_shift = 0.0
    root = rig.bones[0]
    for k, (nf, nv) in kn.items():
        ia = (nf >= a0) & (nf <= a1)
        ib = (nf >= b0) & (nf <= b1)
        worst_a = max(worst_a, np.abs(nv[ia] - kw[k][1]).max())
        d = nv[ib] - kr[k][1]
        if k[0] == root.loc_path:
            worst_shift = max(worst_shift, np.abs(d - d[0]).max())
        else:
            worst_b = max(worst_b, np.abs(d).max())
    check("outside_first_max", worst_a)
    check("outside_second_max", worst_b)
    check("root_shift_not_constant", worst_shift)

    # Continuity at both joins, in key values: the step across a join is like
    # the steps beside it (value), and so is the change of step (velocity).
    worst_v = worst_a2 = 0.0
    for k, (nf, nv) in kn.items():
        for e in (a1, b0 - 1):
            i = int(e - nf[0])
            d1 = np.diff(nv)
            d2 = np.diff(nv, 2)
            near1 = np.abs(d1[max(0, i - 6) : i - 1]).max() + np.abs(d1[i + 1 : i + 6]).max()
            worst_v = max(worst_v, np.abs(d1[i]) / (near1 + 1e-4))
            near2 = np.abs(d2[max(0, i - 7) : i - 2]).max() + np.abs(d2[i + 1 : i + 6]).max()
            worst_a2 = max(worst_a2, np.abs(d2[i - 1 : i + 1]).max() / (near2 + 1e-4))
    check("join_step_ratio", worst_v)
    check("join_velocity_change_ratio", worst_a2)

    # mx's Python API on the same clips (as Blender holds them, through the
    # same bone mapping and body): mx.sp with the same options; the keys in
    # the gap must be its values (float32, as F-curves store them).
    getr = lambda p, i: kr[(p, i)][1] if (p, i) in kr else None
    tw, tr = rig.to_mx(get), rig.to_mx(getr)
    n = b1 - a0 + 1
    grid = np.full((n, len(rig.dofs)), np.nan)
    grid[: len(tw)] = tw
    tr[:, rot] += 2 * np.pi * np.round((tw[-1, rot] - tr[0, rot]) / (2 * np.pi))
    grid[b0 - a0 :] = tr
    times = np.arange(n) / f
    body = rig.body(mx, 1.0 / f)
    filled, report = mx.sp(mx.Motion.from_array(rig.dofs, times, grid), body, progress=False, root="auto", contact="none", example="self")
    api = rig.from_mx(filled.sample(times))
    worst = 0.0
    for k, (nf, nv) in kn.items():
        gap = slice(a1 + 1 - a0, b0 - a0)
        d = nv[gap] - np.float32(api[k][gap]).astype(float)
        if "rotation_euler" in k[0]:
            d -= 2 * np.pi * np.round(d / (2 * np.pi))
        worst = max(worst, np.abs(d).max())
    check("gap_vs_python_api_max", worst)

    # The same against the files themselves (mx.load, its body_of): float32 apart.
    w, r = mx.load(os.path.join(MOCAP, WALK)), mx.load(os.path.join(MOCAP, RUN))
    fw, fr_ = w.sample((wf - wf[0]) / f)[:, cols], r.sample((rf - rf[0]) / f)[:, cols]
    g2 = np.full_like(grid, np.nan)
    g2[: len(fw)] = fw
    fr_[:, rot] += 2 * np.pi * np.round((fw[-1, rot] - fr_[0, rot]) / (2 * np.pi))
    g2[b0 - a0 :] = fr_
    filled2, _ = mx.sp(mx.Motion.from_array(rig.dofs, times, g2), mx.body_of(w), progress=False, root="auto")
    ours = rig.to_mx(lambda p, i: kn[(p, i)][1] if (p, i) in kn else None)
    d = ours - filled2.sample(times)
    d[:, rot] -= 2 * np.pi * np.round(d[:, rot] / (2 * np.pi))
    check("vs_files_api_max", np.abs(d).max())
    print("REPORT", report.get("text", ""), flush=True)


def gapped_walk(mx, name):
    """The walk imported, a 1 s hole cut into its keys in the middle; returns
    (armature, action, hole start, hole end) in frames."""
    fresh()
    ob, act = import_bvh(mx, name)
    from bpy_extras import anim_utils

    bag = anim_utils.action_get_channelbag_for_slot(act, act.slots[0])
    c0 = bag.fcurves[0]
    n = len(c0.keyframe_points)
    per_s = round(fps())
    h0 = n // 2 - per_s // 2
    h1 = h0 + per_s  # keys h0+1 .. h1-1 (frames) removed: a 1 s gap from h0 to h1
    for c in bag.fcurves:
        co = np.empty(2 * n, dtype=np.float32)
        c.keyframe_points.foreach_get("co", co)
        f = co[0::2]
        keep = (f <= h0) | (f >= h1)
        kept = co.reshape(-1, 2)[keep].ravel()
        c.keyframe_points.clear()
        c.keyframe_points.add(len(kept) // 2)
        c.keyframe_points.foreach_set("co", kept)
        c.update()
    return ob, act, h0, h1


def best(fn, runs=3):
    out = []
    for _ in range(runs):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return min(out)


def run_timing():
    addon, mx = install()
    ops = addon.operators
    for name in TIMING_CLIPS:
        ob, act, h0, h1 = gapped_walk(mx, name)
        f = fps()

        def op():
            ob.animation_data.action = act
            ob.animation_data.action_slot = act.slots[0]
            assert bpy.ops.mx.fill_transition(source="GAP") == {"FINISHED"}

        t_op = best(op)
        phases = dict(ops.LAST_TIMING)
        clip = mx.load(os.path.join(MOCAP, name))
        body = mx.body_of(clip)
        first = 1  # Blender's first frame is the file's frame 0
        t0, t1 = (h0 - first) / f, (h1 - first) / f
        span = clip.span
        gapped = clip.clip_in_place(span[0], t0) + clip.clip_in_place(t1, span[1])
        t_py = best(lambda: mx.sp(gapped, body, progress=False))
        print(
            f"TIME {name} operator {t_op:.3f} s python_sp {t_py:.3f} s ratio {t_op / t_py:.3f} "
            f"(read+map {phases['read']:.3f}, sp {phases['sp']:.3f}, bake+write {phases['write']:.3f})",
            flush=True,
        )
        check(f"ratio_{name}", t_op / t_py)
        prof = cProfile.Profile()
        prof.enable()
        op()
        prof.disable()
        s = io.StringIO()
        pstats.Stats(prof, stream=s).sort_stats("tottime").print_stats(8)
        print("\n".join("PROFILE " + l for l in s.getvalue().splitlines() if l.strip()), flush=True)


if __name__ == "__main__":
    {"check": run_check, "timing": run_timing}[MODE]()
