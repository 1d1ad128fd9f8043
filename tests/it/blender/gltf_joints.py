"""Blender's own glTF importer on mx-written files (run by tests/it/gltf.rs
with a Python that has `bpy`, Blender as a module).

Arguments: pairs of `file.glb positions.json`; the JSON holds mx's joint
positions {"times": [...], "names": [...], "points": [[[x, y, z], ...], ...]}
(glTF's y-up metres). For each pair: import into an empty scene, play every
frame, and print one line `name worst_distance_m joints_missing`, where the
distance is between each pose bone's head (world) and mx's joint.
"""

import json
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
for glb, pos in zip(args[0::2], args[1::2]):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=glb)
    arm = next(o for o in bpy.data.objects if o.type == "ARMATURE")
    scene = bpy.context.scene
    # The importer keys seconds × the scene's frame rate.
    fps = scene.render.fps / scene.render.fps_base
    data = json.load(open(pos))
    missing = [n for n in data["names"] if n not in arm.pose.bones]
    worst = 0.0
    for t, frame in zip(data["times"], data["points"]):
        f = (t - data["times"][0]) * fps
        scene.frame_set(int(f), subframe=f - int(f))
        for name, (x, y, z) in zip(data["names"], frame):
            if name in arm.pose.bones:
                h = arm.matrix_world @ arm.pose.bones[name].head
                # glTF y-up to Blender z-up: (x, y, z) -> (x, -z, y).
                worst = max(worst, ((h.x - x) ** 2 + (h.y + z) ** 2 + (h.z - y) ** 2) ** 0.5)
    print("RESULT", glb, worst, len(missing), flush=True)
