"""F-curves in and out as NumPy arrays, one `foreach_get` / `foreach_set`
per curve (a per-keyframe Python loop is what would make the glue slow)."""

import numpy as np

from bpy_extras import anim_utils


def channelbag(action):
    """The channel bag of the action's first slot (Blender 5 actions are
    slotted; an importer's action has one slot)."""
    if not action.slots:
        return None
    return anim_utils.action_get_channelbag_for_slot(action, action.slots[0])


# Each curve's keys, read once per operator run (fresh() starts a run): the
# sources, the mapping and the bake all ask, and a foreach_get per ask was a
# fifth of the glue on a 120 Hz clip.
_KEYS = {}


def fresh():
    """Forget the keys read so far (call at the start of an operator)."""
    _KEYS.clear()


def curve_map(action):
    """{(data_path, index): FCurve} of the action."""
    bag = channelbag(action)
    return {} if bag is None else {(c.data_path, c.array_index): c for c in bag.fcurves}


def keys(action):
    """{(data_path, index): (curve, key frames, key values)} (float64 of float32)."""
    k = action.name_full
    if k not in _KEYS:
        out = {}
        for key, c in curve_map(action).items():
            points = c.keyframe_points
            co = np.empty(2 * len(points), dtype=np.float32)
            points.foreach_get("co", co)
            out[key] = (c, co[0::2].astype(float), co[1::2].astype(float))
        _KEYS[k] = out
    return _KEYS[k]


def keyed_frames(action):
    """Sorted integer frames that carry a key on any curve."""
    ks = keys(action).values()
    if not ks:
        return np.array([], dtype=int)
    return np.unique(np.round(np.concatenate([f for _, f, _ in ks])).astype(int))


def sample(curve, kf, kv, frames):
    """The curve (keys kf, kv) at integer `frames` (float64): the keys when
    they are on those frames, else the curve evaluated."""
    n = len(kf)
    if n == len(frames) and n and kf[0] == frames[0] and kf[-1] == frames[-1] and np.all(np.diff(kf) == 1):
        return kv  # one key per frame (an importer's curve): the keys are the samples
    idx = np.minimum(np.searchsorted(kf, frames), max(n - 1, 0))
    if n and np.all(kf[idx] == frames):
        return kv[idx]
    return np.array([curve.evaluate(float(f)) for f in frames])


def reader(action, frames):
    """`get(path, index)` for rig.Rig.to_mx: the channel over `frames`, or
    None when the action does not animate it."""
    curves = keys(action)
    cache = {}

    def get(path, index):
        if (path, index) not in cache:
            c = curves.get((path, index))
            cache[(path, index)] = None if c is None else sample(*c, frames)
        return cache[(path, index)]

    return get


def write_action(name, target_id_type, frames, channels, groups):
    """A new action with one key per frame on each channel.

    channels: {(data_path, index): values [T]}; groups: {data_path: group
    name} (the bone, as importers group them). Keys are linear, as Blender's
    BVH importer makes them, so the curve between frames is the straight line
    between mx's samples.
    """
    import bpy

    action = bpy.data.actions.new(name)
    slot = action.slots.new(target_id_type, "Slot")
    bag = anim_utils.action_ensure_channelbag_for_slot(action, slot)
    f = np.asarray(frames, dtype=np.float32)
    co = np.empty(2 * len(f), dtype=np.float32)
    co[0::2] = f
    linear = None
    for (path, index), values in channels.items():
        c = bag.fcurves.new(data_path=path, index=index, group_name=groups.get(path, ""))
        c.keyframe_points.add(len(f))
        co[1::2] = values
        c.keyframe_points.foreach_set("co", co)
        if linear is None:
            linear = _linear_code(c)
        c.keyframe_points.foreach_set("interpolation", np.full(len(f), linear, dtype=np.int32))
        # No c.update(): the keys go in sorted, one per frame, and linear keys
        # need no handles; update() would re-sort and recompute them (a third
        # of the write on a 120 Hz clip).
    return action, slot


def _linear_code(curve):
    """The integer `foreach_set` takes for interpolation 'LINEAR' (enum codes
    are Blender's, not documented): set one key by name and read it back."""
    curve.keyframe_points[0].interpolation = "LINEAR"
    buf = np.empty(len(curve.keyframe_points), dtype=np.int32)
    curve.keyframe_points.foreach_get("interpolation", buf)
    return int(buf[0])
