//! The pest parser generated from `grammar/mx.pest` (its `Rule`s).

use pest_derive::Parser;

#[derive(Parser)]
#[grammar = "../grammar/mx.pest"]
pub struct MxParser;
