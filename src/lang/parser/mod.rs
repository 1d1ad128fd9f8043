//! Source text → AST. pest does the tokenising and structure
//! (`grammar/mx.pest`, `grammar.rs`); `build.rs` builds the tree, with an
//! operator-precedence loop for the operator trees; `nesting.rs` bounds
//! pest's recursion before it runs; `errors.rs` turns syntax errors into
//! [`MxError`]s with the span pest reports and a help line; `recover.rs`
//! parses on past syntax errors for `mx check`; `complete.rs` answers the
//! REPL's "is this input complete?".

pub(crate) mod build;
mod complete;
mod errors;
mod grammar;
mod recover;

use pest::Parser;

use super::ast::*;
use super::diagnostics::{ErrorKind, MxError, MxResult};
pub use super::nesting::MAX_NESTING;
use super::nesting::check_nesting;
use build::Builder;
pub use complete::is_incomplete;
use errors::syntax_error;
use grammar::{MxParser, Rule};
pub use recover::MAX_SYNTAX_ERRORS;

/// Parse a whole program from source `file`.
pub fn parse_program(src: &str, file: SourceId) -> MxResult<Program> {
    check_nesting(src, file)?;
    // pest recurses once per nesting level, which `check_nesting` bounds;
    // run it on a stack of known size (reserved, not committed) so that
    // bound fits whatever thread we are on (test threads have 2 MB).
    stacker::grow(PARSE_STACK, || parse_program_inner(src, file))
}

fn parse_program_inner(src: &str, file: SourceId) -> MxResult<Program> {
    let mut pairs = MxParser::parse(Rule::program, src).map_err(|e| syntax_error(e, src, file))?;
    let program = pairs
        .next()
        .ok_or_else(|| MxError::new(ErrorKind::Syntax, "empty parse"))?;
    let b = Builder {
        file,
        src,
        offset: 0,
    };
    let mut stmts = Vec::new();
    for p in program.into_inner() {
        if p.as_rule() == Rule::EOI {
            break;
        }
        stmts.push(b.stmt(p)?);
    }
    Ok(Program { stmts })
}

/// Parse a whole program, reading on past syntax errors (`mx check`): the
/// statements that parse and every syntax error, in source order (at most
/// [`MAX_SYNTAX_ERRORS`], then a note). A broken `let x`/`fn f` statement
/// still binds its name in the program returned (to an empty list: the
/// program is for name resolution, not for running). A program that parses
/// is returned as [`parse_program`] returns it, with no errors.
pub fn parse_program_recovering(src: &str, file: SourceId) -> (Program, Vec<MxError>) {
    if let Err(e) = check_nesting(src, file) {
        return (Program { stmts: vec![] }, vec![e]);
    }
    stacker::grow(PARSE_STACK, || match parse_program_inner(src, file) {
        Ok(p) => (p, vec![]),
        Err(first) => {
            let (program, errors) = recover::parse_statements(src, file);
            // The statement-wise pass must find at least the error the
            // whole-program parse found.
            if errors.is_empty() {
                (program, vec![first])
            } else {
                (program, errors)
            }
        }
    })
}

/// Reserved (not committed) for pest's recursion: [`MAX_NESTING`] levels of
/// the deepest construct took under 1 MB (measured, release and dev), so
/// the bound leaves a wide margin.
const PARSE_STACK: usize = 256 * 1024 * 1024;

/// Parse a single expression (REPL `:type`, `mx eval`).
pub fn parse_expr(src: &str, file: SourceId) -> MxResult<Expr> {
    let program = parse_program(src, file)?;
    let mut stmts = program.stmts;
    match (stmts.len(), stmts.pop()) {
        (1, Some(Stmt::Expr(e))) => Ok(e),
        (_, Some(s)) => Err(
            MxError::new(ErrorKind::Syntax, "expected a single expression")
                .at(s.span())
                .help("write one expression, e.g. `1 + 2` or `len([1, 2])`"),
        ),
        (_, None) => Err(
            MxError::new(ErrorKind::Syntax, "expected an expression, found nothing")
                .at(Span::new(file, 0, 0))
                .help("write one expression, e.g. `1 + 2`"),
        ),
    }
}

/// The value of `text` read as a number literal of the language (`3.2`,
/// `1e-3`, `.5`, `250ms`, `90deg`: the grammar's own `number` rule, units
/// applied), with an optional sign in front (`-2`, `+2`, `−2`); `None` for
/// anything else. `number("…")` reads text this way, so a string holding
/// what a script could write as a literal reads as that literal does.
pub fn number_literal(text: &str) -> Option<f64> {
    let (sign, digits) = match text.chars().next()? {
        '-' | '−' => (-1.0, &text[text.chars().next()?.len_utf8()..]),
        '+' => (1.0, &text[1..]),
        _ => (1.0, text),
    };
    let pair = MxParser::parse(Rule::number, digits).ok()?.next()?;
    if pair.as_str().len() != digits.len() {
        return None;
    }
    let mut it = pair.into_inner();
    let x: f64 = it.next()?.as_str().parse().ok()?;
    let x = build::in_base_units(x, it.next().map(|u| u.as_str()));
    x.is_finite().then_some(sign * x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(src: &str) -> Program {
        match parse_program(src, 0) {
            Ok(p) => p,
            Err(e) => panic!("{src:?}: {e} {:?}", e.span),
        }
    }

    fn show(e: &Expr) -> String {
        match &e.kind {
            ExprKind::Number(x) => format!("{x}"),
            ExprKind::Ident(n) => n.clone(),
            ExprKind::Binary(op, a, b) => format!("({} {} {})", show(a), op.symbol(), show(b)),
            ExprKind::Unary(UnOp::Neg, a) => format!("(-{})", show(a)),
            ExprKind::Unary(UnOp::Not, a) => format!("(!{})", show(a)),
            ExprKind::Call(f, args) => format!(
                "{}({})",
                show(f),
                args.iter()
                    .map(|a| show(&a.value))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            ExprKind::Method(r, n, _, args) => {
                format!(
                    "{}.{}({})",
                    show(r),
                    n,
                    args.iter()
                        .map(|a| show(&a.value))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
            ExprKind::Field(r, n, _) => format!("{}.{n}", show(r)),
            other => format!("{other:?}"),
        }
    }

    fn e(src: &str) -> String {
        match &p(src).stmts[..] {
            [Stmt::Expr(e)] => show(e),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn precedence() {
        assert_eq!(e("a + b * c"), "(a + (b * c))");
        assert_eq!(e("a - b - c"), "((a - b) - c)");
        assert_eq!(e("a + b & c"), "(a + (b & c))");
        assert_eq!(e("a ∧ b − c"), "((a & b) - c)");
        assert_eq!(e("-a * b"), "((-a) * b)");
        assert_eq!(e("a < b + 1 && c || d"), "(((a < (b + 1)) && c) || d)");
        assert_eq!(e("x.only(1).f(2)"), "x.only(1).f(2)");
        assert_eq!(e("a - -b"), "(a - (-b))");
    }

    #[test]
    fn units() {
        assert_eq!(e("2s"), "2");
        assert_eq!(e("250ms"), "0.25");
        assert_eq!(e("180deg"), format!("{}", std::f64::consts::PI));
        assert_eq!(e("1.2rad"), "1.2");
        assert_eq!(e("-2s"), "-2");
        assert!(parse_program("2sin", 0).is_err());
    }

    #[test]
    fn statements_and_newlines() {
        let prog = p(
            "let a = 1; let b = 2\n\n// comment\nfn f(t) = t * 2 /* block\n comment */\nf(a +\n b)\n",
        );
        assert_eq!(prog.stmts.len(), 4);
        let prog = p(
            "let r = {a: 1, \"Hips.Xposition\": 2,\n}\nlet l = [\n1,\n2\n]\nsave(m, \"x.csv\", rate: 30)",
        );
        assert_eq!(prog.stmts.len(), 3);
        let prog = p(
            "if a < 1 { 2 } else if b { 3 } else {\n 4\n}\nlet g = fn(x, y = 2) = x + y\nwalk\n  .only(\"x\")",
        );
        assert_eq!(prog.stmts.len(), 3);
        // A newline ends a statement: `a` then `-1`.
        assert_eq!(p("a\n-1").stmts.len(), 2);
    }

    fn stmts(src: &str) -> Vec<String> {
        p(src)
            .stmts
            .iter()
            .map(|s| match s {
                Stmt::Expr(e) => show(e),
                Stmt::Let(name, _, value) => format!("let {name} = {}", show(value)),
                other => format!("{other:?}"),
            })
            .collect()
    }

    /// A line that begins with an infix operator continues the line above;
    /// a leading minus does so only when whitespace follows it.
    #[test]
    fn a_line_may_begin_with_an_operator() {
        assert_eq!(stmts("a\n  + b"), ["(a + b)"]);
        assert_eq!(stmts("let x = a\n  + b\n  * c"), ["let x = (a + (b * c))"]);
        assert_eq!(stmts("a\n- b"), ["(a - b)"]);
        assert_eq!(stmts("a\n−\tb"), ["(a - b)"]);
        for op in [
            "/", "%", "&", "∧", "×", "==", "!=", "<", "<=", ">", ">=", "≤", "≥", "&&", "||", "and",
            "or",
        ] {
            let want = stmts(&format!("a {op} b"));
            assert_eq!(stmts(&format!("a\n  {op} b")), want, "{op}");
            assert_eq!(stmts(&format!("a\r\n  {op} b")), want, "{op} after CRLF");
        }
        // past blank and comment lines, and inside brackets and blocks
        assert_eq!(stmts("a\n\n  // why\n  + b"), ["(a + b)"]);
        assert_eq!(stmts("f(a\n  + b)"), ["f((a + b))"]);
        assert_eq!(stmts("{ let y = 1\n  y\n  + 2 }").len(), 1);
        // a field or method on the next line
        assert_eq!(stmts("r\n  .a\n  .b"), ["r.a.b"]);
        assert_eq!(stmts("x\n  .f(1)\n  + 2"), ["(x.f(1) + 2)"]);
    }

    /// The ambiguous cases: a minus glued to its operand is unary and starts a
    /// new statement, as in Python, Julia and Kotlin; so is `!x`, `not x`, a
    /// name that begins with `and`/`or`, and a `.5` literal.
    #[test]
    fn a_leading_unary_operator_starts_a_statement() {
        assert_eq!(stmts("a\n-b"), ["a", "(-b)"]);
        assert_eq!(stmts("a\n  -1"), ["a", "-1"]);
        assert_eq!(stmts("a\n−b"), ["a", "(-b)"]);
        assert_eq!(stmts("let y = 2\n-y"), ["let y = 2", "(-y)"]);
        assert_eq!(stmts("{ let y = 2\n  -y }").len(), 1, "a block's value");
        assert_eq!(stmts("a\n!b"), ["a", "(!b)"]);
        assert_eq!(stmts("a\nnot b"), ["a", "(!b)"]);
        assert_eq!(stmts("a\norder"), ["a", "order"]);
        assert_eq!(stmts("a\nandy"), ["a", "andy"]);
        assert_eq!(stmts("a\n.5"), ["a", "0.5"]);
        // a minus then another minus: binary, then unary
        assert_eq!(stmts("a\n- -b"), ["(a - (-b))"]);
    }

    #[test]
    fn a_leading_operator_with_nothing_above_says_why() {
        for src in ["+ 1", "* 2", "fn f() { 1 }\n+ 1", ".a", "let x = 1;\n== 2"] {
            let err = parse_program(src, 0).unwrap_err();
            let help = err.help.clone().unwrap_or_default();
            assert!(
                help.contains("continues the expression on the line above"),
                "{src:?}: {help}"
            );
        }
    }

    #[test]
    fn number_literals_read_from_text() {
        assert_eq!(number_literal("3.2"), Some(3.2));
        assert_eq!(number_literal("-1e-3"), Some(-1e-3));
        assert_eq!(number_literal("+.5"), Some(0.5));
        assert_eq!(number_literal("−2"), Some(-2.0));
        assert_eq!(number_literal("250ms"), Some(0.25));
        assert_eq!(number_literal("90deg"), Some(std::f64::consts::FRAC_PI_2));
        assert_eq!(number_literal("-0").map(f64::is_sign_negative), Some(true));
        for bad in [
            "", "-", "3,2", "3.", "1e", "nan", "inf", "0x10", "2 s", "2sec", "1e999", "--1",
            "3.2.1", "½",
        ] {
            assert_eq!(number_literal(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn syntax_errors_have_spans_and_help() {
        let err = parse_program("let x = (1 + 2", 0).unwrap_err();
        assert_eq!(err.kind, ErrorKind::Syntax);
        assert!(err.help.is_some());
        let err = parse_program("let = 3", 0).unwrap_err();
        assert_eq!(err.span.map(|s| s.start), Some(4));
        assert!(parse_program("print(\"abc)", 0).is_err());
        assert!(parse_program("{a: 1, a: 2}", 0).is_err());
    }

    /// Runs on the test harness's thread (2 MB stack): deep input must give
    /// the nesting diagnostic, not overflow the stack.
    #[test]
    fn deep_nesting_is_refused_with_a_diagnostic() {
        let n = 100_000;
        for src in [
            format!("{}1{}", "(".repeat(n), ")".repeat(n)),
            format!("{}1", "[".repeat(n)),
            format!("{}1", "{a: ".repeat(n)),
            format!("{}1", "{ ".repeat(n)),
            format!("{}1", "f(".repeat(n)),
            format!("let f = {}1", "fn(x) = ".repeat(n)),
            format!("fn f(x = {}1) = x", "fn(y = ".repeat(n)),
            format!("{}true{}", "if ".repeat(n), " { 1 }".repeat(n)),
            format!("if a {{ {}1", "if b { ".repeat(n)),
        ] {
            let e = parse_program(&src, 0).unwrap_err();
            assert!(e.message.contains("nesting too deep"), "{}", e.message);
            let span = e.span.expect("a span");
            assert!(span.start > 0 && (span.start as usize) < src.len() / 2);
            assert!(e.help.is_some());
        }
    }

    /// At the limit every recursive construct still parses (on the parse
    /// stack, from the harness's 2 MB thread).
    #[test]
    fn nesting_up_to_the_limit_parses() {
        let n = MAX_NESTING;
        for src in [
            format!("{}1{}", "(".repeat(n), ")".repeat(n)),
            format!("{}1{}", "[".repeat(n), "]".repeat(n)),
            format!("{}1{}", "{a: ".repeat(n), "}".repeat(n)),
            format!("{}1{}", "f(".repeat(n), ")".repeat(n)),
            // The last `fn`'s parameter list, the blocks after the last
            // `if`, open one level more.
            format!("{}1", "fn(x) = ".repeat(n - 1)),
            format!("{}true{}", "if ".repeat(n - 1), " { 1 }".repeat(n - 1)),
            format!("{}1{}", "if b { ".repeat(n / 2), " }".repeat(n / 2)),
            format!(
                "{}1{}",
                "-[fn(x) = if x { ".repeat(n / 4),
                " }]".repeat(n / 4)
            ),
        ] {
            if let Err(e) = parse_program(&src, 0) {
                panic!("{}: {e} {:?}", &src[..20], e.span);
            }
        }
    }

    /// Chains of operators, calls and `else if` are loops in the grammar and
    /// in the precedence parser, and the tree drops iteratively: they have
    /// no depth limit.
    #[test]
    fn long_chains_parse_and_drop() {
        let n = 1_000_000;
        let chains = [
            format!("{}x", "-".repeat(n)),
            format!("{}x", "not ".repeat(n)),
            format!("x{}", " + x".repeat(n)),
            format!("x{}", " * -x".repeat(n)),
            format!("f{}", "()".repeat(n)),
            format!("r{}", ".a".repeat(n)),
            format!(
                "if a {{ 1 }}{} else {{ 3 }}",
                " else if b { 2 }".repeat(n / 10)
            ),
        ];
        for src in chains {
            assert_one_statement(&src);
        }
    }

    /// `src` parses to exactly one statement (long inputs: the error names its start).
    fn assert_one_statement(src: &str) {
        match parse_program(src, 0) {
            Ok(p) => assert_eq!(p.stmts.len(), 1),
            Err(e) => panic!("{}: {e}", &src[..20.min(src.len())]),
        }
    }

    #[test]
    fn else_if_chains_nest_from_each_if() {
        let src = "if a { 1 } else if b { 2 } else if c { 3 } else { 4 }";
        let [Stmt::Expr(e)] = &p(src).stmts[..] else {
            panic!()
        };
        let mut node = e;
        for (start, cond) in [(0, "a"), (16, "b"), (32, "c")] {
            let ExprKind::If(c, _, Some(els)) = &node.kind else {
                panic!("{node:?}")
            };
            assert_eq!(
                (node.span.start, node.span.end as usize),
                (start, src.len())
            );
            assert_eq!(show(c), cond);
            node = els;
        }
        assert!(matches!(node.kind, ExprKind::Block(_)));
        let [Stmt::Expr(e)] = &p("if a { 1 } else if b { 2 }").stmts[..] else {
            panic!()
        };
        let ExprKind::If(_, _, Some(inner)) = &e.kind else {
            panic!()
        };
        assert!(matches!(inner.kind, ExprKind::If(_, _, None)));
    }

    #[test]
    fn long_runs_of_whitespace_and_prefixes_parse() {
        // Whitespace, newlines, comments and prefix operators are loops in
        // the grammar, not recursion: long runs need no deep stack.
        let n = 200_000;
        for src in [
            format!("1{}+ 1", " ".repeat(n)),
            format!("f(1,{}2)", "\n".repeat(n)),
            format!("1{}+ 1", "/**/".repeat(n)),
            format!("{}1", "- ".repeat(n)),
        ] {
            assert_one_statement(&src);
        }
    }

    #[test]
    fn incomplete_input() {
        assert!(is_incomplete("f(1,"));
        assert!(is_incomplete("let a = [1,\n2"));
        assert!(is_incomplete("1 +"));
        assert!(!is_incomplete("f(1)"));
        assert!(!is_incomplete("\"abc"));
    }
}
