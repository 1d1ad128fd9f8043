"""The new action's channels from SP's result.

Where SP left a bone's DOFs as they were (outside the gap, bit for bit) its
channels are the original keys, copied: no float32 round trip through the
bone mapping, and no mapping work. Where SP changed them outside the gap
(the root moved by root: "shift") the original keys get SP's change mapped
into the channels; in the gap the channels are SP's motion mapped back,
as the Euler triples (whole turns, branch) or quaternion signs that
continue the keys before it."""

import numpy as np

_AXIS = {"X": 0, "Y": 1, "Z": 2}


def channels(rig, pieces_src, pieces_rows, mx_input, mx_filled, n_frames):
    """{(path, index): values [n_frames]}.

    pieces_src: per piece, `get(path, index)` of its original keys (None:
    not animated); pieces_rows: per piece, its rows in the grid; mx_input:
    per piece, the mx values SP was given for it (after any turn shift);
    mx_filled: SP's values on the whole grid [n_frames, D]."""
    out = {}
    in_piece = np.zeros(n_frames, dtype=bool)
    for rows in pieces_rows:
        in_piece[rows] = True
    gap_rows = np.nonzero(~in_piece)[0]
    first = 0
    for b in rig.bones:
        cols = slice(first, first + len(b.dofs()))
        first = cols.stop
        keys = b.curves()
        v = {k: np.empty(n_frames) for k in keys}
        for get, rows, given in zip(pieces_src, pieces_rows, mx_input):
            orig = {k: get(*k) for k in keys}
            changed = np.any(mx_filled[rows, cols] != given[:, cols], axis=1)
            if changed.any() or any(o is None for o in orig.values()):
                # SP's change (or a rest value) mapped into the channels.
                back_in = b.from_mx(given[:, cols])
                back_sp = b.from_mx(mx_filled[rows, cols])
                for k in keys:
                    base = back_in[k] if orig[k] is None else orig[k]
                    delta = back_sp[k] - back_in[k]
                    if k[0] == b.rot_path and b.mode != "QUATERNION":
                        delta = _wrap(delta)
                    v[k][rows] = base + delta
            else:
                for k in keys:
                    v[k][rows] = orig[k]
        for s0, e0 in _runs(gap_rows):
            back = b.from_mx(mx_filled[s0:e0, cols])
            for k in keys:
                v[k][s0:e0] = back[k]
            _continue_rotation(b, v, s0, e0)
        out.update(v)
    return out


def _runs(rows):
    """[(start, stop)] of the runs of consecutive integers in `rows`."""
    if len(rows) == 0:
        return []
    cut = np.nonzero(np.diff(rows) > 1)[0]
    starts = np.r_[rows[0], rows[cut + 1]]
    stops = np.r_[rows[cut] + 1, rows[-1] + 1]
    return list(zip(starts, stops))


def _continue_rotation(b, v, s0, e0):
    """Rows s0..e0 of the bone's rotation channels made to continue row s0 - 1."""
    if s0 == 0:
        return
    if b.mode == "QUATERNION":
        rk = [(b.rot_path, i) for i in range(4)]
        if sum(v[k][s0] * v[k][s0 - 1] for k in rk) < 0:
            for k in rk:
                v[k][s0:e0] *= -1
        return
    rk = [(b.rot_path, i) for i in range(3)]
    e = np.stack([v[k][s0:e0] for k in rk], 1)
    prev = np.array([v[k][s0 - 1] for k in rk])
    c = _continuing(e, prev, [_AXIS[a] for a in b.mode[::-1]])
    for n, k in enumerate(rk):
        v[k][s0:e0] = c[:, n]


def _wrap(a):
    return a - 2 * np.pi * np.round(a / (2 * np.pi))


def _continuing(e, prev, order):
    """Rows e [T, 3] (slots x, y, z; `order`: the slots from outer to inner
    angle) as the Euler triples of the same rotations that continue `prev`:
    each row the solution (e or its dual, a+pi, pi-b, c+pi) on the branch the
    rows before it are on, then moved by whole turns. Vectorised: the branch
    flips where a row's dual is nearer the row before than the row itself."""
    dual = e.copy()
    dual[:, order[0]] += np.pi
    dual[:, order[1]] = np.pi - dual[:, order[1]]
    dual[:, order[2]] += np.pi

    def dist(a, b):
        return np.abs(_wrap(a - b)).sum(-1)

    first_dual = dist(dual[0], prev) < dist(e[0], prev)
    flips = np.r_[False, dist(dual[1:], e[:-1]) < dist(e[1:], e[:-1])]
    branch = (np.cumsum(flips) % 2 == 1) ^ first_dual
    c = np.where(branch[:, None], dual, e)
    return np.unwrap(np.vstack([prev, c]), axis=0)[1:]
