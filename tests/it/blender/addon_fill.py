"""The mx add-on in real Blender (bpy 5 from PyPI), run by
tests/it/blender_addon.rs with a Python that has `bpy`.

    python addon_fill.py ZIP MOCAP_DIR check   # install, fill walk -> run, check it
    python addon_fill.py ZIP MOCAP_DIR check_quaternion  # the same, bones keyed as quaternions
    python addon_fill.py ZIP MOCAP_DIR plan    # fill standing on the ground: the plan's empties
    python addon_fill.py ZIP MOCAP_DIR timing  # the operator against mx.sp on 1 s gaps of walks
    python addon_fill.py REPO_DIR MOCAP_DIR local  # blender/ added as a local repository, enabled

Prints `CHECK name value` lines (the Rust side asserts on them) and `TIME`
lines; exits non-zero on an exception. Frames are Blender's (1 = a BVH's
first frame); the add-on's own seconds are (frame - first) / fps.
"""

import cProfile
import io
import json
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
    return mx.Interpreter().eval("bvh_info(" + json.dumps(path) + ").metres_per_unit")


ROTATE_MODE = "QUATERNION" if MODE == "check_quaternion" else "NATIVE"


def import_bvh(mx, name):
    path = os.path.join(MOCAP, name)
    bpy.ops.import_anim.bvh(
        filepath=path, global_scale=units(mx, path), update_scene_fps=True, rotate_mode=ROTATE_MODE
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
    """An empty scene; factory settings disable add-ons, so enable it again."""
    import addon_utils

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("bl_ext.user_default.mx_transitions", default_set=True)


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
    shifted = []
    for k, (nf, nv) in kn.items():
        ia = (nf >= a0) & (nf <= a1)
        ib = (nf >= b0) & (nf <= b1)
        worst_a = max(worst_a, np.abs(nv[ia] - kw[k][1]).max())
        d = nv[ib] - kr[k][1]
        if k[0].endswith(".location") and d[0] != 0:
            shifted.append(k)
            worst_shift = max(worst_shift, np.abs(d - d[0]).max())
        else:
            worst_b = max(worst_b, np.abs(d).max())
    print("SHIFTED", shifted, flush=True)
    check("outside_first_max", worst_a)
    check("outside_second_max", worst_b)
    check("shifted_curves", len(shifted))
    check("shift_not_constant", worst_shift)

    # SP's result as the operator computed it (float64, mx's DOFs) ...
    last = addon.operators.LAST_TIMING
    result = last["values"]
    assert list(last["dofs"]) == rig.dofs and last["frames"][0] == a0 and last["frames"][-1] == b1
    # ... is what the keys hold (float32 apart) ...
    ours = rig.to_mx(lambda p, i: kn[(p, i)][1] if (p, i) in kn else None)
    d = ours - result
    d[:, rot] -= 2 * np.pi * np.round(d[:, rot] / (2 * np.pi))
    j = np.unravel_index(np.argmax(np.abs(d)), d.shape)
    print("KEYS worst", rig.dofs[j[1]], "frame", a0 + j[0], d[j], flush=True)
    check("keys_vs_result_max", np.abs(d).max())

    # ... joins the clips continuously: in mx's DOFs (well-conditioned, unlike
    # a bone's Euler channels near their middle angle's 90 degrees), the step
    # across each join and its change are like those of the frames beside it.
    worst_v = worst_a2 = 0.0
    ours[:, rot] = np.unwrap(ours[:, rot], axis=0)
    for j, name in enumerate(rig.dofs):
        v = ours[:, j]
        d1, d2 = np.diff(v), np.diff(v, 2)
        for e in (a1, b0 - 1):
            i = e - a0
            near1 = np.abs(d1[i - 6 : i - 1]).max() + np.abs(d1[i + 1 : i + 6]).max()
            r1 = np.abs(d1[i]) / (near1 + 1e-4)
            near2 = np.abs(d2[i - 7 : i - 2]).max() + np.abs(d2[i + 1 : i + 6]).max()
            r2 = np.abs(d2[i - 1 : i + 1]).max() / (near2 + 1e-4)
            if r1 > worst_v or r2 > worst_a2:
                print("JOIN", name, e, round(r1, 3), round(r2, 3), flush=True)
            worst_v, worst_a2 = max(worst_v, r1), max(worst_a2, r2)
    check("join_step_ratio", worst_v)
    check("join_velocity_change_ratio", worst_a2)

    # ... and is mx's Python API on the same clips (as Blender holds them,
    # through the same bone mapping and body) with the same options.
    getr = lambda p, i: kr[(p, i)][1] if (p, i) in kr else None
    tw, tr = rig.to_mx(get), rig.to_mx(getr)
    n = b1 - a0 + 1
    grid = np.full((n, len(rig.dofs)), np.nan)
    grid[: len(tw)] = tw
    tr[:, rot] += 2 * np.pi * np.round((tw[-1, rot] - tr[0, rot]) / (2 * np.pi))
    grid[b0 - a0 :] = tr
    times = np.arange(n) / f
    body = rig.body(mx, 1.0 / f)
    motion = mx.Motion.from_array(rig.dofs, times, grid)
    filled, report = mx.sp(motion, body, progress=False, root="auto", example="self")
    check("result_vs_python_api_max", np.abs(filled.sample(times) - result).max())

    # The same against the files themselves (mx.load, its body_of): float32 apart.
    w, r = mx.load(os.path.join(MOCAP, WALK)), mx.load(os.path.join(MOCAP, RUN))
    fw, fr_ = w.sample((wf - wf[0]) / f)[:, cols], r.sample((rf - rf[0]) / f)[:, cols]
    g2 = np.full_like(grid, np.nan)
    g2[: len(fw)] = fw
    fr_[:, rot] += 2 * np.pi * np.round((fw[-1, rot] - fr_[0, rot]) / (2 * np.pi))
    g2[b0 - a0 :] = fr_
    m2 = mx.Motion.from_array(rig.dofs, times, g2)
    filled2, _ = mx.sp(m2, mx.body_of(w), progress=False, root="auto")
    # (the file's values with the armature's body: how much of it is the body)
    same_body, _ = mx.sp(m2, body, progress=False, root="auto")
    check("files_body_vs_rest_body_max", np.abs(filled2.sample(times) - same_body.sample(times)).max())
    d = result - filled2.sample(times)
    d[:, rot] -= 2 * np.pi * np.round(d[:, rot] / (2 * np.pi))
    j = np.unravel_index(np.argmax(np.abs(d)), d.shape)
    print("FILES worst", rig.dofs[j[1]], "frame", a0 + j[0], d[j], flush=True)
    check("vs_files_api_max", np.abs(d).max())
    # with the armature's body, the files' values give the operator's transition to float32
    d = result - same_body.sample(times)
    d[:, rot] -= 2 * np.pi * np.round(d[:, rot] / (2 * np.pi))
    check("vs_files_same_body_max", np.abs(d).max())
    print("REPORT", report.get("text", ""), flush=True)

    # Between two NLA strips: the walk, then the run GAP frames after its
    # end, as strips; the operator gives the same transition.
    ad = walk_ob.animation_data
    track = ad.nla_tracks.new()
    track.strips.new("walk", a0, walk)
    track.strips.new("run", b0, run)
    ad.action = None
    assert bpy.ops.mx.fill_transition(source="NLA") == {"FINISHED"}
    check("nla_vs_actions_max", np.abs(addon.operators.LAST_TIMING["values"] - result).max())
    ad.nla_tracks.remove(track)

    # Misuse is a report, not a traceback (bpy raises RuntimeError on an ERROR report).
    for kw, want in [
        (dict(source="ACTIONS", first=walk.name, second="no such action"), "no action named"),
        (dict(source="GAP"), "no gap to fill"),
        (dict(source="NLA"), "select exactly two NLA"),
    ]:
        ad.action = walk
        ad.action_slot = walk.slots[0]
        try:
            bpy.ops.mx.fill_transition(**kw)
            check(f"misuse_{kw['source']}_reported", 0)
        except RuntimeError as e:
            print("MISUSE", kw["source"], str(e).strip(), flush=True)
            check(f"misuse_{kw['source']}_reported", 1 if want in str(e) else 0)

    # Export the fill with mx and import it back onto the armature, per format.
    import tempfile

    ad.action = new
    ad.action_slot = new.slots[0]
    with tempfile.TemporaryDirectory() as tmp:
        for ext in ("json", "bvh", "glb", "gltf"):
            path = os.path.join(tmp, "fill." + ext)
            assert bpy.ops.mx.export_motion(filepath=path) == {"FINISHED"}, ext
            assert bpy.ops.mx.import_motion(filepath=path) == {"FINISHED"}, ext
            back = keys(walk_ob.animation_data.action)
            nb = len(back[next(iter(back))][0])
            v = rig.to_mx(lambda p, i: back[(p, i)][1] if (p, i) in back else None)
            d = v - result[:nb]
            d[:, rot] -= 2 * np.pi * np.round(d[:, rot] / (2 * np.pi))
            print("ROUNDTRIP", ext, nb, "frames", flush=True)
            check(f"roundtrip_frames_{ext}", nb - len(result))
            check(f"roundtrip_{ext}_max", np.abs(d).max())

    # Undo: the fill pushed as an undo step (bpy.ops' second argument, as the
    # UI does) goes away with Ctrl-Z; the walk is the active action again.
    ob_name, walk_name = walk_ob.name, walk.name
    ad.action = walk
    ad.action_slot = walk.slots[0]
    bpy.ops.ed.undo_push(message="before the fill")
    before = {a.name for a in bpy.data.actions}
    assert bpy.ops.mx.fill_transition(
        "EXEC_DEFAULT", True, source="ACTIONS", first=walk.name, second=run.name, gap=GAP
    ) == {"FINISHED"}
    check("undo_fill_added_actions", len({a.name for a in bpy.data.actions} - before))
    bpy.ops.ed.undo()
    ob = bpy.data.objects[ob_name]  # undo reloads the data: old references are stale
    check("undo_left_actions", len({a.name for a in bpy.data.actions} - before))
    check("undo_active_is_walk", ob.animation_data.action.name == walk_name)


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


def min_pairs(a, b, runs):
    ta, tb = [], []
    for _ in range(runs):
        for fn, out in ((a, ta), (b, tb)):
            t = time.perf_counter()
            fn()
            out.append(time.perf_counter() - t)
    return min(ta), min(tb)


def run_timing():
    """The operator on a 1 s gap of each walk against mx.sp from Python on
    the same problem (the same clip as Blender holds it, the same body):
    best of three, warm; the rest is the glue. mx.sp on the file (mx.load,
    body_of, the same gap) is printed beside it."""
    addon, mx = install()
    ops = addon.operators
    for name in TIMING_CLIPS:
        ob, act, h0, h1 = gapped_walk(mx, name)
        f = fps()

        def op():
            ob.animation_data.action = act
            ob.animation_data.action_slot = act.slots[0]
            assert bpy.ops.mx.fill_transition(source="GAP") == {"FINISHED"}

        op()
        phases = dict(ops.LAST_TIMING)
        # The same problem from Python: the action's keys through the rig, NaN in the hole.
        ka = keys(act)
        rig = addon.rig.Rig(ob, {p for (p, _) in ka})
        frames = np.arange(int(phases["frames"][0]), int(phases["frames"][-1]) + 1)
        have = np.isin(frames, ka[next(iter(ka))][0].astype(int))
        vals = rig.to_mx(lambda p, i: np.interp(frames, *ka[(p, i)]) if (p, i) in ka else None)
        vals[~have] = np.nan
        times = (frames - frames[0]) / f
        body = rig.body(mx, 1 / f)
        motion = mx.Motion.from_array(rig.dofs, times, vals)
        # Interleaved, best of five each: the machine's load changes from second to second.
        t_op, t_py = min_pairs(op, lambda: mx.sp(motion, body, progress=False), 5)
        phases = dict(ops.LAST_TIMING)
        clip = mx.load(os.path.join(MOCAP, name))
        t0, t1 = (h0 - 1) / f, (h1 - 1) / f  # Blender's frame 1 is the file's first frame
        gapped = clip - clip.clip_in_place(t0, t1)
        t_file = best(lambda: mx.sp(gapped, mx.body_of(clip), progress=False), 2)
        print(
            f"TIME {name} operator {t_op:.3f} s, mx.sp same problem {t_py:.3f} s, ratio {t_op / t_py:.3f}; "
            f"phases: read+map {phases['read']:.3f}, sp {phases['sp']:.3f}, bake+write {phases['write']:.3f}; "
            f"mx.sp on the file {t_file:.3f} s",
            flush=True,
        )
        check(f"ratio_{name}", t_op / t_py)
        check(f"glue_{name}", t_op - t_py)
        prof = cProfile.Profile()
        prof.enable()
        op()
        prof.disable()
        s = io.StringIO()
        pstats.Stats(prof, stream=s).sort_stats("cumulative").print_stats("mx_transitions", 12)
        print("\n".join("PROFILE " + l for l in s.getvalue().splitlines() if "mx_transitions" in l), flush=True)


def run_plan():
    """The fill standing on the ground (contact AUTO): one empty per stance of
    SP's plan, named by point and source, at the plan's anchor (mx's y-up
    armature space, shown through the armature's matrix: (x, y, z) mx is
    (x, -z, y) Blender), and the foot bone there while the stance holds."""
    from mathutils import Vector

    addon, mx = install()
    fresh()
    walk_ob, walk = import_bvh(mx, WALK)
    run_ob, run = import_bvh(mx, RUN)
    bpy.data.objects.remove(run_ob)
    bpy.context.view_layer.objects.active = walk_ob
    walk_ob.select_set(True)
    # a moved armature: the empties follow its matrix
    walk_ob.location = (0.5, -0.25, 0.0)
    bpy.context.view_layer.update()
    res = bpy.ops.mx.fill_transition(source="ACTIONS", first=walk.name, second=run.name, gap=GAP, contact="AUTO")
    assert res == {"FINISHED"}, res
    last = addon.operators.LAST_TIMING
    stances = last["report"]["contacts"]
    names = last["empties"]
    check("plan_stances", len(stances))
    check("plan_empties", len(names))
    coll = bpy.data.collections["mx plan"]
    worst = named = 0.0
    worst_bone = 0.0
    for k, (s, name) in enumerate(zip(stances, names)):
        e = coll.objects[name]
        at = s["at"]
        want = walk_ob.matrix_world @ Vector((at[0], -at[2], at[1]))
        worst = max(worst, (e.matrix_world.translation - want).length)
        named += 1 if (s["point"] in name and s["source"] in name) else 0
        # the foot bone stands there at the stance's middle frame
        f0 = last["frames"][0]
        mid = round(f0 + (s["from"] + s["to"]) / 2 * fps())
        bpy.context.scene.frame_set(mid)
        bone = next(b for b in walk_ob.pose.bones if b.name.replace(".", "_") == s["point"])
        head = walk_ob.matrix_world @ bone.head
        err = s["error"] if s["error"] is not None else 0.0
        worst_bone = max(worst_bone, (head - want).length - err)
    check("plan_anchor_max", worst)
    check("plan_named", named)
    check("plan_bone_beyond_error_max", worst_bone)
    # a second fill replaces the empties
    assert bpy.ops.mx.fill_transition(source="ACTIONS", first=walk.name, second=run.name, gap=GAP, contact="NONE") == {"FINISHED"}
    check("plan_after_none", len(coll.objects))


def run_local():
    """The repository's blender/ folder as a local extension repository: the
    add-on enables, its wheel installs, the operator registers."""
    import addon_utils

    assert bpy.ops.preferences.extension_repo_add(
        name="mx_local", type="LOCAL", use_custom_directory=True, custom_directory=ZIP
    ) == {"FINISHED"}
    repo = next(r for r in bpy.context.preferences.extensions.repos if r.name == "mx_local")
    addon_utils.enable(f"bl_ext.{repo.module}.mx_transitions", default_set=True, handle_error=None)
    import mx

    check("local_operator_registered", hasattr(bpy.ops.mx, "fill_transition"))
    check("local_mx_imports", hasattr(mx, "sp"))


if __name__ == "__main__":
    {"check": run_check, "check_quaternion": run_check, "plan": run_plan, "timing": run_timing, "local": run_local}[MODE]()
