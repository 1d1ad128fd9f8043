//! The help text: `:help` (every name by topic), `:help TOPIC` (one group
//! with its docs), `:help NAME`, and the same entries as the Markdown page
//! `docs/reference.md` (`mx help --markdown`). Everything comes from the doc
//! strings: the built-ins' (`Registry::add`) and the comments above each
//! function of the prelude (`stdlib/prelude.mx`), whose `// ---- TOPIC ----`
//! section lines say which topic they belong to.

use std::fmt::Write;

use super::registry::Registry;
use super::topic::Topic;

/// One documented name.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub name: String,
    /// `clamp(x, lo, hi)`, or `pi = 3.14…` for a constant.
    pub signature: String,
    pub doc: String,
    pub topic: Topic,
    /// Written in mx, in the prelude.
    pub in_prelude: bool,
}

/// The built-ins' entries: constants first, then functions, in registration order.
pub fn builtin_entries(reg: &Registry) -> Vec<Entry> {
    let constants = reg.constants().map(|(name, v, doc)| Entry {
        name: name.to_string(),
        signature: format!("{name} = {}", v.repr()),
        doc: doc.to_string(),
        topic: Topic::Language,
        in_prelude: false,
    });
    let functions = reg.functions().map(|b| Entry {
        name: b.name.clone(),
        signature: b.signature.to_string(),
        doc: b.doc.clone(),
        topic: b.topic,
        in_prelude: false,
    });
    constants.chain(functions).collect()
}

/// The documented functions of a prelude text: each `fn name(params) = …`
/// at the start of a line, with the `//` comment lines just above it as its
/// doc, under the topic of the last `// ---- TOPIC ----` line before it
/// (language before any).
pub fn prelude_entries(src: &str) -> Vec<Entry> {
    let mut out = Vec::new();
    let mut topic = Topic::Language;
    let mut comment: Vec<&str> = Vec::new();
    for line in src.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("// ----") {
            let word = rest.trim_matches(|c: char| c == '-' || c.is_whitespace());
            let key = word.split([':', ' ']).next().unwrap_or("");
            if let Some(k) = Topic::parse(key) {
                topic = k;
            }
            comment.clear();
        } else if let Some(c) = t.strip_prefix("//") {
            comment.push(c.trim());
        } else if let Some(def) = line.strip_prefix("fn ") {
            if let Some(close) = def.find(')') {
                let signature = def[..=close].trim().to_string();
                let name = signature.split('(').next().unwrap_or("").trim().to_string();
                out.push(Entry {
                    name,
                    signature,
                    doc: comment.join(" "),
                    topic,
                    in_prelude: true,
                });
            }
            comment.clear();
        } else if t.is_empty() || !line.starts_with(' ') {
            comment.clear();
        }
    }
    out
}

/// `:help` with no argument: the commands, then every name by topic.
pub fn overview(entries: &[Entry]) -> String {
    let mut s = String::new();
    s.push_str("Commands: :help [TOPIC or NAME], :type EXPR, :info EXPR, :load FILE, :time EXPR, :plot EXPR, :quit\n");
    s.push_str("Built-ins by topic (:help TOPIC for one topic with its docs, :help NAME for one name, :help formats for files):\n");
    for topic in Topic::ALL {
        let mut sigs: Vec<&str> = in_topic(entries, topic)
            .map(|e| e.signature.as_str())
            .collect();
        if sigs.is_empty() {
            continue;
        }
        sigs.sort_unstable();
        let _ = writeln!(s, "\n{} (:help {})", topic.title(), topic.key());
        for sig in sigs {
            let _ = writeln!(s, "  {sig}");
        }
    }
    s
}

/// `:help TOPIC`: every name of one topic with its doc, alphabetically.
pub fn topic_text(entries: &[Entry], topic: Topic) -> String {
    let mut s = format!("{}\n", topic.title());
    for e in sorted(in_topic(entries, topic)) {
        let _ = writeln!(s, "\n  {}", e.signature);
        if !e.doc.is_empty() {
            let _ = writeln!(s, "    {}", e.doc);
        }
    }
    s
}

/// `:help NAME`: the signature, then the doc.
pub fn entry_text(e: &Entry) -> String {
    format!("{}\n  {}", e.signature, e.doc)
}

/// The file formats `load`/`save` know, one line each.
pub fn formats_text(reg: &Registry) -> String {
    let mut s = String::new();
    for f in reg.formats() {
        let rw = match (f.load.is_some(), f.save.is_some()) {
            (true, true) => "load/save",
            (true, false) => "load",
            _ => "save",
        };
        let _ = writeln!(s, "  .{} ({rw}): {}", f.ext, f.doc);
    }
    s
}

/// The reference page `docs/reference.md`: every topic with every name's
/// signature and doc, and the file formats.
pub fn markdown(entries: &[Entry], reg: &Registry) -> String {
    let mut s = String::new();
    s.push_str("# mx reference\n\n");
    s.push_str("Every built-in function and constant, and every function of the prelude (`stdlib/prelude.mx`), by topic. ");
    s.push_str("Generated from their doc strings by `mx help --markdown > docs/reference.md`: edit the doc strings, not this page ");
    s.push_str("(`tests/it/reference.rs` fails when the two differ). The REPL shows the same text: `:help`, `:help TOPIC`, `:help NAME`.\n\n");
    for topic in Topic::ALL {
        if in_topic(entries, topic).next().is_some() {
            let _ = writeln!(s, "- [{}](#{})", topic.title(), anchor(topic.title()));
        }
    }
    s.push_str("- [File formats](#file-formats)\n");
    for topic in Topic::ALL {
        let group = sorted(in_topic(entries, topic));
        if group.is_empty() {
            continue;
        }
        let _ = writeln!(s, "\n## {}\n", topic.title());
        for e in group {
            let from = if e.in_prelude { " *(prelude)*" } else { "" };
            let _ = writeln!(s, "- `{}`{from}: {}", e.signature, e.doc.trim());
        }
    }
    s.push_str("\n## File formats\n\n`load(path)` and `save(x, path, …)` choose the format by the file's extension.\n\n");
    for f in reg.formats() {
        let rw = match (f.load.is_some(), f.save.is_some()) {
            (true, true) => "load, save",
            (true, false) => "load",
            _ => "save",
        };
        let _ = writeln!(s, "- `.{}` ({rw}): {}", f.ext, f.doc.trim());
    }
    s
}

fn in_topic(entries: &[Entry], topic: Topic) -> impl Iterator<Item = &Entry> {
    entries.iter().filter(move |e| e.topic == topic)
}

fn sorted<'a>(it: impl Iterator<Item = &'a Entry>) -> Vec<&'a Entry> {
    let mut v: Vec<&Entry> = it.collect();
    v.sort_by(|a, b| a.name.cmp(&b.name).then(a.signature.cmp(&b.signature)));
    v
}

/// GitHub's heading anchor: lower case, spaces to `-`, punctuation dropped.
fn anchor(title: &str) -> String {
    title
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prelude_docs_are_the_comments_above_each_function_under_their_topic() {
        let src = "// file header\n\n// ---- language: numbers ----\n\n// Twice x.\n// (exactly)\nfn double(x) = 2 * x\nfn bare(y) = y\n\n// ---- motion ----\n// m later.\nfn shift(m, dt) = affine(dt, 1, m)\n";
        let e = prelude_entries(src);
        assert_eq!(e.len(), 3);
        assert_eq!(
            (e[0].name.as_str(), e[0].signature.as_str()),
            ("double", "double(x)")
        );
        assert_eq!(e[0].doc, "Twice x. (exactly)");
        assert_eq!(e[0].topic, Topic::Language);
        assert_eq!(e[1].doc, "");
        assert_eq!((e[2].name.as_str(), e[2].topic), ("shift", Topic::Motion));
        assert!(e.iter().all(|x| x.in_prelude));
    }

    #[test]
    fn a_topic_lists_only_its_own_names() {
        let mut reg = Registry::new();
        reg.topic(Topic::Motion)
            .add("walkish(m)", "A motion thing.", |_, _| {
                Ok(super::super::value::Value::Nil)
            });
        reg.topic(Topic::Language)
            .add("twice(x)", "A number thing.", |_, _| {
                Ok(super::super::value::Value::Nil)
            });
        let entries = builtin_entries(&reg);
        let motion = topic_text(&entries, Topic::Motion);
        assert!(motion.contains("walkish(m)") && motion.contains("A motion thing."));
        assert!(!motion.contains("twice"));
        let all = overview(&entries);
        assert!(all.find("Language").unwrap() < all.find("twice(x)").unwrap());
        assert!(all.find("Motion (:help motion)").unwrap() < all.find("walkish(m)").unwrap());
        assert_eq!(anchor("Bodies and dynamics"), "bodies-and-dynamics");
    }
}
