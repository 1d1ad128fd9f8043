//! Motions of one body as a glTF 2.0 skeleton animation.
//!
//! Every joint of the body (the links `positions` reports) is a node, children
//! under their parent joint; one skin lists them all as joints, with inverse
//! bind matrices of the rest pose (every coordinate 0), so importers build an
//! armature. Each motion is one animation: per joint a LINEAR rotation channel
//! (unit quaternions, kept on one hemisphere frame to frame so slerp takes the
//! short way), and a translation channel for the roots and for any joint whose
//! offset moves (prismatic coordinates). Keys sit on the motion's frames
//! ([`crate::mocap::frame_times`]), written relative to its first frame, since
//! players start an animation at 0 s.
//!
//! The JSON is built with `serde_json` directly: the part of the schema a
//! skeleton animation needs is a dozen object kinds, and writing them as
//! literals keeps the file readable next to the spec.
//!
//! Units: metres and seconds, mx's world frame as is (clips from BVH are
//! y-up, as glTF asks). Each node's `extras.mx` holds its link's mass
//! properties ([`mass_properties`]) and, for a body from a clip, its BVH
//! channels ([`bvh_channels`]): the reader gives both back to `body_of`.
//! An animation's `extras.mx` holds the frames whose Euler angles are not the
//! principal ones ([`flipped_frames`]) and, when asked, the motion's contact
//! forces per frame ([`super::forces`]).

use std::path::Path;

use nalgebra::{Matrix4, Rotation3, UnitQuaternion, Vector3};
use serde_json::{Value, json};

use super::GltfError;
use crate::ground::ForceSeries;
use crate::lie::Se3;
use crate::mocap::{Missing, frame_times, poses_at};
use crate::model::Model;
use crate::motion::Mu;

/// One motion to write and its animation's name.
#[derive(Clone, Copy, Debug)]
pub struct Clip<'a> {
    pub name: &'a str,
    pub motion: &'a Mu,
}

/// How the document's binary buffer is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Container {
    /// One `.glb` file: JSON chunk and BIN chunk.
    Binary,
    /// One `.gltf` JSON file, the buffer embedded as a base64 `data:` URI (no
    /// sidecar `.bin`, so the write stays one atomic file).
    Embedded,
}

impl Container {
    /// The container a file name asks for: `.glb` binary, anything else embedded JSON.
    pub fn for_path(path: &Path) -> Container {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("glb") => Container::Binary,
            _ => Container::Embedded,
        }
    }
}

/// The bytes of a glTF file holding `clips` played on `body`, sampled at
/// `rate` Hz (default: each motion's own frame rate, else 30 Hz).
pub fn to_bytes(
    body: &Model,
    clips: &[Clip],
    rate: Option<f64>,
    container: Container,
) -> Result<Vec<u8>, GltfError> {
    to_bytes_with_forces(body, clips, &[], rate, container)
}

/// [`to_bytes`], where `forces[i]` (when given) are the contact forces of
/// `clips[i]` on the frames its animation is keyed on (`ground_forces` with
/// the same `rate`), written to the animation's `extras.mx.forces`
/// ([`super::forces`]). Forces on other frames are an error.
pub fn to_bytes_with_forces(
    body: &Model,
    clips: &[Clip],
    forces: &[Option<&ForceSeries>],
    rate: Option<f64>,
    container: Container,
) -> Result<Vec<u8>, GltfError> {
    if forces.len() > clips.len() {
        return Err(GltfError::invalid(format!(
            "{} sets of forces for {} motions",
            forces.len(),
            clips.len()
        )));
    }
    if clips.is_empty() {
        return Err(GltfError::invalid("no motion to write"));
    }
    let mut doc = Document::default();
    // Rest pose: every coordinate 0 (the pose the body's offsets describe).
    let mut rest_poses = Vec::new();
    body.forward_kinematics(&vec![0.0; body.coordinate_names().len()], &mut rest_poses)
        .map_err(|e| GltfError::invalid(e.to_string()))?;
    let (links, parents) = crate::mocap::positions::joint_points(body);
    if links.is_empty() {
        return Err(GltfError::invalid(
            "the body has no links to write as joints",
        ));
    }
    let rest: Vec<Se3> = links.iter().map(|&l| rest_poses[l]).collect();
    let rest_local = locals(&rest, &parents);

    let channels: Vec<Option<Vec<&str>>> = links
        .iter()
        .map(|&l| bvh_channels(body, l, &links))
        .collect();
    // Nodes: one per joint, in link order (parents first).
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
    for (j, p) in parents.iter().enumerate() {
        if let Some(p) = p {
            children[*p].push(j);
        }
    }
    for (j, &l) in links.iter().enumerate() {
        let (t, q) = trs(&rest_local[j]);
        let mut node = json!({
            "name": body.link(l).name,
            "translation": t,
            "rotation": q,
        });
        if !children[j].is_empty() {
            node["children"] = json!(children[j]);
        }
        let mut mx = serde_json::Map::new();
        let inertia = &body.link(l).inertia;
        if !inertia.is_zero() {
            mx.extend(mass_properties(inertia));
        }
        if let Some(c) = &channels[j] {
            mx.insert("channels".into(), json!(c));
        }
        if !mx.is_empty() {
            node["extras"] = json!({ "mx": mx });
        }
        doc.nodes.push(node);
    }
    let roots: Vec<usize> = (0..links.len()).filter(|&j| parents[j].is_none()).collect();

    // Skin: inverse bind matrices of the rest pose, column-major.
    let ibm: Vec<f32> = rest
        .iter()
        .flat_map(|w| column_major(&w.inverse()))
        .collect();
    let ibm = doc.accessor(&ibm, "MAT4", links.len(), None);
    let mut skin =
        json!({ "joints": (0..links.len()).collect::<Vec<_>>(), "inverseBindMatrices": ibm });
    if let [root] = roots.as_slice() {
        skin["skeleton"] = json!(root);
    }
    doc.skins.push(skin);

    // where each contact point's force acts: the node of its link
    let node_of = |name: &str| links.iter().position(|&l| body.link(l).name == name);
    let up = crate::ground::up_of(&body.default_gravity);
    for (i, clip) in clips.iter().enumerate() {
        let times = frame_times(clip.motion, rate)?;
        let poses = poses_at(clip.motion, body, times, Missing::Error)?;
        if poses.links != links {
            return Err(GltfError::invalid(
                "the body's joints changed while writing",
            ));
        }
        let flipped = flipped_frames(clip.motion, body, &links, &channels, &poses.times)?;
        doc.animation(clip.name, &poses.times, &poses.poses, &parents, &rest_local);
        let mut mx = serde_json::Map::new();
        if !flipped.is_empty() {
            mx.insert("flipped".into(), json!(flipped));
        }
        if let Some(f) = forces.get(i).copied().flatten() {
            on_frames(f, &poses.times, clip.name)?;
            let nodes: Vec<Option<usize>> = f.points.iter().map(|p| node_of(p)).collect();
            let extras = super::forces::to_extras(f, poses.times[0], up, &nodes);
            mx.insert("forces".into(), extras);
        }
        if !mx.is_empty()
            && let Some(a) = doc.animations.last_mut()
        {
            a["extras"] = json!({ "mx": mx });
        }
    }
    doc.finish(&roots, container)
}

/// Writes `clips` on `body` to `path` atomically (`.glb` binary, `.gltf` embedded).
pub fn save(body: &Model, clips: &[Clip], rate: Option<f64>, path: &Path) -> Result<(), GltfError> {
    save_with_forces(body, clips, &[], rate, path)
}

/// [`save`] with contact forces per clip, as [`to_bytes_with_forces`] writes them.
pub fn save_with_forces(
    body: &Model,
    clips: &[Clip],
    forces: &[Option<&ForceSeries>],
    rate: Option<f64>,
    path: &Path,
) -> Result<(), GltfError> {
    let bytes = to_bytes_with_forces(body, clips, forces, rate, Container::for_path(path))?;
    crate::io::atomic::write_atomic(path, &bytes)?;
    Ok(())
}

/// `Err` unless `f` has one frame per time of the animation, at that time.
fn on_frames(f: &ForceSeries, times: &[f64], name: &str) -> Result<(), GltfError> {
    let fits = f.times.len() == times.len()
        && f.forces.iter().all(|fr| fr.len() == f.points.len())
        && [
            f.forces.len(),
            f.residual_force.len(),
            f.residual_moment.len(),
            f.percent_bw.len(),
        ]
        .iter()
        .all(|&n| n == times.len())
        && f.times
            .iter()
            .zip(times)
            .all(|(a, b)| (a - b).abs() <= 1e-9 * b.abs().max(1.0));
    if fits {
        return Ok(());
    }
    let span = |t: &[f64]| match t {
        [] => "no frames".to_string(),
        [a, .., b] => format!("{} frames from {a} s to {b} s", t.len()),
        [a] => format!("1 frame at {a} s"),
    };
    Err(GltfError::invalid(format!(
        "the forces of `{name}` are on {}, its animation on {}: compute them on the motion saved at the rate saved (`forces: true` does)",
        span(&f.times),
        span(times)
    )))
}

/// A link's mass properties as glTF `extras` (`{"mx": {…}}` on its node), so
/// `body_of(load("x.glb"))` is the body that was saved: mass (kg), centre of
/// mass (m) and the inertia about it (kg·m², `[xx, yy, zz, xy, xz, yz]`), in
/// the node's frame, as f64 (JSON numbers read back exactly). Every link
/// that carries mass is a node: `joint_points` leaves out massless ones only.
fn mass_properties(i: &crate::model::Inertia) -> serde_json::Map<String, Value> {
    let c = i.com();
    let m = i.inertia_com();
    let mut out = serde_json::Map::new();
    out.insert("mass".into(), json!(i.mass));
    out.insert("com".into(), json!([c.x, c.y, c.z]));
    out.insert(
        "inertia".into(),
        json!([
            m[(0, 0)],
            m[(1, 1)],
            m[(2, 2)],
            m[(0, 1)],
            m[(0, 2)],
            m[(1, 2)]
        ]),
    );
    out
}

/// The BVH channels of joint link `l` in the body's order, when its
/// coordinates are such channels (`Hips.Zrotation`…, a body from `body_of`):
/// the reader then gives back the same DOFs, Euler order included, so the
/// loaded motion drives the saved body in its own coordinates (∫Στ² depends
/// on them). `None` for other bodies.
fn bvh_channels(body: &Model, l: usize, joints: &[usize]) -> Option<Vec<&'static str>> {
    // the links of this joint: up from `l` to the previous joint point
    let mut chain = vec![l];
    let mut p = body.link(l).parent;
    while let Some(k) = p.filter(|k| !joints.contains(k)) {
        chain.push(k);
        p = body.link(k).parent;
    }
    let name = &body.link(l).name;
    let mut out = vec![];
    for &k in chain.iter().rev() {
        for c in body.joint_coordinates(k) {
            let (joint, channel) = body.coordinate_names()[c].rsplit_once('.')?;
            if joint != name {
                return None;
            }
            out.push(crate::mocap::bvh::Channel::parse(channel)?.name());
        }
    }
    (!out.is_empty()).then_some(out)
}

/// Where a joint's Euler angles (stated channels, three rotations) are not
/// the principal ones (middle angle beyond ±90°): the same rotation has two
/// Euler triples, and a clip that turns past 90° keeps its angles continuous
/// while an exporter that writes principal angles flips. The reader takes the
/// principal triple except on these frames, so it gives back the clip's own
/// coordinates. `{node: [[first, last], …]}` (frame indices), joints without
/// such frames left out.
fn flipped_frames(
    motion: &Mu,
    body: &Model,
    links: &[usize],
    channels: &[Option<Vec<&str>>],
    times: &[f64],
) -> Result<serde_json::Map<String, Value>, GltfError> {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let mut out = serde_json::Map::new();
    for (j, c) in channels.iter().enumerate() {
        let Some(c) = c else { continue };
        let name = &body.link(links[j]).name;
        let rotations: Vec<String> = c
            .iter()
            .filter(|c| c.ends_with("rotation"))
            .map(|c| format!("{name}.{c}"))
            .collect();
        let [_, middle, _] = &rotations[..] else {
            continue;
        };
        let mut ranges: Vec<[usize; 2]> = vec![];
        for (k, &t) in times.iter().enumerate() {
            let Some(b) = motion.sample_value(middle, t)? else {
                continue;
            };
            // wrapped into (−π, π]: principal when within ±π/2
            let b = b - TAU * ((b + PI) / TAU).ceil() + TAU;
            if b.abs() <= FRAC_PI_2 {
                continue;
            }
            match ranges.last_mut() {
                Some(r) if r[1] + 1 == k => r[1] = k,
                _ => ranges.push([k, k]),
            }
        }
        if !ranges.is_empty() {
            out.insert(j.to_string(), json!(ranges));
        }
    }
    Ok(out)
}

/// Each joint's frame in its parent joint's frame (world for a root).
fn locals(world: &[Se3], parents: &[Option<usize>]) -> Vec<Se3> {
    world
        .iter()
        .zip(parents)
        .map(|(w, p)| match p {
            Some(p) => world[*p].inv_compose(w),
            None => *w,
        })
        .collect()
}

fn quaternion(r: &nalgebra::Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r))
}

/// glTF's translation and rotation ([x, y, z, w]) of a transform.
fn trs(x: &Se3) -> ([f64; 3], [f64; 4]) {
    let q = quaternion(&x.r);
    ([x.p.x, x.p.y, x.p.z], [q.i, q.j, q.k, q.w])
}

fn column_major(x: &Se3) -> [f32; 16] {
    let mut m = Matrix4::<f64>::identity();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&x.r);
    m.fixed_view_mut::<3, 1>(0, 3).copy_from(&x.p);
    // nalgebra stores column-major, as glTF does.
    let mut out = [0f32; 16];
    for (o, v) in out.iter_mut().zip(m.as_slice()) {
        *o = *v as f32;
    }
    out
}

/// The document under construction: JSON arrays and the one binary buffer.
#[derive(Default)]
struct Document {
    nodes: Vec<Value>,
    skins: Vec<Value>,
    animations: Vec<Value>,
    accessors: Vec<Value>,
    views: Vec<Value>,
    bin: Vec<u8>,
}

impl Document {
    /// Appends `data` (f32, `count` elements of `kind`) as its own buffer view
    /// and accessor; `min_max` for the accessors that must state them.
    fn accessor(
        &mut self,
        data: &[f32],
        kind: &str,
        count: usize,
        min_max: Option<(f32, f32)>,
    ) -> usize {
        // Every view starts on a 4-byte boundary (all data is f32, so it stays aligned).
        let offset = self.bin.len();
        for v in data {
            self.bin.extend_from_slice(&v.to_le_bytes());
        }
        self.views
            .push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": data.len() * 4 }));
        let mut a = json!({
            "bufferView": self.views.len() - 1,
            "componentType": 5126,
            "count": count,
            "type": kind,
        });
        if let Some((lo, hi)) = min_max {
            a["min"] = json!([lo]);
            a["max"] = json!([hi]);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// One animation: a rotation channel per joint, translation channels where
    /// the joint's offset moves (always at a root).
    fn animation(
        &mut self,
        name: &str,
        times: &[f64],
        poses: &[Vec<Se3>],
        parents: &[Option<usize>],
        rest: &[Se3],
    ) {
        let t0 = times[0];
        let keys: Vec<f32> = times.iter().map(|t| (t - t0) as f32).collect();
        let (lo, hi) = (keys[0], keys[keys.len() - 1]);
        let input = self.accessor(&keys, "SCALAR", keys.len(), Some((lo, hi)));
        let local: Vec<Vec<Se3>> = poses.iter().map(|fr| locals(fr, parents)).collect();
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        for j in 0..parents.len() {
            // A joint that never turns keeps its rest rotation: no channel (readers
            // then know a fixed leaf, like a BVH End Site, for what it is).
            let turns = local.iter().any(|fr| (fr[j].r - rest[j].r).norm() > 1e-12);
            if parents[j].is_some() && !turns {
                self.translation_channel(
                    j,
                    input,
                    &local,
                    parents,
                    rest,
                    &mut samplers,
                    &mut channels,
                );
                continue;
            }
            let mut prev: Option<UnitQuaternion<f64>> = None;
            let mut rot = Vec::with_capacity(4 * times.len());
            for fr in &local {
                let mut q = quaternion(&fr[j].r);
                // q and −q are one rotation; keep neighbours on one hemisphere.
                if prev.is_some_and(|p| p.coords.dot(&q.coords) < 0.0) {
                    q = UnitQuaternion::new_unchecked(-q.into_inner());
                }
                rot.extend([q.i, q.j, q.k, q.w].map(|c| c as f32));
                prev = Some(q);
            }
            let out = self.accessor(&rot, "VEC4", times.len(), None);
            samplers.push(json!({ "input": input, "output": out, "interpolation": "LINEAR" }));
            channels.push(json!({ "sampler": samplers.len() - 1, "target": { "node": j, "path": "rotation" } }));
            self.translation_channel(
                j,
                input,
                &local,
                parents,
                rest,
                &mut samplers,
                &mut channels,
            );
        }
        self.animations
            .push(json!({ "name": name, "samplers": samplers, "channels": channels }));
    }

    /// Joint `j`'s translation channel, at a root or where its offset moves.
    #[allow(clippy::too_many_arguments)]
    fn translation_channel(
        &mut self,
        j: usize,
        input: usize,
        local: &[Vec<Se3>],
        parents: &[Option<usize>],
        rest: &[Se3],
        samplers: &mut Vec<Value>,
        channels: &mut Vec<Value>,
    ) {
        let moves = local.iter().any(|fr| (fr[j].p - rest[j].p).norm() > 1e-9);
        if parents[j].is_none() || moves {
            let tr: Vec<f32> = local.iter().flat_map(|fr| vec3(&fr[j].p)).collect();
            let out = self.accessor(&tr, "VEC3", local.len(), None);
            samplers.push(json!({ "input": input, "output": out, "interpolation": "LINEAR" }));
            channels.push(json!({ "sampler": samplers.len() - 1, "target": { "node": j, "path": "translation" } }));
        }
    }

    fn finish(self, roots: &[usize], container: Container) -> Result<Vec<u8>, GltfError> {
        let mut buffer = json!({ "byteLength": self.bin.len() });
        if container == Container::Embedded {
            use base64::Engine;
            let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
            buffer["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
        }
        let doc = json!({
            "asset": { "version": "2.0", "generator": concat!("mx ", env!("CARGO_PKG_VERSION")) },
            "scene": 0,
            "scenes": [{ "name": "mx", "nodes": roots }],
            "nodes": self.nodes,
            "skins": self.skins,
            "animations": self.animations,
            "accessors": self.accessors,
            "bufferViews": self.views,
            "buffers": [buffer],
        });
        let text = serde_json::to_vec(&doc).map_err(|e| GltfError::invalid(e.to_string()))?;
        Ok(match container {
            Container::Embedded => text,
            Container::Binary => glb(text, self.bin),
        })
    }
}

fn vec3(p: &Vector3<f64>) -> [f32; 3] {
    [p.x as f32, p.y as f32, p.z as f32]
}

/// The GLB container: 12-byte header, a JSON chunk padded with spaces and a BIN
/// chunk padded with zeros, each to a multiple of 4 bytes.
fn glb(mut json: Vec<u8>, mut bin: Vec<u8>) -> Vec<u8> {
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}
