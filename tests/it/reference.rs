//! `docs/reference.md` is generated from the doc strings (`mx help
//! --markdown`): this fails when a doc string, a signature or a topic changed
//! without the page being regenerated.

use std::path::PathBuf;

#[test]
fn the_committed_reference_page_matches_the_doc_strings() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/reference.md");
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    let generated = mx::Interpreter::new().help_markdown();
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .map(|i| i + 1)
            .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()) + 1);
        panic!(
            "{} is out of date (first difference at line {line}); regenerate it with\n  \
             cargo run -- help --markdown > docs/reference.md",
            path.display()
        );
    }
}

#[test]
fn every_topic_has_names_and_help_topic_lists_only_its_own() {
    let mx = mx::Interpreter::new();
    let entries = mx.help_entries();
    for topic in mx::lang::Topic::ALL {
        let names: Vec<&str> = entries
            .iter()
            .filter(|e| e.topic == topic)
            .map(|e| e.name.as_str())
            .collect();
        assert!(!names.is_empty(), "{topic:?} has no names");
        let text = mx.help(topic.key()).unwrap();
        assert!(text.starts_with(topic.title()), "{text}");
        for e in entries.iter().filter(|e| e.topic != topic) {
            assert!(
                !text.contains(&format!("\n  {}\n", e.signature)),
                "{} listed under {topic:?}",
                e.name
            );
        }
    }
    // Prelude functions keep their doc strings in :help.
    let clamp = mx.help("clamp").unwrap();
    assert!(
        clamp.starts_with("clamp(x, lo, hi)\n  x limited to [lo, hi]."),
        "{clamp}"
    );
    assert!(mx.help("no_such_name").is_err());
}
