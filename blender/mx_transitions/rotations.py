"""Rotation matrices from Euler angles and quaternions and back, vectorised
over frames with NumPy (no bpy: Blender's mathutils works one value at a time,
which is what makes a Python glue slow).

An order string "ZXY" means R = Rz(a0) · Rx(a1) · Ry(a2): the BVH (and mx)
convention, the angles in the order of the letters. Blender's Euler mode
"XYZ" is R = Rz · Ry · Rx, i.e. this module's order "ZYX" with the angles read
from the x, y, z slots; `blender_order` converts.
"""

import numpy as np

_AXIS = {"X": 0, "Y": 1, "Z": 2}


def blender_order(mode):
    """This module's order for a Blender Euler rotation mode ("XYZ" -> "ZYX")."""
    return mode[::-1]


def axis_matrices(axis, angles):
    """[T, 3, 3] rotations by `angles` (radians) about axis 0, 1 or 2."""
    c, s = np.cos(angles), np.sin(angles)
    m = np.zeros((len(angles), 3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m[:, axis, axis] = 1.0
    m[:, i, i] = c
    m[:, j, j] = c
    m[:, i, j] = -s
    m[:, j, i] = s
    return m


def euler_to_matrix(angles, order):
    """[T, 3, 3] from angles [T, 3] given in the order of `order`'s letters."""
    r = axis_matrices(_AXIS[order[0]], angles[:, 0])
    for k in (1, 2):
        r = r @ axis_matrices(_AXIS[order[k]], angles[:, k])
    return r


def matrix_to_euler(r, order):
    """Angles [T, 3] (in `order`'s letter order) of rotations r [T, 3, 3];
    the middle angle in [-pi/2, pi/2]."""
    i, j, k = (_AXIS[a] for a in order)
    # Even permutations of XYZ have sign +1, odd ones -1.
    s = 1.0 if (j - i) % 3 == 1 else -1.0
    out = np.empty((r.shape[0], 3))
    out[:, 1] = np.arcsin(np.clip(s * r[:, i, k], -1.0, 1.0))
    out[:, 0] = np.arctan2(-s * r[:, j, k], r[:, k, k])
    out[:, 2] = np.arctan2(-s * r[:, i, j], r[:, i, i])
    return out


def quaternion_to_matrix(q):
    """[T, 3, 3] from quaternions [T, 4] (w, x, y, z), normalised first."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        1,
    )


def matrix_to_quaternion(r):
    """Quaternions [T, 4] (w, x, y, z) of rotations r, signs continuous in time.

    Shepperd's method: per row the largest component from the diagonal, the
    others from off-diagonal sums and differences. (Taking every component's
    size from the diagonal turns a 1e-7 non-orthogonality of a float32 rest
    matrix into a 3e-4 rad error near the identity.)"""
    r00, r11, r22 = r[:, 0, 0], r[:, 1, 1], r[:, 2, 2]
    cand = np.stack([1 + r00 + r11 + r22, 1 + r00 - r11 - r22, 1 - r00 + r11 - r22, 1 - r00 - r11 + r22], 1)
    big = np.argmax(cand, 1)
    s = np.sqrt(np.maximum(cand[np.arange(len(r)), big], 1e-300)) * 2  # 4 * the largest component
    d21, d02, d10 = r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]
    s01, s02, s12 = r[:, 0, 1] + r[:, 1, 0], r[:, 0, 2] + r[:, 2, 0], r[:, 1, 2] + r[:, 2, 1]
    rows = [
        np.stack([s / 4, d21 / s, d02 / s, d10 / s], 1),
        np.stack([d21 / s, s / 4, s01 / s, s02 / s], 1),
        np.stack([d02 / s, s01 / s, s / 4, s12 / s], 1),
        np.stack([d10 / s, s02 / s, s12 / s, s / 4], 1),
    ]
    q = np.choose(big[:, None], rows)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    flips = np.cumsum(np.r_[False, np.einsum("ti,ti->t", q[1:], q[:-1]) < 0]) % 2 == 1
    q[flips] *= -1
    return q
