"""SP's contact plan as empties on the floor: one per stance, at its anchor,
named by point and source ("mx Toes_L 2 context"), in the collection
"mx plan" (emptied at each fill). The anchors are mx's (y up, the armature's
space): shown in the world through the armature's matrix."""

import bpy
import numpy as np
from mathutils import Matrix, Vector

from .rig import TO_MX

COLLECTION = "mx plan"


def to_world(ob, at):
    """mx's point `at` (metres, y up, armature space) in Blender's world."""
    p = TO_MX.T @ np.asarray(at, dtype=float)
    return ob.matrix_world @ Vector(p.tolist())


def _collection(scene):
    coll = bpy.data.collections.get(COLLECTION)
    if coll is None:
        coll = bpy.data.collections.new(COLLECTION)
    if coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    for o in list(coll.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    return coll


def show(scene, ob, stances, fps, first_frame):
    """An empty per stance of `stances` (the report's `contacts`: records
    with point, from, to, at, source) on `ob`'s floor; returns them. Each
    carries its stance's frames as custom properties."""
    coll = _collection(scene)
    out = []
    for k, s in enumerate(stances):
        e = bpy.data.objects.new(f"mx {s['point']} {k} {s['source']}", None)
        e.empty_display_type = "CIRCLE"
        e.empty_display_size = 0.07
        # a circle lies in its local xy plane: turn it onto the floor (world z up)
        e.matrix_world = Matrix.Translation(to_world(ob, s["at"])) @ ob.matrix_world.to_3x3().normalized().to_4x4() @ Matrix.Rotation(np.pi / 2, 4, "X")
        e["mx_point"] = s["point"]
        e["mx_source"] = s["source"]
        e["mx_frames"] = (first_frame + s["from"] * fps, first_frame + s["to"] * fps)
        coll.objects.link(e)
        out.append(e)
    return out
