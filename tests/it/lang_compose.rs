//! Scripts that compose and checks that read signatures: `import`, string
//! `split` and indexing, `has` on values with fields, named arguments
//! checked against each built-in's signature, and usage lines generated
//! from the same signature.

use std::path::Path;
use std::process::Command;

use mx::Interpreter;
use mx::lang::{Args, ErrorKind, Value};

fn write(dir: &Path, name: &str, text: &str) {
    let p = dir.join(name);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, text).unwrap();
}

fn mx(args: &[&str], dir: &Path) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_mx"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs mx");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn an_import_is_read_from_the_importing_scripts_folder_and_keeps_names_apart() {
    let dir = tempfile::tempdir().unwrap();
    // the main script lives in a folder of its own; mx runs from elsewhere
    write(
        dir.path(),
        "scripts/main.mx",
        "let speed = 1\n\
         import \"lib/walks.mx\" as walks\n\
         import \"lib/walks.mx\"\n\
         print(speed, walks.speed, walks.double(21), walks.joint(\"Hips.Xrotation\"))\n\
         print(has({a: 1}, \"a\"), has(walks, \"_helper\"), has(walks, \"speed\"))\n",
    );
    write(
        dir.path(),
        "scripts/lib/walks.mx",
        "// the importer's `speed` is not visible here, nor changed by this one\n\
         let speed = 2\n\
         fn _helper(x) = x * 2\n\
         fn double(x) = _helper(x)\n\
         fn joint(dof) = dof.split(\".\")[0]\n",
    );
    let (ok, out, err) = mx(&["run", "scripts/main.mx"], dir.path());
    assert!(ok, "{err}");
    assert_eq!(out, "1 2 42 Hips\ntrue false true\n");
    let (ok, _, err) = mx(&["check", "scripts/main.mx"], dir.path());
    assert!(ok, "{err}");

    // the imported script sees only the built-ins and the prelude
    write(
        dir.path(),
        "leak/main.mx",
        "let secret = 1\nimport \"b.mx\" as b\n",
    );
    write(dir.path(), "leak/b.mx", "let x = 1\nlet y = secret + 1\n");
    let (ok, _, err) = mx(&["run", "leak/main.mx"], dir.path());
    assert!(!ok);
    assert!(
        err.contains("unknown name `secret`") && err.contains("b.mx:2:"),
        "{err}"
    );
}

#[test]
fn import_cycles_are_reported_with_the_chain() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.mx", "import \"b.mx\" as b\nprint(1)\n");
    write(dir.path(), "b.mx", "import \"c.mx\" as c\n");
    write(dir.path(), "c.mx", "import \"a.mx\" as a\n");
    for cmd in ["run", "check"] {
        let (ok, _, err) = mx(&[cmd, "a.mx"], dir.path());
        assert!(!ok, "{cmd}");
        assert!(
            err.contains("import cycle: a.mx → b.mx → c.mx → a.mx"),
            "{cmd}: {err}"
        );
    }
    // a missing script: a clear error at the path
    write(dir.path(), "m.mx", "import \"nowhere.mx\" as n\n");
    let (ok, _, err) = mx(&["run", "m.mx"], dir.path());
    assert!(
        !ok && err.contains("cannot import") && err.contains("m.mx:1:8"),
        "{err}"
    );
    // a file name that is no name needs `as`
    write(dir.path(), "n.mx", "import \"my-walks.mx\"\n");
    let (ok, _, err) = mx(&["check", "n.mx"], dir.path());
    assert!(!ok && err.contains("as walks"), "{err}");
}

#[test]
fn check_reads_imported_scripts_and_named_arguments() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "main.mx",
        "import \"lib.mx\" as lib\n\
         let m = load(\"walk.bvh\")\n\
         let f = SP(m, coeficients: 5)\n\
         fn g(a, b = 1) = a + b\n\
         print(g(1, bb: 2), lib.wlak, lib.f(1))\n",
    );
    write(
        dir.path(),
        "lib.mx",
        "fn f(x) = x\nlet y = undefined_thing\n",
    );
    let (ok, _, err) = mx(&["check", "main.mx"], dir.path());
    assert!(!ok);
    for says in [
        "`SP` has no parameter named `coeficients`",
        "did you mean `coefficients`?",
        "`g` has no parameter named `bb`",
        "the script imported as `lib` has no name `wlak`",
        "unknown name `undefined_thing`",
        "lib.mx:2:9",
    ] {
        assert!(err.contains(says), "missing {says:?} in:\n{err}");
    }
}

#[test]
fn strings_split_and_index_by_character() {
    let mut i = Interpreter::new();
    let v = |i: &mut Interpreter, s: &str| match i.eval_str(s) {
        Ok(v) => v.repr(),
        Err(d) => panic!("{s}: {}", d.render_plain()),
    };
    assert_eq!(
        v(&mut i, "\"Hips.Xrotation\".split(\".\")"),
        "[\"Hips\", \"Xrotation\"]"
    );
    assert_eq!(v(&mut i, "split(\"a..b\", \".\")"), "[\"a\", \"\", \"b\"]");
    assert_eq!(
        v(&mut i, "join(\"a.b.c\".split(\".\"), \".\")"),
        "\"a.b.c\""
    );
    assert_eq!(
        v(&mut i, "let s = \"Hips\"\n[s[0], s[-1], s[len(s) - 1]]"),
        "[\"H\", \"s\", \"s\"]"
    );
    assert_eq!(v(&mut i, "\"ÄÖ\"[1]"), "\"Ö\"");
    for (src, says) in [
        (
            "\"Hips\"[4]",
            "index 4 is out of range for a string of 4 characters",
        ),
        ("\"Hips\"[-5]", "out of range"),
        ("\"Hips\"[0.5]", "out of range"),
        ("\"Hips\"[\"a\"]", "a string index must be a number"),
        ("\"a\".split(\"\")", "`sep` is empty"),
        ("has(1, \"a\")", "a record or a value with fields"),
    ] {
        let d = i.eval_str(src).unwrap_err();
        assert!(
            d.render_plain().contains(says),
            "{src}: {}",
            d.render_plain()
        );
    }
}

#[test]
fn has_answers_on_an_sp_report() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let mut i = Interpreter::new();
    let src = format!(
        "let m = load({})\n\
         let g = clip_in_place(0s, 0.8s, m) + clip_in_place(1.2s, 2s, m)\n\
         let r = sp_report(SP(g, body: body_of(m), samples: 6, iterations: 5))\n\
         [has(r, \"groups\"), has(r, \"no_such_field\")]",
        mx::lang::value::quote(&data.display().to_string())
    );
    let v = i
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    assert_eq!(v.repr(), "[true, false]");
}

#[test]
fn usage_and_help_are_the_signature_the_checker_reads() {
    let i = Interpreter::new();
    let b = i.registry().function("SP").unwrap();
    let usage = b.signature.to_string();
    for p in ["contact: ", "floor: ", "root: ", "coefficients: "] {
        assert!(usage.contains(p), "SP's usage lacks {p}: {usage}");
    }
    assert!(i.help("SP").unwrap().starts_with(&usage));
    // every built-in: what :help shows is the parsed signature
    for f in i.registry().functions() {
        let e = i.help_entry(&f.name).unwrap();
        assert_eq!(e.signature, f.signature.to_string(), "{}", f.name);
    }
    // an error's usage line is that text too
    let mut i = Interpreter::new();
    let d = i.eval_str("SP(1, coeficients: 5)").unwrap_err();
    let help = d.error().help.clone().unwrap_or_default();
    assert!(help.ends_with(&usage), "{help}");
}

#[test]
fn a_built_in_reading_a_parameter_its_signature_does_not_list_is_a_defect_reported() {
    let mut i = Interpreter::new();
    i.register("f(x)", "reads an unlisted option", |a: &mut Args, _| {
        let x = a.number("x")?;
        let extra = a.number_or("scale", 1.0)?;
        Ok(Value::Number(x * extra))
    });
    let d = i.eval_str("f(2)").unwrap_err();
    assert_eq!(d.kind(), ErrorKind::Host);
    assert!(
        d.render_plain()
            .contains("reads the parameter `scale`, which its signature `f(x)` does not list"),
        "{}",
        d.render_plain()
    );
    i.register("g(x, scale: 1)", "lists it", |a: &mut Args, _| {
        Ok(Value::Number(a.number("x")? * a.number_or("scale", 1.0)?))
    });
    assert_eq!(i.eval_str("g(2, scale: 3)").unwrap().as_number(), Some(6.0));
}
