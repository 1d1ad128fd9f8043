"""The operators: fill a transition, import and export mx motions. Each
gathers what Blender holds, hands arrays to rig/transition/bake, and writes a
new action; errors become reports, not tracebacks."""

import os
import time

import bpy
import numpy as np
from bpy.props import EnumProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import bake, fcurves, plan, sources, transition
from .rig import Rig, RigError, joint_name, location_path

# The last fill: its phases in seconds, and SP's result in mx's terms (dofs,
# frames, values float64), before the float32 of F-curves (tests read it).
LAST_TIMING = {}


def _mx():
    try:
        import mx
    except ImportError as e:  # the wheel did not install
        raise RigError(f"mx's Python package is not installed ({e}); reinstall the extension") from e
    return mx


def _armature(context):
    ob = context.active_object
    if ob is None or ob.type != "ARMATURE":
        raise RigError("make an armature the active object")
    return ob


def _fps(scene):
    return scene.render.fps / scene.render.fps_base


def _assign(ob, action, slot):
    ad = ob.animation_data or ob.animation_data_create()
    ad.action = action
    ad.action_slot = slot


def _groups(rig):
    return {p: b.name for b in rig.bones for p in (b.loc_path, b.rot_path)}


class MX_OT_fill_transition(bpy.types.Operator):
    """Fill the frames between two actions, a gap in the active action, or between two NLA strips with an mx SP transition (torque-minimising), written into a new action"""

    bl_idname = "mx.fill_transition"
    bl_label = "Fill Transition (mx SP)"
    bl_options = {"REGISTER", "UNDO"}

    source: EnumProperty(
        name="Between",
        items=[
            ("ACTIONS", "Two Actions", "The first action, a gap, then the second"),
            ("GAP", "Gap in Action", "The frames missing from the active action's keys"),
            ("NLA", "NLA Strips", "The two selected NLA strips (or the only two)"),
        ],
        default="ACTIONS",
    )
    first: StringProperty(name="First", description="The action before the gap")
    second: StringProperty(name="Second", description="The action after the gap")
    gap: IntProperty(
        name="Gap (frames)",
        description="Frames from the first action's last key to the second's first (two actions only)",
        default=30,
        min=2,
        soft_max=240,
    )
    root: EnumProperty(
        name="Root",
        items=[
            ("AUTO", "Auto", "Pinned when the recorded root displacement fits the gap, else shifted"),
            ("SHIFT", "Shift", "What follows the gap moves to continue the root's path (Rose)"),
            ("PINNED", "Pinned", "The root stays where it was recorded"),
        ],
        default="AUTO",
    )
    contact: EnumProperty(
        name="Contact",
        items=[
            ("DEFAULT", "SP's Default", "Whatever SP does by default (standing on the ground once that is its default)"),
            ("AUTO", "Auto", "Stand on the ground: plan foot stances from those around the gap, planted feet held"),
            ("NONE", "None", "Rose's support legs only"),
        ],
        default="DEFAULT",
    )
    example: EnumProperty(
        name="Example",
        items=[
            ("SELF", "Self", "Follow the stretch of the motion that best matches the gap's context"),
            ("NONE", "None", "The plain smoothness prior"),
        ],
        default="SELF",
    )

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return ob is not None and ob.type == "ARMATURE"

    def invoke(self, context, event):
        ob = context.active_object
        act = ob.animation_data.action if ob and ob.animation_data else None
        if not self.first and act is not None:
            self.first = act.name
        return self.execute(context)

    def draw(self, context):
        col = self.layout.column()
        col.prop(self, "source")
        if self.source == "ACTIONS":
            col.prop_search(self, "first", bpy.data, "actions")
            col.prop_search(self, "second", bpy.data, "actions")
            col.prop(self, "gap")
        col.prop(self, "root")
        col.prop(self, "contact")
        col.prop(self, "example")

    def _placed(self, ob):
        if self.source == "ACTIONS":
            for n in (self.first, self.second):
                if n not in bpy.data.actions:
                    raise sources.SourceError(f"no action named {n!r}: choose the first and second actions")
            return sources.two_actions(bpy.data.actions[self.first], bpy.data.actions[self.second], self.gap)
        if self.source == "GAP":
            act = ob.animation_data.action if ob.animation_data else None
            if act is None:
                raise sources.SourceError("the armature has no active action")
            return sources.gap_in(act)
        return sources.nla_strips(ob)

    def execute(self, context):
        fcurves.fresh()
        try:
            fill(context, self._placed(_armature(context)), self.root, self.contact, self.example)
        except (RigError, sources.SourceError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        except Exception as e:  # mx's own errors carry its diagnostic text
            if type(e).__module__.startswith("mx"):
                self.report({"ERROR"}, f"mx: {e}")
                return {"CANCELLED"}
            raise
        self.report({"INFO"}, LAST_TIMING.get("summary", "filled"))
        return {"FINISHED"}


def fill(context, placed, root="AUTO", contact="DEFAULT", example="SELF"):
    """The fill on placed clips: a new action on the active armature, returned;
    SP's contact plan, when it made one, as empties on the floor (`plan.py`)."""
    t0 = time.perf_counter()
    mx = _mx()
    ob = _armature(context)
    fps = _fps(context.scene)
    paths = {p for pl in placed for (p, _) in fcurves.keys(pl.action)}
    rig = Rig(ob, paths)
    gets = [fcurves.reader(pl.action, pl.src) for pl in placed]
    pieces = [transition.Piece(pl.dst, rig.to_mx(g)) for pl, g in zip(placed, gets)]
    frames, values = transition.grid(pieces, rig.rotation_columns())
    body = rig.body(mx, 1.0 / fps)
    t1 = time.perf_counter()
    filled, report = transition.fill(
        mx, rig.dofs, frames, values, fps, body, transition.options(root, contact, example)
    )
    t2 = time.perf_counter()
    rows = [pl.dst - frames[0] for pl in placed]
    given = [values[r] for r in rows]
    chans = bake.channels(rig, gets, rows, given, filled, len(frames))
    names = " + ".join(dict.fromkeys(pl.action.name for pl in placed))
    action, slot = fcurves.write_action(f"{names} (mx SP)", "OBJECT", frames, chans, _groups(rig))
    _assign(ob, action, slot)
    scene = context.scene
    scene.frame_start, scene.frame_end = int(frames[0]), int(frames[-1])
    empties = plan.show(scene, ob, report.get("contacts") or [], fps, int(frames[0]))
    t3 = time.perf_counter()
    LAST_TIMING.clear()
    LAST_TIMING.update(
        read=t1 - t0, sp=t2 - t1, write=t3 - t2, total=t3 - t0, report=report, action=action.name,
        dofs=rig.dofs, frames=frames, values=filled, empties=[e.name for e in empties],
        summary=f"mx SP: {action.name!r}, frames {frames[0]}-{frames[-1]} ({t3 - t0:.2f} s, SP {t2 - t1:.2f} s)",
    )
    return action


class MX_OT_import_motion(ImportHelper, bpy.types.Operator):
    """Load a motion with mx (.json, .bvh, .glb, .gltf) as a new action on the active armature, whose bones must carry the motion's joint names"""

    bl_idname = "mx.import_motion"
    bl_label = "Import mx Motion"
    bl_options = {"REGISTER", "UNDO"}
    filter_glob: StringProperty(default="*.json;*.bvh;*.glb;*.gltf", options={"HIDDEN"})

    def execute(self, context):
        try:
            mx = _mx()
            ob = _armature(context)
            m = mx.load(self.filepath)
            if not isinstance(m, mx.Motion):
                raise RigError(f"{os.path.basename(self.filepath)} holds a {type(m).__name__}, not a motion")
            fps = _fps(context.scene)
            rig = Rig(ob, {p for p in _location_paths(ob, m.dofs)})
            missing = sorted(set(rig.dofs) - set(m.dofs))
            if len(missing) == len(rig.dofs):
                raise RigError("none of the armature's bones is in the motion (names must match)")
            if m.span is None:
                raise RigError(f"{os.path.basename(self.filepath)} holds an empty motion")
            lo, hi = m.span
            n = int(np.floor((hi - lo) * fps + 1e-9)) + 1
            times = lo + np.arange(n) / fps
            values = rig.from_named(m.dofs, m.sample(times))
            frames = context.scene.frame_start + np.arange(n)
            chans = rig.from_mx(np.nan_to_num(values))
            name = os.path.splitext(os.path.basename(self.filepath))[0]
            action, slot = fcurves.write_action(name, "OBJECT", frames, chans, _groups(rig))
            _assign(ob, action, slot)
        except Exception as e:
            if isinstance(e, RigError) or type(e).__module__.startswith("mx"):
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            raise
        self.report({"INFO"}, f"mx: {name!r}, {n} frames")
        return {"FINISHED"}


def _location_paths(ob, dofs):
    names = {d.rsplit(".", 1)[0] for d in dofs if d.endswith("position")}
    return {location_path(b.name) for b in ob.pose.bones if joint_name(b.name) in names}


class MX_OT_export_motion(ExportHelper, bpy.types.Operator):
    """Save the active armature's action with mx (.json, .bvh, .glb, .gltf by extension)"""

    bl_idname = "mx.export_motion"
    bl_label = "Export mx Motion"
    filename_ext = ".glb"
    filter_glob: StringProperty(default="*.json;*.bvh;*.glb;*.gltf", options={"HIDDEN"})

    def execute(self, context):
        fcurves.fresh()
        try:
            mx = _mx()
            ob = _armature(context)
            act = ob.animation_data.action if ob.animation_data else None
            if act is None:
                raise RigError("the armature has no active action to export")
            ext = os.path.splitext(self.filepath)[1].lower()
            if ext not in (".json", ".bvh", ".glb", ".gltf"):
                raise RigError(f"mx writes .json, .bvh, .glb and .gltf, not {ext or 'no extension'}")
            frames = fcurves.keyed_frames(act)
            if len(frames) == 0:
                raise RigError(f"the action {act.name!r} has no keys to export")
            frames = np.arange(frames[0], frames[-1] + 1)
            rig = Rig(ob, {p for (p, _) in fcurves.keys(act)})
            fps = _fps(context.scene)
            values = rig.to_mx(fcurves.reader(act, frames))
            m = mx.Motion.from_array(rig.dofs, (frames - frames[0]) / fps, values)
            opts = {} if ext == ".json" else {"body": rig.body(mx, 1.0 / fps)}
            m.save(self.filepath, **opts)
        except Exception as e:
            if isinstance(e, RigError) or type(e).__module__.startswith("mx"):
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            raise
        self.report({"INFO"}, f"mx: wrote {self.filepath}")
        return {"FINISHED"}


CLASSES = (MX_OT_fill_transition, MX_OT_import_motion, MX_OT_export_motion)
