//! The clip library value (`library(…)`, `load("x.mxlib")`): what `match`
//! searches and SP's `example:` follows.

use std::sync::Arc;

use super::sp_report::{num, record};
use crate::lang::value::{HostObject, Value};
use crate::library::Library;

/// A built clip library, shared (it can hold thousands of clips).
#[derive(Clone)]
pub struct LibraryValue(pub Arc<Library>);

impl std::fmt::Debug for LibraryValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.summary())
    }
}

impl HostObject for LibraryValue {
    fn type_name(&self) -> &'static str {
        "Library"
    }
    fn summary(&self) -> String {
        let l = &self.0;
        format!(
            "Library: {} clips, {} frames at {} Hz{}",
            l.clips.len(),
            l.frames(),
            l.settings.rate,
            if l.skipped.is_empty() {
                String::new()
            } else {
                format!(", {} skipped (see .skipped)", l.skipped.len())
            }
        )
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &["clips", "skipped", "frames", "rate", "warps"]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        let l = &self.0;
        match name {
            "clips" => Some(Value::list(
                l.clips.iter().map(|c| Value::str(c.name())).collect(),
            )),
            "skipped" => Some(Value::list(
                l.skipped
                    .iter()
                    .map(|s| {
                        record(vec![
                            ("clip", Value::str(&s.clip)),
                            ("reason", Value::str(&s.reason)),
                        ])
                    })
                    .collect(),
            )),
            "frames" => Some(num(l.frames() as f64)),
            "rate" => Some(num(l.settings.rate)),
            "warps" => Some(Value::list(
                l.settings.warps.iter().map(|w| num(*w)).collect(),
            )),
            _ => None,
        }
    }
}
