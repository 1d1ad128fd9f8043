//! Engine errors are typed: no function, closure or alias in `src/` outside
//! `src/lang/` has `String` as a `Result`'s error type, so every error below
//! the language can say which argument it concerns by a field and be matched
//! on, never parsed. The test reads the source (comments and string
//! literals skipped) and names the file and line of each one that comes back.

use std::fs;
use std::path::{Path, PathBuf};

/// `src` with comments, string and char literals blanked (newlines kept, so
/// byte offsets still give lines).
fn code_only(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = b.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for c in &mut out[from..to] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
    };
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                let end = b[i..]
                    .iter()
                    .position(|&c| c == b'\n')
                    .map_or(b.len(), |n| i + n);
                blank(&mut out, i, end);
                i = end;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let end = src[i + 2..].find("*/").map_or(b.len(), |n| i + 2 + n + 2);
                blank(&mut out, i, end);
                i = end;
            }
            b'r' if matches!(b.get(i + 1), Some(b'#' | b'"'))
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
                if b.get(i + 1 + hashes) != Some(&b'"') {
                    i += 1;
                    continue;
                }
                let close = format!("\"{}", "#".repeat(hashes));
                let body = i + 2 + hashes;
                let end = src[body..]
                    .find(&close)
                    .map_or(b.len(), |n| body + n + close.len());
                blank(&mut out, i, end);
                i = end;
            }
            b'"' => {
                let mut j = i + 1;
                while j < b.len() && b[j] != b'"' {
                    j += if b[j] == b'\\' { 2 } else { 1 };
                }
                blank(&mut out, i, (j + 1).min(b.len()));
                i = j + 1;
            }
            // a char literal ('x', '\n'), not a lifetime ('a)
            b'\'' if b.get(i + 2) == Some(&b'\'') || b.get(i + 1) == Some(&b'\\') => {
                let end = b[i + 1..]
                    .iter()
                    .skip(1)
                    .position(|&c| c == b'\'')
                    .map_or(b.len(), |n| i + 3 + n);
                blank(&mut out, i, end);
                i = end;
            }
            _ => i += 1,
        }
    }
    String::from_utf8(out).expect("blanking keeps UTF-8")
}

/// Each `Result<…, String>` in `code` (as [`code_only`] leaves it): the line
/// and the text of the type.
fn string_results(code: &str) -> Vec<(usize, String)> {
    let b = code.as_bytes();
    let mut found = vec![];
    let mut from = 0;
    while let Some(k) = code[from..].find("Result").map(|n| from + n) {
        from = k + 1;
        let ident_before = k > 0 && (b[k - 1].is_ascii_alphanumeric() || b[k - 1] == b'_');
        let mut open = k + "Result".len();
        while open < b.len() && b[open].is_ascii_whitespace() {
            open += 1;
        }
        if ident_before || b.get(open) != Some(&b'<') {
            continue;
        }
        // the matching `>`; `->` inside (a closure type's return) is no bracket
        let (mut depth, mut j, mut commas) = (0usize, open, vec![]);
        while j < b.len() {
            match b[j] {
                b'<' | b'(' | b'[' => depth += 1,
                b'>' if j > 0 && b[j - 1] == b'-' => {}
                b'>' | b')' | b']' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                b',' if depth == 1 => commas.push(j),
                _ => {}
            }
            j += 1;
        }
        // the last argument (before a trailing comma, if there is one)
        let end = j.min(b.len());
        let (c, end) = match commas.as_slice() {
            [.., c, t] if code[t + 1..end].trim().is_empty() => (*c, *t),
            [.., c] => (*c, end),
            [] => continue,
        };
        let err = code[c + 1..end].trim();
        if matches!(
            err,
            "String" | "std::string::String" | "alloc::string::String"
        ) {
            let line = code[..k].matches('\n').count() + 1;
            found.push((
                line,
                code[k..=j.min(b.len() - 1)].split_whitespace().collect(),
            ));
        }
    }
    found
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).expect("read src/").flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_engine_error_is_a_bare_string() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![];
    rust_files(&src, &mut files);
    files.sort();
    assert!(
        files.len() > 50,
        "found only {} files under src/",
        files.len()
    );
    let mut bad = vec![];
    for f in files.iter().filter(|f| !f.starts_with(src.join("lang"))) {
        let text = fs::read_to_string(f).expect("read a source file");
        for (line, ty) in string_results(&code_only(&text)) {
            let rel = f.strip_prefix(&src).unwrap_or(f).display().to_string();
            bad.push(format!("src/{rel}:{line}: `{ty}`"));
        }
    }
    assert!(
        bad.is_empty(),
        "engine errors must be typed (an enum or struct naming what is wrong), not String:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_scanner_finds_string_errors_and_only_them() {
    let code = code_only(
        "fn a() -> Result<u8, String> {}\n\
         // fn b() -> Result<u8, String>\n\
         fn c() -> Result<Vec<(u8, String)>, MyError> { \"Result<u8, String>\" }\n\
         let f = |x: u8| -> Result<Box<dyn Fn(u8) -> u8>, std::string::String> { 'r' };\n\
         type R<T> = Result<\n    T,\n    String,\n>;\n\
         fn d<'a>(x: &'a str) -> MyResult<String> {}\n",
    );
    let found: Vec<usize> = string_results(&code).into_iter().map(|(l, _)| l).collect();
    assert_eq!(found, vec![1, 4, 5]);
}
