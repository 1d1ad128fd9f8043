//! A glTF skeleton animation read back as a clip, through the BVH clip model:
//! the skin's joints become BVH joints (offset = the node's rest translation,
//! in metres), every joint gets `Zrotation Xrotation Yrotation` channels (the
//! node's rotation as intrinsic Z·X·Y Euler angles, glTF having no Euler
//! order of its own), a root also `Xposition Yposition Zposition`, and so does
//! any other joint whose translation is animated away from its rest. The motion
//! is then the one a BVH file with those channels gives (`Joint.Zrotation`, …,
//! radians and metres, cubic between frames), and `body_of` builds its body.
//!
//! Frames: keys are resampled on a uniform grid (the densest channel's key
//! spacing) from the first key, which becomes t = 0. Interpolation follows the
//! sampler (LINEAR with slerp, STEP, CUBICSPLINE); at a key the key's value is
//! taken as is. Static transforms of nodes above or between joints (an
//! exporter's armature node, its unit scale) are folded into the joints below
//! them; uniform scales become lengths in metres.
//!
//! A file mx wrote says more in each node's `extras.mx`: the joint's mass
//! properties (given back as [`Skeleton::inertias`], so `body_of` builds the
//! saved body) and its BVH channels (then read in that order, Euler order
//! included, instead of Z·X·Y: the saved body's own coordinates).
//!
//! Ignored, each with a note: other animations and skins, meshes, scale and
//! morph-weight channels, animation of nodes that are not joints, non-uniform
//! scale.

use std::collections::BTreeSet;
use std::path::Path;

use nalgebra::{Matrix3, Matrix4, Quaternion, Rotation3, UnitQuaternion, Vector3};

use super::GltfError;
use crate::mocap::bvh::{BvhFile, BvhJoint, Channel, Skeleton, Units};
use crate::mocap::{Clip, from_bvh};
use crate::model::Inertia;

/// Which animation of a file to read.
#[derive(Clone, Debug, Default)]
pub enum Which {
    /// The first one.
    #[default]
    First,
    /// The one with this name.
    Name(String),
    /// By position, 0 first.
    Index(usize),
}

/// A glTF animation read as a clip, and what the reader left out.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub clip: Clip,
    /// The animation read.
    pub animation: String,
    /// Every animation in the file, in order.
    pub animations: Vec<String>,
    /// What was ignored, one sentence each.
    pub notes: Vec<String>,
}

/// Reads `path` (`.glb` or `.gltf`; a `.gltf`'s buffers may be `data:` URIs or
/// files beside it).
pub fn load(path: &Path, which: Which) -> Result<Loaded, GltfError> {
    let bytes = std::fs::read(path).map_err(|source| crate::io::FileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    from_bytes(&bytes, path.parent(), which)
}

/// Reads a glTF document from memory; `base` is the folder relative buffer
/// URIs are resolved against.
pub fn from_bytes(bytes: &[u8], base: Option<&Path>, which: Which) -> Result<Loaded, GltfError> {
    let gltf = ::gltf::Gltf::from_slice(bytes)
        .map_err(|e| GltfError::invalid(format!("not a valid glTF 2.0 file: {e}")))?;
    let doc = &gltf.document;
    let buffers = buffers(&gltf, base)?;
    let mut notes = Vec::new();

    let animations: Vec<String> = doc
        .animations()
        .map(|a| {
            a.name()
                .map(str::to_string)
                .unwrap_or_else(|| format!("animation {}", a.index()))
        })
        .collect();
    if animations.is_empty() {
        return Err(GltfError::invalid(format!(
            "the file has no animation ({} nodes, {} skins, {} meshes): mx reads skeleton animations",
            doc.nodes().len(),
            doc.skins().len(),
            doc.meshes().len()
        )));
    }
    let index = match &which {
        Which::First => 0,
        Which::Index(k) if *k < animations.len() => *k,
        Which::Index(k) => {
            return Err(GltfError::invalid(format!(
                "animation {k} does not exist: the file has {} (0 to {})",
                animations.len(),
                animations.len() - 1
            )));
        }
        Which::Name(n) => animations.iter().position(|a| a == n).ok_or_else(|| {
            GltfError::invalid(format!(
                "no animation named `{n}`; the file has: {}",
                animations.join(", ")
            ))
        })?,
    };
    if animations.len() > 1 {
        notes.push(format!(
            "read animation `{}`; the file has {} (choose with `animation:`): {}",
            animations[index],
            animations.len(),
            animations.join(", ")
        ));
    }
    let anim = doc.animations().nth(index).expect("index checked");

    // The skin whose joints the animation moves most.
    let targeted: BTreeSet<usize> = anim.channels().map(|c| c.target().node().index()).collect();
    let skin = doc
        .skins()
        .max_by_key(|s| (s.joints().filter(|j| targeted.contains(&j.index())).count(), usize::MAX - s.index()))
        .ok_or_else(|| {
            GltfError::invalid("the file has no skin (skeleton): mx reads skeleton animations, and this one moves plain nodes")
        })?;
    if doc.skins().len() > 1 {
        notes.push(format!(
            "read skin {} of {}; the others are ignored",
            skin.index(),
            doc.skins().len()
        ));
    }
    if doc.meshes().len() > 0 {
        notes.push(format!(
            "{} meshes ignored (mx reads the skeleton)",
            doc.meshes().len()
        ));
    }

    let mut skeleton = SkinTree::new(doc, &skin, &mut notes)?;
    skeleton.read_extras(&raw_json(bytes), index, &mut notes);
    let tracks = Tracks::new(&anim, &skeleton, &buffers, &mut notes)?;
    let file = skeleton.sample(&tracks)?;
    let clip = from_bvh(&file, Units::MetresPerUnit(1.0))?;
    Ok(Loaded {
        clip,
        animation: animations[index].clone(),
        animations,
        notes,
    })
}

/// The data of every buffer: the GLB's BIN chunk, a base64 `data:` URI, or a file.
fn buffers(gltf: &::gltf::Gltf, base: Option<&Path>) -> Result<Vec<Vec<u8>>, GltfError> {
    gltf.document
        .buffers()
        .map(|b| {
            let data = match b.source() {
                ::gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                    GltfError::invalid("buffer 0 refers to a BIN chunk the file does not have")
                })?,
                ::gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                    let Some((_, data)) = uri.split_once(";base64,") else {
                        return Err(GltfError::invalid(format!(
                            "buffer {}: only base64 data URIs are read",
                            b.index()
                        )));
                    };
                    use base64::Engine;
                    base64::engine::general_purpose::STANDARD
                        .decode(data)
                        .map_err(|e| {
                            GltfError::invalid(format!("buffer {}: bad base64: {e}", b.index()))
                        })?
                }
                ::gltf::buffer::Source::Uri(uri) => {
                    let p = base.unwrap_or(Path::new(".")).join(percent_decode(uri));
                    std::fs::read(&p)
                        .map_err(|source| crate::io::FileError::Read { path: p, source })?
                }
            };
            if data.len() < b.length() {
                return Err(GltfError::invalid(format!(
                    "buffer {} holds {} bytes, the file says {}",
                    b.index(),
                    data.len(),
                    b.length()
                )));
            }
            Ok(data)
        })
        .collect()
}

/// The channels a node's `extras.mx.channels` states, if they are ones the
/// reader can write: three rotations about distinct axes (an Euler order),
/// with no position or all three.
fn stated_channels(v: &serde_json::Value) -> Option<Vec<Channel>> {
    let channels: Vec<Channel> = v
        .as_array()?
        .iter()
        .map(|c| c.as_str().and_then(Channel::parse))
        .collect::<Option<_>>()?;
    let axes = |rotation: bool| {
        let mut a: Vec<usize> = channels
            .iter()
            .filter(|c| c.is_rotation() == rotation)
            .map(|c| c.axis())
            .collect();
        a.sort_unstable();
        a
    };
    let positions = axes(false);
    (axes(true) == [0, 1, 2] && (positions.is_empty() || positions == [0, 1, 2]))
        .then_some(channels)
}

/// The document's JSON as plain JSON, for what the `gltf` crate does not
/// keep (node `extras`): a GLB's first chunk, or the whole `.gltf` file.
/// `Null` when it does not parse (the `gltf` crate has read it already).
pub(super) fn raw_json(bytes: &[u8]) -> serde_json::Value {
    let json = match bytes {
        [
            b'g',
            b'l',
            b'T',
            b'F',
            _,
            _,
            _,
            _,
            _,
            _,
            _,
            _,
            l0,
            l1,
            l2,
            l3,
            b'J',
            b'S',
            b'O',
            b'N',
            rest @ ..,
        ] => {
            let len = u32::from_le_bytes([*l0, *l1, *l2, *l3]) as usize;
            rest.get(..len).unwrap_or(&[])
        }
        _ => bytes,
    };
    serde_json::from_slice(json).unwrap_or(serde_json::Value::Null)
}

/// `%20` and friends in a relative URI.
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && let Some(h) = uri
                .get(i + 1..i + 3)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(h);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// A static node transform split into uniform scale, rotation and translation.
#[derive(Clone, Copy, Debug)]
struct Similarity {
    s: f64,
    r: Matrix3<f64>,
    p: Vector3<f64>,
}

impl Similarity {
    fn identity() -> Self {
        Similarity {
            s: 1.0,
            r: Matrix3::identity(),
            p: Vector3::zeros(),
        }
    }

    fn compose(&self, o: &Similarity) -> Similarity {
        Similarity {
            s: self.s * o.s,
            r: self.r * o.r,
            p: self.p + self.s * (self.r * o.p),
        }
    }

    /// A node's matrix; a non-uniform scale is averaged (with a note by the caller).
    fn of_matrix(m: &Matrix4<f64>) -> (Similarity, bool) {
        let a = m.fixed_view::<3, 3>(0, 0).into_owned();
        let cols = [a.column(0).norm(), a.column(1).norm(), a.column(2).norm()];
        let s = (cols[0] * cols[1] * cols[2]).cbrt();
        let uniform = cols.iter().all(|c| (c - s).abs() <= 1e-5 * s.max(1e-12));
        let r = if s > 0.0 { a / s } else { Matrix3::identity() };
        // Orthonormalise: the nearest rotation (the matrix is a rotation up to rounding).
        let r = Rotation3::from_matrix(&r).into_inner();
        (
            Similarity {
                s,
                r,
                p: m.fixed_view::<3, 1>(0, 3).into_owned(),
            },
            uniform,
        )
    }
}

/// One joint of the skin as read.
#[derive(Clone, Debug)]
struct SkinJoint {
    node: usize,
    name: String,
    parent: Option<usize>,
    /// Static transforms of the non-joint nodes between the parent joint (or
    /// the scene root) and this joint.
    pre: Similarity,
    /// Scale of the parent joint's frame (lengths below it are multiplied by it).
    parent_scale: f64,
    /// The node's rest translation, rotation and uniform scale.
    rest_t: Vector3<f64>,
    rest_r: UnitQuaternion<f64>,
    scale: f64,
    /// Offsets (parent-joint frame, metres) of non-joint leaf children: BVH End Sites.
    end_sites: Vec<Vector3<f64>>,
    /// The mass properties in the node's `extras.mx` (a file mx wrote).
    inertia: Option<Inertia>,
    /// The BVH channels in the node's `extras.mx`: three rotations about
    /// distinct axes, with none or all three positions (see [`stated_channels`]).
    channels: Option<Vec<Channel>>,
    /// Frame ranges (first, last) whose Euler angles are the non-principal
    /// triple (see `write::flipped_frames`).
    flipped: Vec<(usize, usize)>,
}

/// The skin's joints in depth-first order (parents first).
struct SkinTree {
    joints: Vec<SkinJoint>,
}

impl SkinTree {
    fn new(
        doc: &::gltf::Document,
        skin: &::gltf::Skin,
        notes: &mut Vec<String>,
    ) -> Result<SkinTree, GltfError> {
        let n = doc.nodes().len();
        let mut parent = vec![None; n];
        for node in doc.nodes() {
            for c in node.children() {
                parent[c.index()] = Some(node.index());
            }
        }
        let nodes: Vec<::gltf::Node> = doc.nodes().collect();
        let is_joint: BTreeSet<usize> = skin.joints().map(|j| j.index()).collect();
        if is_joint.is_empty() {
            return Err(GltfError::invalid("the skin has no joints"));
        }
        let mut non_uniform = Vec::new();
        let matrix = |i: usize| Matrix4::from_fn(|r, c| nodes[i].transform().matrix()[c][r] as f64);
        // Nearest joint ancestor and the static transforms on the way to it.
        let joint_parent = |j: usize, non_uniform: &mut Vec<String>| {
            let mut pre = Similarity::identity();
            let mut p = parent[j];
            while let Some(k) = p {
                if is_joint.contains(&k) {
                    return (Some(k), pre);
                }
                let (s, uniform) = Similarity::of_matrix(&matrix(k));
                if !uniform {
                    non_uniform.push(node_name(&nodes[k]));
                }
                pre = s.compose(&pre);
                p = parent[k];
            }
            (None, pre)
        };
        // Depth-first from the roots, in skin order.
        let skin_order: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let mut info = std::collections::BTreeMap::new();
        for &j in &skin_order {
            info.insert(j, joint_parent(j, &mut non_uniform));
        }
        let mut order = Vec::new();
        let mut stack: Vec<usize> = skin_order
            .iter()
            .rev()
            .copied()
            .filter(|j| info[j].0.is_none())
            .collect();
        while let Some(j) = stack.pop() {
            order.push(j);
            let kids: Vec<usize> = skin_order
                .iter()
                .copied()
                .filter(|k| info[k].0 == Some(j))
                .collect();
            stack.extend(kids.into_iter().rev());
        }
        if order.len() != skin_order.len() {
            return Err(GltfError::invalid("the skin's joints do not form a tree"));
        }
        let position: std::collections::BTreeMap<usize, usize> =
            order.iter().enumerate().map(|(i, &j)| (j, i)).collect();
        let mut names = BTreeSet::new();
        let mut renamed = 0;
        let mut joints: Vec<SkinJoint> = Vec::with_capacity(order.len());
        for &j in &order {
            let (t, r, s) = nodes[j].transform().decomposed();
            let sv = Vector3::new(s[0] as f64, s[1] as f64, s[2] as f64);
            let scale = (sv.x * sv.y * sv.z).abs().cbrt();
            if (sv.x - sv.y).abs() > 1e-5 * scale || (sv.x - sv.z).abs() > 1e-5 * scale {
                non_uniform.push(node_name(&nodes[j]));
            }
            let (p, pre) = info[&j];
            let parent = p.map(|p| position[&p]);
            let parent_scale = parent
                .map(|p: usize| joint_scale(&joints, p))
                .unwrap_or(1.0);
            let raw = node_name(&nodes[j]);
            let name = unique_name(&raw, &mut names);
            if name != raw {
                renamed += 1;
            }
            joints.push(SkinJoint {
                node: j,
                name,
                parent,
                pre,
                parent_scale,
                rest_t: Vector3::new(t[0] as f64, t[1] as f64, t[2] as f64),
                rest_r: unit(&[r[0] as f64, r[1] as f64, r[2] as f64, r[3] as f64]),
                scale,
                end_sites: Vec::new(),
                inertia: None,
                channels: None,
                flipped: Vec::new(),
            });
        }
        // Leaf children that are not joints (exporters' `_end` nodes) end the bones.
        for (i, sj) in joints.iter_mut().enumerate() {
            let own = sj.parent_scale * sj.pre.s * sj.scale;
            let _ = i;
            for c in nodes[sj.node].children() {
                if !is_joint.contains(&c.index()) && c.children().len() == 0 && c.mesh().is_none() {
                    let (t, _, _) = c.transform().decomposed();
                    sj.end_sites
                        .push(own * Vector3::new(t[0] as f64, t[1] as f64, t[2] as f64));
                }
            }
        }
        if renamed > 0 {
            notes.push(format!(
                "{renamed} joint names changed to be DOF-name safe (`.` and spaces become `_`; repeats get a number)"
            ));
        }
        if !non_uniform.is_empty() {
            notes.push(format!(
                "non-uniform scale ignored on: {}",
                non_uniform.join(", ")
            ));
        }
        Ok(SkinTree { joints })
    }

    /// What a file mx wrote states in `extras.mx`: each joint's mass
    /// properties (`write::mass_properties`: in the node's frame, which is
    /// the joint's own frame here unless a scale stands between them), its
    /// BVH channels, and the frames of the read animation where its Euler
    /// angles are not the principal ones (`write::flipped_frames`).
    fn read_extras(&mut self, raw: &serde_json::Value, animation: usize, notes: &mut Vec<String>) {
        let mut unread = Vec::new();
        let flipped = &raw["animations"][animation]["extras"]["mx"]["flipped"];
        for j in &mut self.joints {
            j.flipped = flipped[j.node.to_string()]
                .as_array()
                .map(|ranges| {
                    ranges
                        .iter()
                        .filter_map(|r| Some((r[0].as_u64()? as usize, r[1].as_u64()? as usize)))
                        .collect()
                })
                .unwrap_or_default();
            let extras = &raw["nodes"][j.node]["extras"]["mx"];
            if extras.is_null() {
                continue;
            }
            j.channels = stated_channels(&extras["channels"]);
            if extras["mass"].is_null() {
                continue;
            }
            let nums = |key: &str, n: usize| -> Option<Vec<f64>> {
                let v: Vec<f64> = extras[key]
                    .as_array()?
                    .iter()
                    .filter_map(|x| x.as_f64())
                    .collect();
                (v.len() == n).then_some(v)
            };
            let scaled = (j.parent_scale * j.pre.s * j.scale - 1.0).abs() > 1e-9;
            let read = (|| {
                let m = extras["mass"].as_f64()?;
                let c = nums("com", 3)?;
                let i = nums("inertia", 6)?;
                let i = Matrix3::new(i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2]);
                Inertia::from_com(m, Vector3::new(c[0], c[1], c[2]), i).ok()
            })();
            match read {
                Some(i) if !scaled => j.inertia = Some(i),
                _ => unread.push(j.name.clone()),
            }
        }
        if !unread.is_empty() {
            notes.push(format!(
                "mass properties in `extras.mx` not read (malformed, or under a scale) for: {}; body_of estimates them",
                unread.join(", ")
            ));
        }
    }

    /// The BVH data of the sampled animation (metres, degrees).
    fn sample(&self, tracks: &Tracks) -> Result<BvhFile, GltfError> {
        let n = self.joints.len();
        let frames = tracks.frames;
        // Local transform of each joint in its parent joint's frame, per frame.
        let mut rot: Vec<Vec<Matrix3<f64>>> = vec![Vec::with_capacity(frames); n];
        let mut pos: Vec<Vec<Vector3<f64>>> = vec![Vec::with_capacity(frames); n];
        for (i, j) in self.joints.iter().enumerate() {
            let (tt, rt) = (&tracks.translation[i], &tracks.rotation[i]);
            for k in 0..frames {
                let t = tracks.times[k];
                let tr = tt.as_ref().map(|x| x.vec3(t)).unwrap_or(j.rest_t);
                let q = rt.as_ref().map(|x| x.quat(t)).unwrap_or(j.rest_r);
                let c = j.parent_scale;
                pos[i].push(c * (j.pre.p + j.pre.s * (j.pre.r * tr)));
                rot[i].push(j.pre.r * q.to_rotation_matrix().into_inner());
            }
        }
        // A leaf joint nothing animates only marks where its parent's bone ends
        // (mx writes BVH End Sites so): it becomes an End Site of its parent.
        let has_children: Vec<bool> = (0..n)
            .map(|i| self.joints.iter().any(|j| j.parent == Some(i)))
            .collect();
        let end_site: Vec<bool> = (0..n)
            .map(|i| {
                self.joints[i].parent.is_some()
                    && !has_children[i]
                    && tracks.translation[i].is_none()
                    && tracks.rotation[i].is_none()
                    && self.joints[i].inertia.is_none_or(|m| m.is_zero())
            })
            .collect();
        let mut index = vec![usize::MAX; n];
        let mut skeleton = Skeleton::default();
        let mut moving = vec![false; n];
        for (i, j) in self.joints.iter().enumerate() {
            let rest = j.parent_scale * (j.pre.p + j.pre.s * (j.pre.r * j.rest_t));
            if end_site[i] {
                let p = index[j.parent.expect("an end site has a parent")];
                skeleton.joints[p].end_sites.push(rest);
                continue;
            }
            moving[i] = j.parent.is_none() || pos[i].iter().any(|p| (p - rest).norm() > 1e-6);
            // the channels the file states (the saved body's own DOFs), unless
            // they leave out a translation the animation has
            let stated = j
                .channels
                .clone()
                .filter(|c| !moving[i] || c.iter().any(|c| !c.is_rotation()));
            let channels = stated.unwrap_or_else(|| {
                let mut c = Vec::new();
                if moving[i] {
                    c.extend([Channel::Xposition, Channel::Yposition, Channel::Zposition]);
                }
                c.extend([Channel::Zrotation, Channel::Xrotation, Channel::Yrotation]);
                c
            });
            index[i] = skeleton.joints.len();
            skeleton.joints.push(BvhJoint {
                name: j.name.clone(),
                parent: j.parent.map(|p| index[p]),
                offset: rest,
                channels,
                end_sites: j.end_sites.clone(),
            });
        }
        // the file's mass properties, when it states any (a file mx wrote)
        if self.joints.iter().any(|j| j.inertia.is_some()) {
            skeleton.inertias = Some(
                self.joints
                    .iter()
                    .zip(&end_site)
                    .filter(|(_, e)| !**e)
                    .map(|(j, _)| j.inertia.unwrap_or_else(Inertia::zero))
                    .collect(),
            );
        }
        let width = skeleton.channel_count();
        let mut values = Vec::with_capacity(width * frames);
        for k in 0..frames {
            for i in 0..n {
                if end_site[i] {
                    continue;
                }
                let channels = &skeleton.joints[index[i]].channels;
                let order: Vec<usize> = channels
                    .iter()
                    .filter(|c| c.is_rotation())
                    .map(|c| c.axis())
                    .collect();
                let angles = match order[..] {
                    [2, 0, 1] if self.joints[i].channels.is_none() => zxy_degrees(&rot[i][k]),
                    // the principal angles, as a BVH exporter writes them (the
                    // clip's reader unwraps whole turns)
                    [a, b, c] => {
                        let [x, y, z] = crate::motion::rotation::euler_of([a, b, c], &rot[i][k]);
                        let pi = std::f64::consts::PI;
                        let flip = self.joints[i]
                            .flipped
                            .iter()
                            .any(|&(f, l)| (f..=l).contains(&k));
                        // the other triple of the same rotation, where the clip had it
                        let e = if flip {
                            [x + pi, pi - y, z + pi]
                        } else {
                            [x, y, z]
                        };
                        e.map(f64::to_degrees)
                    }
                    _ => {
                        return Err(GltfError::invalid(
                            "a joint's rotation channels are not an Euler order",
                        ));
                    }
                };
                let mut r = 0;
                for c in channels {
                    if c.is_rotation() {
                        values.push(angles[r]);
                        r += 1;
                    } else {
                        values.push(pos[i][k][c.axis()]);
                    }
                }
            }
        }
        Ok(BvhFile {
            skeleton,
            frame_time: tracks.frame_time,
            values,
        })
    }
}

/// The cumulative uniform scale of joint `p`'s frame (what its children's lengths are multiplied by).
fn joint_scale(joints: &[SkinJoint], p: usize) -> f64 {
    let j = &joints[p];
    j.parent_scale * j.pre.s * j.scale
}

fn node_name(n: &::gltf::Node) -> String {
    n.name()
        .map(str::to_string)
        .filter(|s| !s.trim().is_empty())
        .unwrap_or_else(|| format!("joint{}", n.index()))
}

/// A DOF-name-safe joint name (`Joint.channel` splits at the dot), unique in `taken`.
fn unique_name(raw: &str, taken: &mut BTreeSet<String>) -> String {
    let base: String = raw
        .chars()
        .map(|c| {
            if c == '.' || c.is_whitespace() {
                '_'
            } else {
                c
            }
        })
        .collect();
    let mut name = base.clone();
    let mut k = 2;
    while taken.contains(&name) {
        name = format!("{base}_{k}");
        k += 1;
    }
    taken.insert(name.clone());
    name
}

fn unit(q: &[f64; 4]) -> UnitQuaternion<f64> {
    let q = Quaternion::new(q[3], q[0], q[1], q[2]);
    if q.norm() > 0.0 {
        UnitQuaternion::new_normalize(q)
    } else {
        UnitQuaternion::identity()
    }
}

/// Intrinsic Z·X·Y Euler angles (degrees) of `r = Rz(a)·Rx(b)·Ry(c)`, in that order.
pub(crate) fn zxy_degrees(r: &Matrix3<f64>) -> [f64; 3] {
    // Third row of Rz Rx Ry is (−cos b sin c, sin b, cos b cos c); its second
    // column (−sin a cos b, cos a cos b, sin b).
    let b = r[(2, 1)].clamp(-1.0, 1.0).asin();
    let (a, c) = if b.cos() > 1e-9 {
        ((-r[(0, 1)]).atan2(r[(1, 1)]), (-r[(2, 0)]).atan2(r[(2, 2)]))
    } else {
        // Gimbal lock: only a ± c is determined; put it all in a.
        (r[(1, 0)].atan2(r[(0, 0)]), 0.0)
    };
    [a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

/// How a sampler interpolates.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Interp {
    Linear,
    Step,
    Cubic,
}

/// One channel's keys (values: 3 or 4 components; cubic: in-tangent, value, out-tangent per key).
#[derive(Clone, Debug)]
struct Track {
    times: Vec<f64>,
    values: Vec<[f64; 4]>,
    interp: Interp,
    rotation: bool,
}

impl Track {
    fn key(&self, k: usize) -> [f64; 4] {
        if self.interp == Interp::Cubic {
            self.values[3 * k + 1]
        } else {
            self.values[k]
        }
    }

    /// Interpolated components at `t` (held before the first and after the last key).
    fn at(&self, t: f64) -> [f64; 4] {
        let n = self.times.len();
        // A grid time within a thousandth of the key spacing of a key takes the
        // key as is: key times are f32 (a frame at 20 s is off by ~1 µs), and
        // interpolating across that would move a fast joint by microns.
        let eps = 1e-3 * (self.times[n - 1] - self.times[0]) / (n.max(2) - 1) as f64;
        let i = self.times.partition_point(|&x| x <= t + eps);
        if i == 0 {
            return self.key(0);
        }
        let i = i - 1;
        if (t - self.times[i]).abs() <= eps || i + 1 == n {
            return self.key(i);
        }
        let (t0, t1) = (self.times[i], self.times[i + 1]);
        let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
        match self.interp {
            Interp::Step => self.key(i),
            Interp::Linear if self.rotation => {
                let (a, b) = (unit(&self.key(i)), unit(&self.key(i + 1)));
                let q = a.try_slerp(&b, u, 1e-12).unwrap_or(a);
                [q.i, q.j, q.k, q.w]
            }
            Interp::Linear => {
                let (a, b) = (self.key(i), self.key(i + 1));
                std::array::from_fn(|c| a[c] + u * (b[c] - a[c]))
            }
            Interp::Cubic => {
                let d = t1 - t0;
                let (p0, m0) = (self.values[3 * i + 1], self.values[3 * i + 2]);
                let (p1, m1) = (self.values[3 * (i + 1) + 1], self.values[3 * (i + 1)]);
                let (u2, u3) = (u * u, u * u * u);
                let (h00, h10, h01, h11) = (
                    2.0 * u3 - 3.0 * u2 + 1.0,
                    u3 - 2.0 * u2 + u,
                    -2.0 * u3 + 3.0 * u2,
                    u3 - u2,
                );
                std::array::from_fn(|c| {
                    h00 * p0[c] + h10 * d * m0[c] + h01 * p1[c] + h11 * d * m1[c]
                })
            }
        }
    }

    fn vec3(&self, t: f64) -> Vector3<f64> {
        let v = self.at(t);
        Vector3::new(v[0], v[1], v[2])
    }

    fn quat(&self, t: f64) -> UnitQuaternion<f64> {
        unit(&self.at(t))
    }
}

/// The animation's tracks per skin joint, and the frame grid.
struct Tracks {
    translation: Vec<Option<Track>>,
    rotation: Vec<Option<Track>>,
    /// The frames' times in the file (the first becomes t = 0).
    times: Vec<f64>,
    frame_time: f64,
    frames: usize,
}

impl Tracks {
    fn new(
        anim: &::gltf::Animation,
        skin: &SkinTree,
        buffers: &[Vec<u8>],
        notes: &mut Vec<String>,
    ) -> Result<Tracks, GltfError> {
        use ::gltf::animation::util::ReadOutputs;
        let n = skin.joints.len();
        let mut translation: Vec<Option<Track>> = vec![None; n];
        let mut rotation: Vec<Option<Track>> = vec![None; n];
        let mut ignored_nodes = BTreeSet::new();
        let mut ignored_paths = BTreeSet::new();
        for ch in anim.channels() {
            let node = ch.target().node();
            let Some(j) = skin.joints.iter().position(|j| j.node == node.index()) else {
                ignored_nodes.insert(node_name(&node));
                continue;
            };
            let reader = ch.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
            let times: Vec<f64> = reader
                .read_inputs()
                .ok_or_else(|| GltfError::invalid("an animation sampler's input cannot be read"))?
                .map(f64::from)
                .collect();
            let interp = match ch.sampler().interpolation() {
                ::gltf::animation::Interpolation::Linear => Interp::Linear,
                ::gltf::animation::Interpolation::Step => Interp::Step,
                ::gltf::animation::Interpolation::CubicSpline => Interp::Cubic,
            };
            let (values, is_rotation): (Vec<[f64; 4]>, bool) = match reader.read_outputs() {
                Some(ReadOutputs::Translations(it)) => (
                    it.map(|v| [v[0] as f64, v[1] as f64, v[2] as f64, 0.0])
                        .collect(),
                    false,
                ),
                Some(ReadOutputs::Rotations(r)) => {
                    (r.into_f32().map(|v| v.map(f64::from)).collect(), true)
                }
                Some(ReadOutputs::Scales(_)) => {
                    ignored_paths.insert("scale");
                    continue;
                }
                Some(ReadOutputs::MorphTargetWeights(_)) => {
                    ignored_paths.insert("morph weights");
                    continue;
                }
                None => {
                    return Err(GltfError::invalid(
                        "an animation sampler's output cannot be read",
                    ));
                }
            };
            let per_key = if interp == Interp::Cubic { 3 } else { 1 };
            if times.is_empty() || values.len() != per_key * times.len() {
                return Err(GltfError::invalid(format!(
                    "a channel of joint `{}` has {} keys and {} values",
                    skin.joints[j].name,
                    times.len(),
                    values.len()
                )));
            }
            if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] <= w[0]) {
                return Err(GltfError::invalid(format!(
                    "a channel of joint `{}` has key times that do not increase",
                    skin.joints[j].name
                )));
            }
            let track = Track {
                times,
                values,
                interp,
                rotation: is_rotation,
            };
            if is_rotation {
                rotation[j] = Some(track);
            } else {
                translation[j] = Some(track);
            }
        }
        if !ignored_nodes.is_empty() {
            notes.push(format!(
                "animation of nodes that are not joints of the skin ignored: {}",
                ignored_nodes.into_iter().collect::<Vec<_>>().join(", ")
            ));
        }
        if !ignored_paths.is_empty() {
            notes.push(format!(
                "{} channels ignored",
                ignored_paths.into_iter().collect::<Vec<_>>().join(" and ")
            ));
        }
        let all: Vec<&Track> = translation.iter().chain(&rotation).flatten().collect();
        if all.is_empty() {
            return Err(GltfError::invalid(
                "the animation moves none of the skin's joints",
            ));
        }
        let start = all.iter().map(|t| t.times[0]).fold(f64::INFINITY, f64::min);
        let stop = all
            .iter()
            .map(|t| t.times[t.times.len() - 1])
            .fold(f64::NEG_INFINITY, f64::max);
        let densest = all.iter().max_by_key(|t| t.times.len()).expect("non-empty");
        let k = densest.times.len();
        let frame_time = if k > 1 && stop > start {
            grid_step(&densest.times)
        } else {
            1.0 / 30.0
        };
        let steps = ((stop - start) / frame_time).round();
        if steps > 10_000_000.0 {
            return Err(GltfError::invalid(format!(
                "{steps} frames is too many to read"
            )));
        }
        let frames = steps as usize + 1;
        // When the densest channel keys every frame over the whole animation (as
        // mx, and Blender with sampling on, write), its own key times are the
        // frames: every key is then read as written, with no interpolation
        // across f32 time rounding (which drifts by ~1e-6 s over a minute).
        let keyed = densest.times.len() == frames
            && densest.times[0] == start
            && densest.times[k - 1] == stop
            && densest
                .times
                .iter()
                .enumerate()
                .all(|(i, t)| (t - (start + i as f64 * frame_time)).abs() < 0.1 * frame_time);
        let times = if keyed {
            densest.times.clone()
        } else {
            (0..frames).map(|i| start + i as f64 * frame_time).collect()
        };
        Ok(Tracks {
            translation,
            rotation,
            times,
            frame_time,
            frames: steps as usize + 1,
        })
    }
}

/// The frame time the keys were written from. Key times are f32, so the
/// mean spacing of a BVH's 0.0333333 s keys is 0.03333330 with the last key's
/// rounding in it, and the last frame would land 2e-7 s early (`sample` at
/// the clip's last frame time would find nothing). The grid is the simplest
/// step whose multiples, rounded to f32, give every key within one f32 step:
/// a whole frame rate (1/30 s), else the shortest decimal (0.0333333 s); the
/// mean spacing when no step does (keys off any grid).
fn grid_step(times: &[f64]) -> f64 {
    let k = times.len();
    let t0 = times[0];
    let dt = (times[k - 1] - t0) / (k - 1) as f64;
    let fits = |step: f64| {
        times.iter().enumerate().all(|(i, &t)| {
            let (want, got) = ((t0 + i as f64 * step) as f32, t as f32);
            (want - got).abs() <= f32::EPSILON * got.abs().max(f32::MIN_POSITIVE)
        })
    };
    let rate = (1.0 / dt).round();
    if rate >= 1.0 && fits(1.0 / rate) {
        return 1.0 / rate;
    }
    (1..=9)
        .map(|digits| significant(dt, digits))
        .find(|&step| step > 0.0 && fits(step))
        .unwrap_or(dt)
}

/// `x` rounded to `digits` significant decimal digits.
fn significant(x: f64, digits: i32) -> f64 {
    let e = digits - 1 - x.abs().log10().floor() as i32;
    if e >= 0 {
        let p = 10f64.powi(e);
        (x * p).round() / p
    } else {
        let p = 10f64.powi(-e);
        (x / p).round() * p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_times_come_back_on_the_grid_they_were_written_on() {
        // keys as a writer stores them: f32 multiples of the frame time
        let keys = |step: f64, n: usize| -> Vec<f64> {
            (0..n)
                .map(|i| f64::from((i as f64 * step) as f32))
                .collect()
        };
        for (step, n) in [
            (0.0333333, 210),
            (1.0 / 30.0, 61),
            (1.0 / 120.0, 5000),
            (0.008333, 900),
            (0.04, 3),
        ] {
            assert_eq!(grid_step(&keys(step, n)), step, "{step} × {n}");
        }
        // keys off any grid keep their mean spacing
        let odd = [0.0, 0.1, 0.25, 0.3];
        assert!((grid_step(&odd) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn zxy_angles_rebuild_the_rotation() {
        let rz = |a: f64| Rotation3::from_axis_angle(&Vector3::z_axis(), a.to_radians());
        let rx = |a: f64| Rotation3::from_axis_angle(&Vector3::x_axis(), a.to_radians());
        let ry = |a: f64| Rotation3::from_axis_angle(&Vector3::y_axis(), a.to_radians());
        for (a, b, c) in [
            (10.0, 20.0, 30.0),
            (-170.0, 80.0, 95.0),
            (0.0, -45.0, 179.0),
            (35.0, 90.0, 0.0),
        ] {
            let r = (rz(a) * rx(b) * ry(c)).into_inner();
            let [a2, b2, c2] = zxy_degrees(&r);
            let back = (rz(a2) * rx(b2) * ry(c2)).into_inner();
            assert!((back - r).norm() < 1e-9, "{a} {b} {c} -> {a2} {b2} {c2}");
        }
    }

    #[test]
    fn cubic_and_linear_tracks_pass_through_their_keys() {
        let lin = Track {
            times: vec![0.0, 1.0],
            values: vec![[0.0, 0.0, 0.0, 0.0], [2.0, 4.0, 6.0, 0.0]],
            interp: Interp::Linear,
            rotation: false,
        };
        assert_eq!(lin.vec3(0.5), Vector3::new(1.0, 2.0, 3.0));
        assert_eq!(lin.vec3(-1.0), Vector3::zeros());
        assert_eq!(lin.vec3(5.0), Vector3::new(2.0, 4.0, 6.0));
        // Hermite with zero tangents: value at the middle is the mean.
        let z = [0.0; 4];
        let cubic = Track {
            times: vec![0.0, 1.0],
            values: vec![z, [1.0, 0.0, 0.0, 0.0], z, z, [3.0, 0.0, 0.0, 0.0], z],
            interp: Interp::Cubic,
            rotation: false,
        };
        assert!((cubic.vec3(0.5).x - 2.0).abs() < 1e-15);
        assert_eq!(cubic.vec3(1.0).x, 3.0);
    }

    #[test]
    fn names_are_made_dof_safe_and_unique() {
        let mut taken = BTreeSet::new();
        assert_eq!(unique_name("Bone.001", &mut taken), "Bone_001");
        assert_eq!(unique_name("Bone 001", &mut taken), "Bone_001_2");
        assert_eq!(unique_name("mixamorig:Hips", &mut taken), "mixamorig:Hips");
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        for bytes in [
            &b""[..],
            b"glTF\x02\0\0\0",
            b"{}",
            b"{\"asset\":{\"version\":\"2.0\"}}",
        ] {
            assert!(from_bytes(bytes, None, Which::First).is_err());
        }
    }
}
