//! A built-in's signature, parsed once when it is registered: the one
//! statement of what it takes. `mx check` checks named arguments against it,
//! the usage line of every error and `:help` print it, and [`super::Args`]
//! refuses to hand a built-in a parameter it does not list — so adding a
//! parameter is one edit to the signature, and the checker, the usage line
//! and the help cannot disagree with what the built-in reads.
//!
//! The text is what `:help` shows: `SP(m, body: b, contact: "off")` —
//! parameters before the first `name: default` are required, `name: default`
//! ones are options (the default as prose), `...` alone takes any number of
//! further positional arguments, `...options` any named ones (the built-in
//! passes them on, as `save` does to a file format). A built-in with two
//! forms lists both: `loop(m, n) | loop(m, ts, tf)`. Parsing is lenient (a
//! default may hold brackets and commas: `gravity: [x, y, z]`), so any text
//! is a signature; an embedder's odd one just checks less.

use std::fmt;

/// One parameter as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: String,
    /// The default as written (`"auto"`, `[x, y, z]`), if it has one.
    pub default: Option<String>,
}

/// One form of a call: `name(params)`.
#[derive(Clone, Debug, PartialEq)]
struct Form {
    params: Vec<Param>,
    /// `...`: any further positional arguments.
    more_positional: bool,
    /// `...options`: any named arguments, passed on.
    open_named: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Signature {
    name: String,
    forms: Vec<Form>,
}

impl Signature {
    pub fn parse(text: &str) -> Signature {
        let name = text.split('(').next().unwrap_or(text).trim().to_string();
        let forms = split_top(text, '|')
            .into_iter()
            .map(|form| {
                let inner = match (form.find('('), form.rfind(')')) {
                    (Some(a), Some(b)) if a < b => &form[a + 1..b],
                    _ => "",
                };
                let mut f = Form {
                    params: vec![],
                    more_positional: false,
                    open_named: None,
                };
                for p in split_top(inner, ',') {
                    let p = p.trim();
                    if let Some(rest) = p.strip_prefix("...") {
                        match rest.trim() {
                            "" => f.more_positional = true,
                            n => f.open_named = Some(n.to_string()),
                        }
                        continue;
                    }
                    let (n, default) = match p.split_once(':') {
                        Some((n, d)) => (n.trim(), Some(d.trim().to_string())),
                        None => (p, None),
                    };
                    if !n.is_empty() {
                        f.params.push(Param {
                            name: n.to_string(),
                            default,
                        });
                    }
                }
                f
            })
            .collect();
        Signature { name, forms }
    }

    /// The function's name (`SP`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Every parameter name of every form, each once, in order.
    pub fn params(&self) -> Vec<&str> {
        let mut out: Vec<&str> = vec![];
        for p in self.forms.iter().flat_map(|f| &f.params) {
            if !out.contains(&p.name.as_str()) {
                out.push(&p.name);
            }
        }
        out
    }

    /// Whether a call may name `name` (`name: value`): one of its parameters,
    /// or any name where it passes named arguments on (`...options`).
    pub fn accepts(&self, name: &str) -> bool {
        self.open_named() || self.params().contains(&name)
    }

    /// Whether it takes any named argument (`...options`): the checker can
    /// then not tell a misspelt one.
    pub fn open_named(&self) -> bool {
        self.forms.iter().any(|f| f.open_named.is_some())
    }
}

/// The usage line: generated from the parsed parameters, so what an error's
/// `usage:` and `:help` show is what the checker checks.
impl fmt::Display for Signature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, form) in self.forms.iter().enumerate() {
            if i > 0 {
                f.write_str(" | ")?;
            }
            let mut parts: Vec<String> = form
                .params
                .iter()
                .map(|p| match &p.default {
                    Some(d) => format!("{}: {d}", p.name),
                    None => p.name.clone(),
                })
                .collect();
            if form.more_positional {
                parts.push("...".into());
            }
            if let Some(n) = &form.open_named {
                parts.push(format!("...{n}"));
            }
            write!(f, "{}({})", self.name, parts.join(", "))?;
        }
        Ok(())
    }
}

/// `text` split at `sep` outside brackets and quotes.
pub(crate) fn split_top(text: &str, sep: char) -> Vec<&str> {
    let mut out = vec![];
    let (mut depth, mut quoted, mut start) = (0i32, false, 0);
    for (i, c) in text.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '(' | '[' | '{' if !quoted => depth += 1,
            ')' | ']' | '}' if !quoted => depth -= 1,
            c if c == sep && depth == 0 && !quoted => {
                out.push(&text[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    out.push(&text[start..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_with_brackets_forms_and_rest() {
        let s = Signature::parse("SP(m, body: b, gravity: [x, y, z], root: \"a, b\")");
        assert_eq!(s.name(), "SP");
        assert_eq!(s.params(), ["m", "body", "gravity", "root"]);
        assert!(s.accepts("gravity") && !s.accepts("y") && !s.accepts("z]"));
        assert_eq!(
            s.to_string(),
            "SP(m, body: b, gravity: [x, y, z], root: \"a, b\")"
        );
        let l = Signature::parse("loop(m, n) | loop(m, ts, tf)");
        assert_eq!(l.params(), ["m", "n", "ts", "tf"]);
        assert_eq!(l.to_string(), "loop(m, n) | loop(m, ts, tf)");
        let p = Signature::parse("print(x, ...)");
        assert!(!p.open_named() && p.accepts("x") && !p.accepts("y"));
        let s = Signature::parse("save(x, path, ...options)");
        assert!(s.open_named() && s.accepts("rate"));
        assert_eq!(s.to_string(), "save(x, path, ...options)");
        assert_eq!(Signature::parse("f()").params(), Vec::<&str>::new());
        // anything is a signature
        assert_eq!(Signature::parse("odd").name(), "odd");
    }
}
