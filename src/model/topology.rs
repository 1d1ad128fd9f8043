//! The joint topology of a link tree as a person sees it: the links that stand
//! for joints, and each one's parent among them. Intermediate links of
//! multi-DOF joints (massless, named after their joint, one child attached with
//! no offset) coincide with the next link and are left out. Drawing, joint
//! positions over time (`mocap::positions`), support detection (`spacetime`)
//! and the in-betweening scores all use this one rule. Which joints are feet
//! goes by name ([`is_foot_name`]): `ground`'s contact points and the up a
//! skeleton stands along (`mocap::up`) share it.

use crate::model::Model;

/// Whether a joint's name says it is a foot: it contains `foot`, `toe`,
/// `ankle`, `heel` or `calcn` (Bandai's `Foot_L`/`Toes_L`, CMU's `LeftFoot`/
/// `LeftToeBase`, OpenSim's `calcn_r`/`toes_r`), case-insensitive; End Sites
/// (`….end`) are not joints and never count.
pub fn is_foot_name(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    !n.ends_with(".end")
        && ["foot", "toe", "ankle", "heel", "calcn"]
            .iter()
            .any(|k| n.contains(k))
}

/// The links reported as joints and their parents among them.
pub fn joint_points(body: &Model) -> (Vec<usize>, Vec<Option<usize>>) {
    let n = body.num_links();
    let skip: Vec<bool> = (0..n)
        .map(|i| {
            let kids = body.children(i);
            let l = body.link(i);
            // Intermediate links are named after their joint (as `body_of` and
            // `human` name them), unlike the link that ends a multi-DOF joint.
            l.name == l.joint_name
                && kids.len() == 1
                && l.inertia.mass == 0.0
                && body.link(kids[0]).offset.p.norm() < 1e-12
        })
        .collect();
    let mut index = vec![None; n];
    let mut links = vec![];
    let mut parents = vec![];
    for i in 0..n {
        if skip[i] {
            continue;
        }
        // Nearest reported ancestor.
        let mut p = body.link(i).parent;
        while let Some(k) = p {
            if index[k].is_some() {
                break;
            }
            p = body.link(k).parent;
        }
        index[i] = Some(links.len());
        links.push(i);
        parents.push(p.and_then(|k| index[k]));
    }
    (links, parents)
}
