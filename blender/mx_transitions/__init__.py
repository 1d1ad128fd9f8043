"""mx Transitions: SP (spacetime, torque-minimising) transitions between
actions and mx's motion files, inside Blender 5.

Files, one job each: rotations (Euler/quaternion arrays), rig (bones <-> mx
DOFs and the body), fcurves (F-curves <-> arrays), sources (what to fill),
transition (SP on arrays), bake (the new action's channels), plan (SP's
contact plan as empties on the floor), operators, ui.
mx itself comes as a wheel (manifest `wheels`), imported when an operator runs.
"""

import bpy

from . import operators, ui


def register():
    for c in operators.CLASSES + ui.CLASSES:
        bpy.utils.register_class(c)
    ui.register_menus()


def unregister():
    ui.unregister_menus()
    for c in reversed(operators.CLASSES + ui.CLASSES):
        bpy.utils.unregister_class(c)
