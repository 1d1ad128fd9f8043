//! Named links joined by named joints, ordered into a tree parents first:
//! the one check that a set of links is a tree (unique names, joints between
//! links that exist, one parent per link, no cycle) and the depth-first order
//! a [`Model`](crate::model::Model) is built in. URDF files and the
//! language's `body([...])` both build through it.

/// One joint: it carries `child` from `parent` (`None`: the world).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeJoint<'a> {
    pub name: &'a str,
    pub parent: Option<&'a str>,
    pub child: &'a str,
}

/// Why links and joints do not form a tree.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TreeError {
    #[error("link `{0}` is defined twice; link names must be unique")]
    DuplicateLink(String),
    #[error("joint `{0}` is defined twice; joint names must be unique")]
    DuplicateJoint(String),
    /// A joint names a link no one defined as its `end` (`"parent"` or
    /// `"child"`; `nearest`: the closest name).
    #[error(
        "joint `{joint}` names {end} link `{link}`, which is not defined{}",
        nearest.as_ref().map(|n| format!(" (did you mean `{n}`?)")).unwrap_or_default()
    )]
    UnknownLink {
        joint: String,
        end: &'static str,
        link: String,
        nearest: Option<String>,
    },
    #[error("link `{link}` is the child of both `{first}` and `{second}`; a body must be a tree")]
    TwoParents {
        link: String,
        first: String,
        second: String,
    },
    /// Links no path from the world reaches: each is its own ancestor.
    #[error(
        "links {} form a cycle (each is an ancestor of itself) and never reach the world; a body must be a tree",
        links.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
    )]
    Cycle {
        links: Vec<String>,
        /// The joints carrying them, in the order given.
        joints: Vec<String>,
    },
}

/// The joints in the order a model is built: depth first from the world,
/// every joint after its parent link's, siblings in the order given (sort
/// `joints` by name first for Pinocchio's order). A link no joint carries is
/// a root, welded to the world; the caller decides how many roots it allows
/// ([`roots`]).
pub fn tree_order(links: &[&str], joints: &[TreeJoint]) -> Result<Vec<usize>, TreeError> {
    let mut known = std::collections::HashSet::with_capacity(links.len());
    for l in links {
        if !known.insert(*l) {
            return Err(TreeError::DuplicateLink(l.to_string()));
        }
    }
    let mut names = std::collections::HashSet::with_capacity(joints.len());
    for j in joints {
        if !names.insert(j.name) {
            return Err(TreeError::DuplicateJoint(j.name.to_string()));
        }
    }
    let mut carried_by = std::collections::HashMap::with_capacity(joints.len());
    let mut children: std::collections::HashMap<Option<&str>, Vec<usize>> =
        std::collections::HashMap::new();
    for (i, j) in joints.iter().enumerate() {
        let ends = j
            .parent
            .map(|p| ("parent", p))
            .into_iter()
            .chain([("child", j.child)]);
        for (end, link) in ends {
            if !known.contains(link) {
                return Err(TreeError::UnknownLink {
                    joint: j.name.to_string(),
                    end,
                    link: link.to_string(),
                    nearest: links
                        .iter()
                        .filter(|k| **k != j.child)
                        .min_by_key(|k| strsim::levenshtein(k, link))
                        .map(|k| k.to_string()),
                });
            }
        }
        if let Some(first) = carried_by.insert(j.child, j.name) {
            return Err(TreeError::TwoParents {
                link: j.child.to_string(),
                first: first.to_string(),
                second: j.name.to_string(),
            });
        }
        children.entry(j.parent).or_default().push(i);
    }
    // The world's children: joints from it, then those of links no joint carries.
    let mut from_world: Vec<usize> = children.get(&None).cloned().unwrap_or_default();
    for l in roots(links, joints) {
        from_world.extend(children.get(&Some(l)).into_iter().flatten());
    }
    let mut order = Vec::with_capacity(joints.len());
    let mut stack: Vec<usize> = from_world.into_iter().rev().collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        if let Some(kids) = children.get(&Some(joints[i].child)) {
            stack.extend(kids.iter().rev());
        }
    }
    if order.len() < joints.len() {
        let mut reached = vec![false; joints.len()];
        for &i in &order {
            reached[i] = true;
        }
        let stray = || joints.iter().zip(&reached).filter(|(_, r)| !**r);
        return Err(TreeError::Cycle {
            links: stray().map(|(j, _)| j.child.to_string()).collect(),
            joints: stray().map(|(j, _)| j.name.to_string()).collect(),
        });
    }
    Ok(order)
}

/// The links no joint carries, in the order given: welded to the world.
pub fn roots<'a>(links: &[&'a str], joints: &[TreeJoint]) -> Vec<&'a str> {
    let carried: std::collections::HashSet<&str> = joints.iter().map(|j| j.child).collect();
    links
        .iter()
        .copied()
        .filter(|l| !carried.contains(l))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn j<'a>(name: &'a str, parent: Option<&'a str>, child: &'a str) -> TreeJoint<'a> {
        TreeJoint {
            name,
            parent,
            child,
        }
    }

    #[test]
    fn parents_come_first_and_siblings_keep_their_order() {
        // given child before parent; two branches from the world
        let links = ["hand", "arm", "leg"];
        let joints = [
            j("wrist", Some("arm"), "hand"),
            j("shoulder", None, "arm"),
            j("hip", None, "leg"),
        ];
        assert_eq!(tree_order(&links, &joints), Ok(vec![1, 0, 2]));
        // a root link (URDF's base) carries its children first
        let links = ["base", "b", "c"];
        let joints = [j("j2", Some("base"), "c"), j("j1", Some("base"), "b")];
        assert_eq!(roots(&links, &joints), vec!["base"]);
        assert_eq!(tree_order(&links, &joints), Ok(vec![0, 1]));
    }

    #[test]
    fn what_is_not_a_tree_is_named() {
        let e = tree_order(&["a", "a"], &[]).unwrap_err();
        assert_eq!(e, TreeError::DuplicateLink("a".into()));
        let e = tree_order(&["a", "b"], &[j("j", None, "a"), j("j", None, "b")]).unwrap_err();
        assert_eq!(e, TreeError::DuplicateJoint("j".into()));
        let e = tree_order(&["arm", "hand"], &[j("wrist", Some("amr"), "hand")]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "joint `wrist` names parent link `amr`, which is not defined (did you mean `arm`?)"
        );
        let e = tree_order(&["a", "b"], &[j("j1", None, "b"), j("j2", Some("a"), "b")]);
        assert!(matches!(e, Err(TreeError::TwoParents { .. })), "{e:?}");
        // a cycle beside a tree: only the cycle is named
        let links = ["a", "b", "c", "d"];
        let joints = [
            j("j1", Some("a"), "b"),
            j("j2", Some("c"), "d"),
            j("j3", Some("d"), "c"),
        ];
        let Err(TreeError::Cycle { links, joints }) = tree_order(&links, &joints) else {
            panic!("no cycle found");
        };
        assert_eq!(
            (links, joints),
            (vec!["d".into(), "c".into()], vec!["j2".into(), "j3".into()])
        );
    }
}
