"""What the fill operator fills: the clips placed on the timeline, as
(action, the action's frames, where they go) pieces, for the three cases the
operator handles. Frames throughout (integers, as animators count)."""

import numpy as np

from . import fcurves


class SourceError(Exception):
    """Nothing to fill, said why."""


class Placed:
    """Frames `src` of `action`, placed at timeline frames `dst` (same length)."""

    def __init__(self, action, src, dst):
        self.action = action
        self.src = np.asarray(src, dtype=int)
        self.dst = np.asarray(dst, dtype=int)


def _span(action):
    f = fcurves.keyed_frames(action)
    if len(f) < 2:
        raise SourceError(f"action {action.name!r} has fewer than two keyed frames")
    return f


def two_actions(first, second, gap):
    """`first` over its keyed range, then `gap` frames from its last frame to
    `second`'s first (so gap - 1 frames are filled)."""
    if gap < 2:
        raise SourceError("the gap must be at least 2 frames (one in-between)")
    a, b = _span(first), _span(second)
    a_range = np.arange(a[0], a[-1] + 1)
    b_range = np.arange(b[0], b[-1] + 1)
    start_b = a[-1] + gap
    return [Placed(first, a_range, a_range), Placed(second, b_range, b_range - b[0] + start_b)]


def gap_in(action):
    """The runs of consecutive keyed frames of `action`: the holes between
    them are filled."""
    f = _span(action)
    breaks = np.nonzero(np.diff(f) > 1)[0]
    if len(breaks) == 0:
        raise SourceError(
            f"action {action.name!r} has a key on every frame from {f[0]} to {f[-1]}: no gap to fill "
            "(delete the keys of the frames to fill, or pick a second action)"
        )
    runs = np.split(f, breaks + 1)
    return [Placed(action, r, r) for r in runs]


def nla_strips(obj):
    """The two strips to join on the object's NLA tracks: the selected ones,
    else all of them; they must be exactly two, in time order, apart."""
    ad = obj.animation_data
    strips = [s for t in (ad.nla_tracks if ad else []) for s in t.strips if s.action is not None]
    chosen = [s for s in strips if s.select] or strips
    if len(chosen) != 2:
        raise SourceError(f"select exactly two NLA action strips (found {len(chosen)})")
    s1, s2 = sorted(chosen, key=lambda s: s.frame_start)
    gap = int(round(s2.frame_start - s1.frame_end))
    if gap < 2:
        raise SourceError(
            f"the strips are {gap} frame(s) apart: move {s2.name!r} at least 2 frames after {s1.name!r}"
        )
    out = []
    for s in (s1, s2):
        if abs(s.scale - 1) > 1e-9 or abs(s.repeat - 1) > 1e-9:
            raise SourceError(f"strip {s.name!r} is scaled or repeated; mx reads strips at scale 1, repeat 1")
        src = np.arange(int(round(s.action_frame_start)), int(round(s.action_frame_end)) + 1)
        dst = src - src[0] + int(round(s.frame_start))
        out.append(Placed(s.action, src, dst))
    return out
