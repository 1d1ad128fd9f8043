//! Where a joint's parent and child frames are: a body, ground, or a chain of
//! PhysicalOffsetFrames composed exactly down to one of them.

use std::collections::HashMap;

use roxmltree::Node;

use super::xml::{Ctx, err, text, vec3};
use crate::lie::Se3;
use crate::model::joints::function_based::body_fixed_xyz;
use crate::model::tree::ModelError;

/// The last component of a socket path (`/bodyset/femur_r` → `femur_r`).
fn last(path: &str) -> &str {
    path.trim_end_matches('/')
        .rsplit('/')
        .next()
        .unwrap_or(path)
}

/// Where a frame is: on `body` (`None` = ground) at `T_body_frame`.
pub(super) type Placed = (Option<String>, Se3);

pub(super) struct Frames<'a, 'i> {
    pub(super) ground: String,
    pub(super) bodies: HashMap<String, ()>,
    /// PhysicalOffsetFrames owned by bodies, ground or the model (not joints), by name.
    pub(super) free: HashMap<String, Vec<Node<'a, 'i>>>,
}

impl<'a, 'i> Frames<'a, 'i> {
    pub(super) fn resolve(
        &self,
        cx: &Ctx,
        path: &str,
        local: &[Node<'a, 'i>],
        depth: usize,
        what: &str,
    ) -> Result<Placed, ModelError> {
        if depth > 32 {
            return err(format!(
                "{what}: the offset frames around '{path}' form a cycle"
            ));
        }
        let name = last(path);
        let frame = local
            .iter()
            .find(|f| f.attribute("name") == Some(name))
            .copied();
        if frame.is_none() && (name == self.ground || path == "/ground") {
            return Ok((None, Se3::identity()));
        }
        if frame.is_none() && self.bodies.contains_key(name) {
            return Ok((Some(name.to_string()), Se3::identity()));
        }
        let frame = match (frame, self.free.get(name).map(Vec::as_slice)) {
            (Some(f), _) => f,
            (None, Some([f])) => *f,
            (None, Some(many)) if !many.is_empty() => {
                return err(format!(
                    "{what}: frame '{path}' is ambiguous: {} offset frames are named '{name}'",
                    many.len()
                ));
            }
            _ => {
                return err(format!(
                    "{what}: frame '{path}' names no body, ground or offset frame of the model"
                ));
            }
        };
        let Some(parent) = text(frame, "socket_parent") else {
            return err(format!(
                "{what}: offset frame '{name}' ({}) has no <socket_parent>",
                cx.at(frame)
            ));
        };
        let o = vec3(cx, frame, "orientation")?;
        let local_t = Se3::new(
            body_fixed_xyz([o.x, o.y, o.z]),
            vec3(cx, frame, "translation")?,
        );
        // A frame's parent is named relative to it: a sibling of the same owner or a full path.
        let (body, t) = self.resolve(cx, parent, local, depth + 1, what)?;
        Ok((body, t.compose(&local_t)))
    }
}
