"""An armature's pose channels <-> mx DOFs.

mx sees an armature as a BVH skeleton: one joint per bone (parents first),
its rotation as three Euler DOFs `Bone.Xrotation` ... in the bone's own Euler
order (Blender's importer gives a BVH bone the file's order), and translation
DOFs `Bone.Xposition` ... on the root and on bones whose location is animated;
radians and metres, y up. A BVH joint's rest frame is the world's, a Blender
bone's is its own (matrix_local), so a pose rotation P is mx's rotation
R = B P B^T with B the bone's rest orientation in mx's axes: exactly the
conjugation Blender's BVH importer applies, so a clip imported by Blender
maps back to the file's values (to float32, what F-curves store).

Blender units are taken as metres (import a centimetre BVH with scale 0.01).
"""

import os
import tempfile

import numpy as np

from . import rotations as rot

# Blender armature space is z-up, mx's (BVH's, glTF's) y-up: (x, y, z) -> (x, z, -y).
TO_MX = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])

_BODIES = {}


class RigError(Exception):
    """An armature mx cannot map (said why)."""


def joint_name(bone):
    """mx's joint name of a bone: its DOFs are `joint.channel`, so `.`
    (Blender's "thigh.L") and spaces become `_`, as mx's glTF reader does."""
    return "".join("_" if c == "." or c.isspace() else c for c in bone)


def location_path(bone):
    return _path(bone, "location")


def _path(bone, prop):
    return 'pose.bones["%s"].%s' % (bone.replace("\\", "\\\\").replace('"', '\\"'), prop)


class Bone:
    """One bone's share of the mapping."""

    def __init__(self, pose_bone, parent_head, has_loc):
        b = pose_bone.bone
        self.name = b.name
        self.joint = joint_name(b.name)
        self.mode = pose_bone.rotation_mode
        if self.mode == "AXIS_ANGLE":
            raise RigError(f"bone {self.name!r}: axis-angle rotation is not supported; use Euler or quaternion")
        head = np.array(b.head_local, dtype=float)
        # Rest orientation in mx's axes, and the joint's offset from its parent's.
        self.rest = TO_MX @ np.array(b.matrix_local.to_3x3(), dtype=float)
        self.offset = TO_MX @ (head - parent_head)
        self.head = head
        self.tail = np.array(b.tail_local, dtype=float)
        self.has_loc = has_loc
        # mx's channel order: the Euler mode's letters (a BVH import's own order).
        self.order = "ZXY" if self.mode == "QUATERNION" else self.mode
        self.children = [c.name for c in b.children]
        self.loc_path = _path(self.name, "location")
        self.rot_path = _path(self.name, "rotation_quaternion" if self.mode == "QUATERNION" else "rotation_euler")

    def dofs(self):
        pos = [f"{self.joint}.{a}position" for a in "XYZ"] if self.has_loc else []
        return pos + [f"{self.joint}.{a}rotation" for a in self.order]

    def curves(self):
        """(data_path, index) of the F-curves this bone reads and writes."""
        out = [(self.loc_path, i) for i in range(3)] if self.has_loc else []
        return out + [(self.rot_path, i) for i in range(4 if self.mode == "QUATERNION" else 3)]

    def to_mx(self, get, nt):
        """[T, k] mx values from the bone's channels over nt frames;
        `get(path, index)` gives a channel's values (None: not animated, so
        its rest value)."""
        cols = []
        rest = np.zeros(nt)
        if self.has_loc:
            loc = np.stack([_or(get(self.loc_path, i), rest) for i in range(3)], 1)
            cols.append(loc @ self.rest.T + self.offset)
        if self.mode == "QUATERNION":
            q = np.stack([_or(get(self.rot_path, i), rest + (1.0 if i == 0 else 0.0)) for i in range(4)], 1)
            p = rot.quaternion_to_matrix(q)
        else:
            e = [_or(get(self.rot_path, i), rest) for i in range(3)]
            order = rot.blender_order(self.mode)
            p = rot.euler_to_matrix(np.stack([e[rot._AXIS[a]] for a in order], 1), order)
        r = self.rest @ p @ self.rest.T
        cols.append(np.unwrap(rot.matrix_to_euler(r, self.order), axis=0))
        return np.concatenate(cols, 1)

    def from_mx(self, v):
        """The bone's channels {(path, index): values} from mx values [T, k]."""
        out = {}
        k = 0
        if self.has_loc:
            loc = (v[:, 0:3] - self.offset) @ self.rest
            for i in range(3):
                out[(self.loc_path, i)] = loc[:, i]
            k = 3
        r = rot.euler_to_matrix(v[:, k : k + 3], self.order)
        p = self.rest.T @ r @ self.rest
        if self.mode == "QUATERNION":
            q = rot.matrix_to_quaternion(p)
            for i in range(4):
                out[(self.rot_path, i)] = q[:, i]
        else:
            order = rot.blender_order(self.mode)
            e = np.unwrap(rot.matrix_to_euler(p, order), axis=0)
            for n, a in enumerate(order):
                out[(self.rot_path, rot._AXIS[a])] = e[:, n]
        return out


def _or(values, rest):
    return rest if values is None else values


def _frames(get, bones):
    """How many frames the channels span (any animated channel's length)."""
    for b in bones:
        for k in b.curves():
            x = get(*k)
            if x is not None:
                return len(x)
    raise RigError("the action animates none of the armature's bones")


class Rig:
    """The mapping for one armature: bones parents first, one root."""

    def __init__(self, arm, animated_paths):
        """`animated_paths`: the data paths the actions animate; a non-root
        bone gets translation DOFs when its location is among them."""
        roots = [b for b in arm.pose.bones if b.parent is None]
        if len(roots) != 1:
            raise RigError(f"armature {arm.name!r} has {len(roots)} root bones; mx needs exactly one")
        self.bones = []
        stack = [(roots[0], np.zeros(3), True)]
        while stack:
            pb, parent_head, is_root = stack.pop()
            bone = Bone(pb, parent_head, is_root or _path(pb.name, "location") in animated_paths)
            self.bones.append(bone)
            for c in reversed(pb.children):
                stack.append((c, bone.head, False))
        self.dofs = [d for b in self.bones for d in b.dofs()]
        joints = [b.joint for b in self.bones]
        clash = sorted({j for j in joints if joints.count(j) > 1})
        if clash:
            raise RigError(f"bones {clash} name the same mx joint once `.` and spaces become `_`; rename one")
        self.fps = None

    def curves(self):
        return [c for b in self.bones for c in b.curves()]

    def rotation_columns(self):
        """Indices of the rotation DOFs (angles: whole turns are free)."""
        return np.array([i for i, d in enumerate(self.dofs) if d.endswith("rotation")], dtype=int)

    def to_mx(self, get):
        """[T, D] mx values from the channels (`get` as for Bone.to_mx), the
        bones of one rotation mode at once: one NumPy pass per mode instead
        of one per bone (the glue's cost on a 30-bone rig)."""
        first = {}
        k = 0
        for b in self.bones:
            first[b.name] = k
            k += len(b.dofs())
        nt = _frames(get, self.bones)
        out = np.empty((nt, len(self.dofs)))
        groups = {}
        for b in self.bones:
            groups.setdefault(b.mode, []).append(b)
        for mode, bones in groups.items():
            if mode == "QUATERNION":
                for b in bones:  # rare in mocap rigs: one bone at a time
                    v = b.to_mx(get, nt)
                    out[:, first[b.name] : first[b.name] + v.shape[1]] = v
                continue
            order = rot.blender_order(mode)
            ang = np.zeros((len(bones), nt, 3))  # [B, T, 3], a channel not animated stays 0
            for j, b in enumerate(bones):
                for n, a in enumerate(order):
                    x = get(b.rot_path, rot._AXIS[a])
                    if x is not None:
                        ang[j, :, n] = x
            nb = len(bones)
            p = rot.euler_to_matrix(ang.reshape(-1, 3), order).reshape(nb, nt, 3, 3)
            rest = np.stack([b.rest for b in bones])[:, None]
            r = rest @ p @ np.swapaxes(rest, -1, -2)
            e = np.unwrap(rot.matrix_to_euler(r.reshape(-1, 3, 3), mode).reshape(nb, nt, 3), axis=1)
            for j, b in enumerate(bones):
                c = first[b.name]
                if b.has_loc:
                    loc = np.stack([_or(get(b.loc_path, i), np.zeros(nt)) for i in range(3)], 1)
                    out[:, c : c + 3] = loc @ b.rest.T + b.offset
                    c += 3
                out[:, c : c + 3] = e[j]
        return out

    def from_named(self, names, raw):
        """[T, D] in the rig's DOFs from a motion's columns (`names`, raw
        [T, K]): a joint's rotation given in another Euler order (a glTF
        file's Z X Y, say) is converted; what the motion lacks is the rest pose."""
        col = {d: i for i, d in enumerate(names)}
        rots = {}
        for d in names:
            # a bare name (an OpenSim coordinate) is no bone's channel
            joint, _, ch = d.rpartition(".")
            if joint and ch.endswith("rotation"):
                rots.setdefault(joint, []).append(d)
        out = np.zeros((raw.shape[0], len(self.dofs)))
        k = 0
        for b in self.bones:
            if b.has_loc:
                for i, a in enumerate("XYZ"):
                    d = f"{b.joint}.{a}position"
                    out[:, k + i] = raw[:, col[d]] if d in col else b.offset[i]
                k += 3
            given = rots.get(b.joint, [])
            if len(given) == 3:
                order = "".join(d.rsplit(".", 1)[1][0] for d in given)
                ang = raw[:, [col[d] for d in given]]
                if order != b.order:
                    ang = np.unwrap(rot.matrix_to_euler(rot.euler_to_matrix(ang, order), b.order), axis=0)
                out[:, k : k + 3] = ang
            k += 3
        return out

    def from_mx(self, values):
        out = {}
        k = 0
        for b in self.bones:
            n = len(b.dofs())
            out.update(b.from_mx(values[:, k : k + n]))
            k += n
        return out

    def rest_bvh(self, frame_time):
        """The skeleton as BVH text (metres, y up) with two rest frames: what
        mx's `body_of` builds the body from."""
        lines = ["HIERARCHY"]
        by_name = {b.name: b for b in self.bones}

        def joint(b, depth):
            ind = "\t" * depth
            lines.append(f"{ind}{'ROOT' if depth == 0 else 'JOINT'} {b.joint}")
            lines.append(f"{ind}{{")
            lines.append(f"{ind}\tOFFSET {b.offset[0]:.17g} {b.offset[1]:.17g} {b.offset[2]:.17g}")
            ch = [a + "position" for a in "XYZ"] if b.has_loc else []
            ch += [a + "rotation" for a in b.order]
            lines.append(f"{ind}\tCHANNELS {len(ch)} {' '.join(ch)}")
            if b.children:
                for c in b.children:
                    joint(by_name[c], depth + 1)
            else:
                e = TO_MX @ (b.tail - b.head)
                lines.append(f"{ind}\tEnd Site")
                lines.append(f"{ind}\t{{")
                lines.append(f"{ind}\t\tOFFSET {e[0]:.17g} {e[1]:.17g} {e[2]:.17g}")
                lines.append(f"{ind}\t}}")
            lines.append(f"{ind}}}")

        joint(self.bones[0], 0)
        zeros = " ".join(["0"] * len(self.dofs))
        lines += ["MOTION", "Frames: 2", f"Frame Time: {frame_time:.17g}", zeros, zeros]
        return "\n".join(lines) + "\n"

    def body(self, mx, frame_time, mass=70.0):
        """mx's body of the skeleton (`body_of` on the rest BVH), cached per
        skeleton: building it parses a file."""
        text = self.rest_bvh(frame_time)
        key = (text, mass)
        if key not in _BODIES:
            fd, path = tempfile.mkstemp(suffix=".bvh", prefix="mx_rest_")
            try:
                with os.fdopen(fd, "w") as f:
                    f.write(text)
                clip = mx.load(path, unit=1.0)
            finally:
                os.unlink(path)
            missing = set(self.dofs) ^ set(clip.dofs)
            if missing:
                raise RigError(f"mx named the skeleton's DOFs differently: {sorted(missing)[:5]}")
            _BODIES.clear()  # one armature at a time is the common case; keep memory flat
            _BODIES[key] = mx.body_of(clip, mass)
        return _BODIES[key]
