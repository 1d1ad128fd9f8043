"""Where the operators show: a sidebar panel in the Dope Sheet, the Graph
Editor and the NLA editor (tab "mx"), and File > Import / Export entries."""

import bpy

from .operators import MX_OT_export_motion, MX_OT_fill_transition, MX_OT_import_motion


class _MxPanel:
    bl_region_type = "UI"
    bl_category = "mx"
    bl_label = "mx Transitions"

    def draw(self, context):
        col = self.layout.column(align=True)
        col.operator(MX_OT_fill_transition.bl_idname, text="Fill Between Actions").source = "ACTIONS"
        col.operator(MX_OT_fill_transition.bl_idname, text="Fill Gap in Action").source = "GAP"
        col.operator(MX_OT_fill_transition.bl_idname, text="Fill Between NLA Strips").source = "NLA"
        col.separator()
        col.operator(MX_OT_import_motion.bl_idname, text="Import Motion")
        col.operator(MX_OT_export_motion.bl_idname, text="Export Motion")


class MX_PT_dopesheet(_MxPanel, bpy.types.Panel):
    bl_space_type = "DOPESHEET_EDITOR"
    bl_idname = "MX_PT_dopesheet"


class MX_PT_graph(_MxPanel, bpy.types.Panel):
    bl_space_type = "GRAPH_EDITOR"
    bl_idname = "MX_PT_graph"


class MX_PT_nla(_MxPanel, bpy.types.Panel):
    bl_space_type = "NLA_EDITOR"
    bl_idname = "MX_PT_nla"


def _menu_import(self, context):
    self.layout.operator(MX_OT_import_motion.bl_idname, text="mx Motion (.json/.bvh/.glb/.gltf)")


def _menu_export(self, context):
    self.layout.operator(MX_OT_export_motion.bl_idname, text="mx Motion (.json/.bvh/.glb/.gltf)")


CLASSES = (MX_PT_dopesheet, MX_PT_graph, MX_PT_nla)


def register_menus():
    bpy.types.TOPBAR_MT_file_import.append(_menu_import)
    bpy.types.TOPBAR_MT_file_export.append(_menu_export)


def unregister_menus():
    bpy.types.TOPBAR_MT_file_import.remove(_menu_import)
    bpy.types.TOPBAR_MT_file_export.remove(_menu_export)
