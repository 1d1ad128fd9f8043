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
    """Quaternions [T, 4] (w, x, y, z) of rotations r, signs continuous in time."""
    t = np.einsum("tii->t", r)
    w = np.sqrt(np.maximum(0.0, 1 + t)) / 2
    x = np.sqrt(np.maximum(0.0, 1 + r[:, 0, 0] - r[:, 1, 1] - r[:, 2, 2])) / 2
    y = np.sqrt(np.maximum(0.0, 1 - r[:, 0, 0] + r[:, 1, 1] - r[:, 2, 2])) / 2
    z = np.sqrt(np.maximum(0.0, 1 - r[:, 0, 0] - r[:, 1, 1] + r[:, 2, 2])) / 2
    x = np.copysign(x, r[:, 2, 1] - r[:, 1, 2])
    y = np.copysign(y, r[:, 0, 2] - r[:, 2, 0])
    z = np.copysign(z, r[:, 1, 0] - r[:, 0, 1])
    q = np.stack([w, x, y, z], 1)
    flips = np.cumsum(np.r_[False, np.einsum("ti,ti->t", q[1:], q[:-1]) < 0]) % 2 == 1
    q[flips] *= -1
    return q


def nearest_turn(values, reference):
    """`values` moved by whole turns (2 pi) to be nearest `reference`."""
    return values + 2 * np.pi * np.round((reference - values) / (2 * np.pi))
