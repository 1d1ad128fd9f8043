"""The README's picture of the add-on, rendered headless with bpy (Blender 5
as a Python module cannot draw its user interface, so this is not the
panel): the walk -> run fill the add-on test makes, as stick figures every
few frames, walk blue, the SP frames orange, run green, rendered by Cycles.

    target/bpyenv/bin/python scripts/blender-addon-picture.py \
        target/blender/mx_transitions-0.1.0.zip ../shared/data/mocap docs/blender_addon.png

Run it with BLENDER_USER_RESOURCES etc. pointing at a scratch folder (the
extension is installed there), as tests/it/blender_addon.rs does.
"""

import json
import os
import sys

import bpy
import numpy as np
from mathutils import Vector

ZIP, MOCAP, OUT = sys.argv[1:4]
WALK, RUN, GAP, STEP = "bandai2_walk_normal_001.bvh", "bandai2_run_normal_001.bvh", 30, 5

bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
import mx  # noqa: E402  (the wheel the extension just installed)

bpy.ops.wm.read_factory_settings(use_empty=True)
__import__("addon_utils").enable("bl_ext.user_default.mx_transitions", default_set=True)


def import_bvh(name):
    path = os.path.join(MOCAP, name)
    scale = mx.Interpreter().eval("bvh_info(" + json.dumps(path) + ").metres_per_unit")
    bpy.ops.import_anim.bvh(filepath=path, global_scale=scale, update_scene_fps=True)
    ob = bpy.context.view_layer.objects.active
    return ob, ob.animation_data.action


arm, walk = import_bvh(WALK)
run_ob, run = import_bvh(RUN)
bpy.data.objects.remove(run_ob)
bpy.context.view_layer.objects.active = arm
walk_end = int(walk.frame_range[1])
assert bpy.ops.mx.fill_transition(source="ACTIONS", first=walk.name, second=run.name, gap=GAP) == {"FINISHED"}
run_start = walk_end + GAP


def material(name, rgb):
    m = bpy.data.materials.new(name)
    m.diffuse_color = (*rgb, 1)
    m.use_nodes = True
    m.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*rgb, 1)
    return m


mats = {
    "walk": material("walk", (0.15, 0.35, 0.85)),
    "sp": material("sp", (0.95, 0.45, 0.1)),
    "run": material("run", (0.15, 0.65, 0.3)),
}
scene = bpy.context.scene
frames = list(range(walk_end - 20, run_start + 21, STEP))
for n, f in enumerate(frames):
    scene.frame_set(f)
    kind = "walk" if f <= walk_end else ("run" if f >= run_start else "sp")
    # Each pose centred on its hips, the poses in a row along y (across the
    # picture): a film strip, not the path walked.
    hips = arm.matrix_world @ arm.pose.bones["Hips"].head
    off = Vector((-hips.x, 0.6 * n - hips.y, 0))
    for pb in arm.pose.bones[1:]:  # not the static joint_Root -> Hips bone
        h = arm.matrix_world @ pb.head
        t = arm.matrix_world @ pb.tail
        if (t - h).length < 1e-4:
            continue
        bpy.ops.mesh.primitive_cylinder_add(radius=0.018, depth=(t - h).length, location=(h + t) / 2 + off)
        c = bpy.context.active_object
        c.rotation_mode = "QUATERNION"
        c.rotation_quaternion = (t - h).to_track_quat("Z", "Y")
        c.data.materials.append(mats[kind])
arm.hide_render = True
bpy.ops.mesh.primitive_plane_add(size=40, location=(0, 0, 0))
bpy.context.active_object.data.materials.append(material("floor", (0.8, 0.8, 0.8)))
bpy.ops.object.light_add(type="SUN", rotation=(0.6, 0.2, 0.8))
bpy.context.active_object.data.energy = 3.0
world = bpy.data.worlds.new("w")
world.color = (0.35, 0.35, 0.38)
scene.world = world
# Camera: looking across the row of figures from the side, slightly above.
mid = np.mean([o.location for o in bpy.data.objects if o.type == "MESH" and o.data.name.startswith("Cyl")], 0)
bpy.ops.object.camera_add(location=(mid[0] + 9.5, mid[1], 1.6))
cam = bpy.context.active_object
cam.rotation_mode = "QUATERNION"
cam.rotation_quaternion = (Vector(mid) + Vector((0, 0, 0.2)) - cam.location).to_track_quat("-Z", "Y")
cam.data.type = "ORTHO"
cam.data.ortho_scale = 0.6 * len(frames) + 0.6
scene.camera = cam
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 24
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = 1400, 300
scene.render.filepath = os.path.abspath(OUT)
bpy.ops.render.render(write_still=True)
print("wrote", OUT, "frames", frames)
