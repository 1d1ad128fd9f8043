//! The REPL's question "is this input complete?": open brackets, an
//! unterminated block comment or a trailing operator ask for another line.
//!
//! A line that *begins* with an operator continues the one above it (see
//! `line_cont` in mx.pest), but the REPL cannot wait for it: when a line is
//! complete it runs. Within one input (brackets still open, or several lines
//! pasted at once) such a line continues the expression above as in a script.

/// Whether `src` is incomplete in a way more lines could fix (open brackets,
/// an unterminated block comment or string, a trailing infix operator, `=`,
/// `,` or `\`): the REPL keeps reading.
pub fn is_incomplete(src: &str) -> bool {
    let mut depth: i64 = 0;
    // where the last token outside comments ends: a comment's last character
    // is not an operator
    let mut code_end = 0;
    let mut chars = src.char_indices().peekable();
    while let Some((_, c)) = chars.next() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            '"' => {
                let mut closed = false;
                while let Some((_, d)) = chars.next() {
                    match d {
                        '\\' => {
                            chars.next();
                        }
                        '"' => {
                            closed = true;
                            break;
                        }
                        '\n' => break,
                        _ => {}
                    }
                }
                if !closed && chars.peek().is_none() {
                    return false;
                }
            }
            '/' if chars.peek().map(|p| p.1) == Some('/') => {
                for (_, d) in chars.by_ref() {
                    if d == '\n' {
                        break;
                    }
                }
                continue;
            }
            '/' if chars.peek().map(|p| p.1) == Some('*') => {
                chars.next();
                let mut closed = false;
                let mut prev = ' ';
                for (_, d) in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        closed = true;
                        break;
                    }
                    prev = d;
                }
                if !closed {
                    return true;
                }
                continue;
            }
            _ => {}
        }
        if !c.is_whitespace() {
            code_end = chars.peek().map_or(src.len(), |p| p.0);
        }
    }
    depth > 0 || ends_with_operator(&src[..code_end])
}

/// A trailing infix operator, `=`, `,` or `\` asks for another line; a
/// trailing `--` does not (nothing continues it).
fn ends_with_operator(code: &str) -> bool {
    if code.ends_with([
        '+', '*', '/', '&', '∧', '=', ',', '|', '−', '<', '>', '%', '×', '≤', '≥', '\\',
    ]) {
        return true;
    }
    if code.ends_with('-') {
        return !code.ends_with("--");
    }
    // `and`, `or`, `not` as whole words, not the end of a name (`color`)
    ["and", "or", "not"].iter().any(|w| {
        code.strip_suffix(w).is_some_and(|head| {
            !head
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
    })
}

#[cfg(test)]
mod tests {
    use super::is_incomplete;

    #[test]
    fn open_brackets_and_trailing_operators_ask_for_more() {
        for src in [
            "[1,",
            "f(",
            "{",
            "1 +",
            "a and",
            "x ==",
            "1 <",
            "2 ×",
            "let x =",
            "a -",
            "1 \\",
            "/* open",
            "xs.map(fn(x) {\n  x\n  + 1",
        ] {
            assert!(is_incomplete(src), "{src:?} is incomplete");
        }
    }

    #[test]
    fn complete_lines_run() {
        for src in [
            "1 + 2",
            "color",
            "let x = 1 // a comment that ends with +",
            "let y = 2 /* ends with - */",
            "x--",
            "[1,\n2]",
            // a leading operator continues inside one input
            "let x = 1\n  + 2",
            "let f = fn(x) {\n  x\n  - 1\n}",
            "\"unclosed",
        ] {
            assert!(!is_incomplete(src), "{src:?} is complete");
        }
    }
}
