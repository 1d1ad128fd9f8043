//! The REPL's question "is this input complete?": open brackets, an
//! unterminated block comment or a trailing operator ask for another line.

/// Whether `src` is incomplete in a way more lines could fix (open brackets,
/// an unterminated block comment or string): the REPL keeps reading.
pub fn is_incomplete(src: &str) -> bool {
    let mut depth: i64 = 0;
    let mut chars = src.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            '"' => {
                let mut closed = false;
                while let Some(d) = chars.next() {
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
            '/' if chars.peek() == Some(&'/') => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        break;
                    }
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                chars.next();
                let mut closed = false;
                let mut prev = ' ';
                for d in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        closed = true;
                        break;
                    }
                    prev = d;
                }
                if !closed {
                    return true;
                }
            }
            _ => {}
        }
    }
    if depth > 0 {
        return true;
    }
    // A trailing infix operator or `=` also asks for another line.
    let t = src.trim_end();
    t.ends_with(['+', '*', '/', '&', '∧', '=', ',', '|', '−']) && !t.ends_with("//")
        || (t.ends_with('-') && !t.ends_with("--"))
}
