//! The BVH writer. Numbers are written in the shared shortest round-trip
//! form ([`crate::fmt_num`]), so read(write(f)) == f exactly and tiny values
//! stay short (`1e-17`, not 17 zeros).

use super::{BvhError, BvhFile, Skeleton};
use crate::fmt_num::Shortest;
use std::fmt::Write as _;
use std::path::Path;

/// Writes `file` to `path` atomically (a reader never sees half a file).
pub fn write_file(file: &BvhFile, path: &Path) -> Result<(), BvhError> {
    let text = to_string(file)?;
    crate::atomic_file::write(path, text.as_bytes()).map_err(|source| BvhError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The text of a BVH file.
pub fn to_string(file: &BvhFile) -> Result<String, BvhError> {
    let nch = file.skeleton.channel_count();
    if nch == 0 && !file.values.is_empty() || nch > 0 && !file.values.len().is_multiple_of(nch) {
        return Err(BvhError::Invalid(format!(
            "{} values do not fill whole frames of {nch} channels",
            file.values.len()
        )));
    }
    if !(file.frame_time.is_finite() && file.frame_time > 0.0) {
        return Err(BvhError::Invalid(format!(
            "frame time {} is not a positive number",
            file.frame_time
        )));
    }
    if let Some(v) = file.values.iter().find(|v| !v.is_finite()) {
        return Err(BvhError::Invalid(format!(
            "cannot write the non-finite value {v}"
        )));
    }
    let mut out = String::with_capacity(file.values.len() * 12 + 4096);
    out.push_str("HIERARCHY\n");
    write_hierarchy(&file.skeleton, &mut out)?;
    let frames = file.frame_count();
    let _ = writeln!(
        out,
        "MOTION\nFrames: {frames}\nFrame Time: {}",
        Shortest(file.frame_time)
    );
    for f in 0..frames {
        let row = file.frame(f);
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                out.push(' ');
            }
            let _ = write!(out, "{}", Shortest(*v));
        }
        out.push('\n');
    }
    Ok(out)
}

fn write_hierarchy(s: &Skeleton, out: &mut String) -> Result<(), BvhError> {
    for (i, j) in s.joints.iter().enumerate() {
        if j.parent.is_some_and(|p| p >= i) {
            return Err(BvhError::Invalid(format!(
                "joint `{}` comes before its parent",
                j.name
            )));
        }
        if j.name.is_empty() || j.name.contains(['{', '}', '\n', '\r']) {
            return Err(BvhError::Invalid(format!(
                "joint name `{}` cannot be written to BVH",
                j.name
            )));
        }
    }
    // Depth-first from each root, children in file order.
    let roots: Vec<usize> = (0..s.joints.len())
        .filter(|&i| s.joints[i].parent.is_none())
        .collect();
    for r in roots {
        write_joint(s, r, 0, out);
    }
    Ok(())
}

fn write_joint(s: &Skeleton, i: usize, depth: usize, out: &mut String) {
    let j = &s.joints[i];
    let ind = "\t".repeat(depth);
    let kw = if j.parent.is_none() { "ROOT" } else { "JOINT" };
    let _ = writeln!(out, "{ind}{kw} {}\n{ind}{{", j.name);
    let _ = writeln!(
        out,
        "{ind}\tOFFSET {} {} {}",
        Shortest(j.offset.x),
        Shortest(j.offset.y),
        Shortest(j.offset.z)
    );
    if !j.channels.is_empty() || j.parent.is_none() {
        let names: Vec<&str> = j.channels.iter().map(|c| c.name()).collect();
        let _ = writeln!(out, "{ind}\tCHANNELS {} {}", names.len(), names.join(" "));
    }
    let children: Vec<usize> = s.children(i).collect();
    for c in children {
        write_joint(s, c, depth + 1, out);
    }
    for e in &j.end_sites {
        let _ = writeln!(
            out,
            "{ind}\tEnd Site\n{ind}\t{{\n{ind}\t\tOFFSET {} {} {}\n{ind}\t}}",
            Shortest(e.x),
            Shortest(e.y),
            Shortest(e.z)
        );
    }
    let _ = writeln!(out, "{ind}}}");
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLIP: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Xposition Yposition Zposition\n\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.04\n1 2 3\n";

    #[test]
    fn write_file_replaces_atomically_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("clip.bvh");
        std::fs::write(&p, "old").unwrap();
        let file = super::super::parse(CLIP).unwrap();
        write_file(&file, &p).unwrap();
        assert_eq!(super::super::read_file(&p).unwrap().values, file.values);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        // A folder where the file should go: the write fails, naming the
        // path, and leaves nothing behind.
        let blocked = dir.path().join("blocked.bvh");
        std::fs::create_dir(&blocked).unwrap();
        let e = write_file(&file, &blocked).unwrap_err();
        assert!(e.to_string().contains("blocked.bvh"), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }
}
