//! Which DOF curves the viewer draws: those asked for (`view(…, curves:
//! [...])`: DOF names, joint names, globs), else the ones that move most.
//! The default leaves out fingers, thumbs and toes and measures angles
//! unwrapped: on a CMU clip the channels that "moved most" were thumbs
//! whose Euler angles wrap between −π and π (a 2π jump that is no motion),
//! and small end joints that capture tracks poorly.

/// A pattern that names no DOF and no joint.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no DOF or joint matches `{pattern}`")]
pub struct Unmatched {
    pub pattern: String,
}

/// The DOFs among `names` that `patterns` ask for, in the patterns' order
/// (a DOF asked twice is drawn once). A pattern is a DOF name
/// (`Hips.Xrotation`), a joint name (`LeftKnee`: all its DOFs, `LeftKnee.*`)
/// or a glob where `*` is any run of characters and `?` one
/// (`*Knee.Xrotation`). `Err` names the first pattern that matches nothing.
pub fn select<'a>(names: &[&'a str], patterns: &[&str]) -> Result<Vec<&'a str>, Unmatched> {
    let mut out: Vec<&'a str> = Vec::new();
    for p in patterns {
        let hits: Vec<&'a str> = names
            .iter()
            .copied()
            .filter(|n| *n == *p || joint_of(n) == *p || glob(p, n))
            .collect();
        if hits.is_empty() {
            return Err(Unmatched {
                pattern: p.to_string(),
            });
        }
        for h in hits {
            if !out.contains(&h) {
                out.push(h);
            }
        }
    }
    Ok(out)
}

/// The joint a DOF belongs to: its name before the last `.`
/// (`LeftKnee.Xrotation` → `LeftKnee`); a DOF named after its joint
/// (URDF: `elbow_joint`) is its own joint.
pub fn joint_of(dof: &str) -> &str {
    crate::motion::channel::Channel::parse(dof).joint
}

/// `*` matches any run of characters, `?` one character; the rest literally.
pub fn glob(pattern: &str, text: &str) -> bool {
    let p: Vec<char> = pattern.chars().collect();
    let t: Vec<char> = text.chars().collect();
    // Iterative matching with one backtrack point (the last `*`): linear in
    // practice, no recursion.
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < t.len() {
        if i < p.len() && (p[i] == '?' || p[i] == t[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|c| *c == '*')
}

/// Whether a DOF belongs to a finger, thumb or toe, by its joint's name
/// (CMU `LeftHandThumb`, `LThumb`, `lfingers`, `LeftToeBase`, `ltoes`;
/// Bandai `Toe_L`; `…Index1`, `…Pinky2`).
pub fn is_extremity(dof: &str) -> bool {
    let j = joint_of(dof).to_ascii_lowercase();
    [
        "thumb", "finger", "toe", "index", "middle", "ring", "pinky", "little",
    ]
    .iter()
    .any(|w| j.contains(w))
}

/// Whether a DOF is an angle whose wraps between −π and π can be unwrapped
/// (BVH rotation channels, `…rotation`, as the channel module reads them).
pub fn is_angle(dof: &str) -> bool {
    crate::motion::channel::rotation_axis(dof).is_some()
}

/// Continues an angle across wraps: a step of more than π between
/// neighbouring samples is taken as the short way round (±2π removed), so
/// the curve shows the motion, not the wrap.
pub fn unwrap(vals: &mut [f64]) {
    use std::f64::consts::{PI, TAU};
    let mut shift = 0.0;
    let mut prev: Option<f64> = None;
    for v in vals.iter_mut() {
        let raw = *v;
        if let Some(p) = prev {
            let step = raw - p;
            if step > PI {
                shift -= TAU * ((step + PI) / TAU).floor();
            } else if step < -PI {
                shift += TAU * ((-step + PI) / TAU).floor();
            }
        }
        prev = Some(raw);
        *v = raw + shift;
    }
}

/// The `n` DOFs of `mu` that move most over `times` (range of the values,
/// angles unwrapped), fingers, thumbs and toes left out unless nothing else
/// moves.
pub fn most_moving<'a>(mu: &'a crate::motion::Mu, times: &[f64], n: usize) -> Vec<&'a str> {
    let mut ranked: Vec<(f64, &str)> = mu
        .dofs
        .iter()
        .map(|(name, d)| {
            let mut vals: Vec<f64> = times
                .iter()
                .filter_map(|&t| d.sample_value(name, t).ok().flatten())
                .filter(|v| v.is_finite())
                .collect();
            if is_angle(name) {
                unwrap(&mut vals);
            }
            let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (if hi >= lo { hi - lo } else { 0.0 }, name.as_str())
        })
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    let body: Vec<&str> = ranked
        .iter()
        .filter(|(_, n)| !is_extremity(n))
        .map(|(_, n)| *n)
        .collect();
    let pool = if body.is_empty() {
        ranked.iter().map(|(_, n)| *n).collect()
    } else {
        body
    };
    pool.into_iter().take(n).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn globs() {
        assert!(glob("*Knee.Xrotation", "LeftKnee.Xrotation"));
        assert!(glob("Hips.?position", "Hips.Yposition"));
        assert!(glob("*", ""));
        assert!(glob("a*b*c", "aXXbYYc"));
        assert!(!glob("a*b*c", "aXXbYY"));
        assert!(!glob("Hips", "Hips.Xrotation"));
    }

    #[test]
    fn select_by_dof_joint_and_glob_in_order() {
        let names = [
            "Hips.Xposition",
            "Hips.Xrotation",
            "LeftKnee.Xrotation",
            "RightKnee.Xrotation",
            "elbow_joint",
        ];
        assert_eq!(
            select(
                &names,
                &["*Knee.Xrotation", "Hips", "elbow_joint", "Hips.Xrotation"]
            )
            .unwrap(),
            [
                "LeftKnee.Xrotation",
                "RightKnee.Xrotation",
                "Hips.Xposition",
                "Hips.Xrotation",
                "elbow_joint"
            ]
        );
        assert_eq!(select(&names, &["Knee"]).unwrap_err().pattern, "Knee");
    }

    #[test]
    fn extremities_and_angles() {
        for n in [
            "LeftHandThumb.Zrotation",
            "LThumb.Xrotation",
            "lfingers.Zrotation",
            "LeftToeBase.Xrotation",
            "Toe_L.Yrotation",
            "RightHandIndex1.Zrotation",
        ] {
            assert!(is_extremity(n), "{n}");
        }
        for n in [
            "LeftKnee.Xrotation",
            "Hips.Xposition",
            "RightHand.Zrotation",
        ] {
            assert!(!is_extremity(n), "{n}");
        }
        assert!(is_angle("Hips.Zrotation") && !is_angle("Hips.Xposition"));
    }

    #[test]
    fn unwrap_removes_wraps_only() {
        let pi = std::f64::consts::PI;
        let mut v = vec![3.0, 3.1, -3.1, -3.0, 3.1, 0.5];
        unwrap(&mut v);
        let want = [3.0, 3.1, 2.0 * pi - 3.1, 2.0 * pi - 3.0, 3.1, 0.5];
        for (a, b) in v.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{v:?}");
        }
        let mut still = vec![0.1, 0.2, -0.3];
        unwrap(&mut still);
        assert_eq!(still, [0.1, 0.2, -0.3]);
    }
}
