//! Reading the XML: located error messages (`<Body> at line 12`) and the small
//! accessors every phase uses (children by tag, numbers, vectors, flags, names).

use nalgebra::Vector3;
use roxmltree::{Document, Node};

use crate::model::tree::ModelError;

pub(super) fn err<T>(msg: impl Into<String>) -> Result<T, ModelError> {
    Err(ModelError::Invalid(msg.into()))
}

pub(super) struct Ctx<'a, 'i> {
    pub(super) doc: &'a Document<'i>,
}

impl<'a, 'i> Ctx<'a, 'i> {
    pub(super) fn line(&self, n: Node) -> u32 {
        self.doc.text_pos_at(n.range().start).row
    }
    pub(super) fn at(&self, n: Node) -> String {
        format!("<{}> at line {}", n.tag_name().name(), self.line(n))
    }
}

pub(super) fn child<'a, 'i>(n: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

pub(super) fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// The `<objects>` of a set (`<BodySet><objects>…`), or nothing.
pub(super) fn objects<'a, 'i>(n: Option<Node<'a, 'i>>) -> Vec<Node<'a, 'i>> {
    n.and_then(|s| child(s, "objects"))
        .map(|o| elements(o).collect())
        .unwrap_or_default()
}

/// 3.x: the joint element inside a body's `<Joint>` (none for ground).
pub(super) fn joint_of_body<'a, 'i>(b: Node<'a, 'i>) -> Option<Node<'a, 'i>> {
    child(b, "Joint").and_then(|j| elements(j).next())
}

pub(super) fn text<'a>(n: Node<'a, '_>, tag: &str) -> Option<&'a str> {
    child(n, tag).map(|c| c.text().unwrap_or("").trim())
}

pub(super) fn nums(cx: &Ctx, n: Node, tag: &str, default: &str) -> Result<Vec<f64>, ModelError> {
    let t = text(n, tag).unwrap_or(default);
    t.split_whitespace()
        .map(|w| {
            w.parse::<f64>().map_err(|_| {
                ModelError::Invalid(format!("<{tag}> of {}: '{w}' is not a number", cx.at(n)))
            })
        })
        .collect()
}

pub(super) fn num(cx: &Ctx, n: Node, tag: &str, default: f64) -> Result<f64, ModelError> {
    match nums(cx, n, tag, "")?.as_slice() {
        [] => Ok(default),
        [x] => Ok(*x),
        many => err(format!(
            "<{tag}> of {} holds {} numbers; expected one",
            cx.at(n),
            many.len()
        )),
    }
}

pub(super) fn vec3(cx: &Ctx, n: Node, tag: &str) -> Result<Vector3<f64>, ModelError> {
    let v = nums(cx, n, tag, "0 0 0")?;
    if v.len() != 3 {
        return err(format!(
            "<{tag}> of {} must hold 3 numbers, not {}",
            cx.at(n),
            v.len()
        ));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

pub(super) fn flag(n: Node, tag: &str) -> bool {
    text(n, tag).is_some_and(|t| t.eq_ignore_ascii_case("true"))
}

pub(super) fn name_of(n: Node) -> String {
    n.attribute("name").unwrap_or("").to_string()
}
