"""The SP transition on arrays: pieces of motion on a frame grid in, the
filled grid out. No bpy here: frames in, seconds only inside (t = frame / fps
from the first frame)."""

import numpy as np


class Piece:
    """mx values [T, D] on consecutive integer `frames` (placed on the timeline)."""

    def __init__(self, frames, values):
        self.frames = np.asarray(frames, dtype=int)
        self.values = np.asarray(values, dtype=float)


def grid(pieces, rotation_columns):
    """(frames, values [T, D] with NaN in the holes): the pieces on one frame
    grid, each piece's angles moved by whole turns to continue the one before
    (two clips' Euler angles may sit a turn apart; SP would spin through it)."""
    pieces = sorted(pieces, key=lambda p: p.frames[0])
    first, last = pieces[0].frames[0], pieces[-1].frames[-1]
    frames = np.arange(first, last + 1)
    values = np.full((len(frames), pieces[0].values.shape[1]), np.nan)
    prev = None
    for p in pieces:
        v = p.values.copy()
        if prev is not None and len(rotation_columns):
            r = rotation_columns
            v[:, r] += 2 * np.pi * np.round((prev[r] - v[0, r]) / (2 * np.pi))
        values[p.frames - first] = v
        prev = v[-1]
    return frames, values


def options(root, contact, example):
    """SP's options from the panel's (lower-case mx names); contact "DEFAULT"
    passes none, so the fill does what SP does by default."""
    opts = {"root": root.lower(), "example": example.lower()}
    if contact != "DEFAULT":
        opts["contact"] = contact.lower()
    return opts


def fill(mx, dofs, frames, values, fps, body, opts):
    """SP on the grid: returns (values [T, D] filled, mx's report dict)."""
    times = (frames - frames[0]) / fps
    motion = mx.Motion.from_array(dofs, times, values)
    filled, report = mx.sp(motion, body, progress=False, **opts)
    return filled.sample(times), report
