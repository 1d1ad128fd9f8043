"""The new action's channels from SP's result.

Outside the gap each channel is the original key plus what SP changed there
(nothing, but for the root moved by root: "shift"), so the clips come back
bit for bit instead of through a float32 round trip of the bone mapping; in
the gap it is SP's motion mapped back to the bone's channels, moved by whole
turns (Euler) or sign (quaternions) to continue the keys before it."""

import numpy as np


def channels(rig, pieces_src, pieces_rows, mx_input, mx_filled, n_frames):
    """{(path, index): values [n_frames]}.

    pieces_src: per piece, `get(path, index)` of its original keys (None:
    not animated); pieces_rows: per piece, its rows in the grid; mx_input:
    per piece, the mx values SP was given for it (after any turn shift);
    mx_filled: SP's values on the whole grid [n_frames, D]."""
    back = rig.from_mx(mx_filled)
    out = {}
    for b in rig.bones:
        quat = b.mode == "QUATERNION"
        keys = b.curves()
        rows_done = np.zeros(n_frames, dtype=bool)
        cols = {k: np.array(back[k]) for k in keys}
        if quat:
            _align_quaternion(cols, keys, pieces_src, pieces_rows)
        for get, rows, given in zip(pieces_src, pieces_rows, mx_input):
            back_in = b.from_mx(given[:, _columns(rig, b)])
            for k in keys:
                path, i = k
                orig = get(path, i)
                if orig is None:
                    orig = back_in[k]
                delta = cols[k][rows] - back_in[k]
                if k[0] == b.rot_path and not quat:
                    delta = delta - 2 * np.pi * np.round(delta / (2 * np.pi))
                out.setdefault(k, cols[k].copy())[rows] = orig + delta
            rows_done[rows] = True
        # The gap rows: SP's curve, by whole turns continuing the row before.
        if not quat:
            for k in keys:
                if k[0] != b.rot_path:
                    continue
                v = out[k]
                for start in np.nonzero(~rows_done[1:] & rows_done[:-1])[0]:
                    end = start + 1
                    while end < n_frames and not rows_done[end]:
                        end += 1
                    turn = np.round((v[start] - cols[k][start]) / (2 * np.pi))
                    v[start + 1 : end] = cols[k][start + 1 : end] + 2 * np.pi * turn
    return out


def _columns(rig, bone):
    first = rig.dofs.index(bone.dofs()[0])
    return slice(first, first + len(bone.dofs()))


def _align_quaternion(cols, keys, pieces_src, pieces_rows):
    """Flip SP's (continuous) quaternion series when it starts opposite the keys."""
    get, rows = pieces_src[0], pieces_rows[0]
    rk = [k for k in keys if "rotation_quaternion" in k[0]]
    orig = [get(*k) for k in rk]
    if any(o is None for o in orig):
        return
    dot = sum(cols[k][rows[0]] * o[0] for k, o in zip(rk, orig))
    if dot < 0:
        for k in rk:
            cols[k] *= -1
