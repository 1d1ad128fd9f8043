//! What a newcomer met in the first hour (issue 28): a script's paths are
//! its folder's, help lines that fit their error, suggestions for misspelt
//! names and parameters, `fmt` and `env`.

use mx::Interpreter;

fn error_of(src: &str) -> String {
    let mut mx = Interpreter::new();
    match mx.eval_str(src) {
        Ok(v) => panic!("expected an error from {src:?}, got {}", v.repr()),
        Err(d) => d.render_plain(),
    }
}

fn walk() -> String {
    format!(
        "let walk = load({:?})\nlet body = body_of(walk)\n",
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/walk.bvh")
    )
}

#[test]
fn a_script_reads_and_writes_beside_itself_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    std::fs::write(
        sub.join("a.mx"),
        "save(mu({x: interval(fn(t) = t, 0, 1)}), \"o.json\")\nlet back = load(\"o.json\")\n",
    )
    .unwrap();
    let mut mx = Interpreter::new();
    // the test's folder is the repository, not `sub`
    if let Err(d) = mx.eval_file(sub.join("a.mx")) {
        panic!("{}", d.render_plain());
    }
    assert!(sub.join("o.json").is_file());
    // after the script, evaluation is back on the current folder
    let e = error_of("load(\"o.json\")");
    assert!(e.contains("o.json"), "{e}");
}

#[test]
fn help_lines_fit_the_error() {
    let e = error_of("load(\"no_such_clip.bvh\")");
    assert!(e.contains("check the file name"), "{e}");
    assert!(!e.contains("malformed"), "{e}");

    let dir = tempfile::tempdir().unwrap();
    let urdf = dir.path().join("r.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="r">
  <link name="base"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/></joint>
</robot>"#,
    )
    .unwrap();
    let e = error_of(&format!("load({:?})", urdf.display().to_string()));
    assert!(e.contains("`arm`") && e.contains("not defined"), "{e}");
    assert!(e.contains("define that link"), "{e}");
    assert!(!e.contains("mx reads fixed-base"), "{e}");
}

#[test]
fn misspelt_names_and_parameters_get_the_right_suggestion() {
    let e = error_of("fil(1)");
    assert!(e.contains("did you mean `fill`?"), "{e}");
    let e = error_of(&format!("{}SP(walk, bdy: body)", walk()));
    assert!(e.contains("no parameter named `bdy`"), "{e}");
    assert!(e.contains("did you mean `body`?"), "{e}");
    let mx = Interpreter::new();
    let e = mx.help("motoin").unwrap_err();
    assert!(e.contains("did you mean `motion`?"), "{e}");
}

#[test]
fn fmt_rounds_and_env_reads_the_environment() {
    let mut mx = Interpreter::new();
    let s = |mx: &mut Interpreter, src: &str| mx.eval_str(src).unwrap().display();
    assert_eq!(s(&mut mx, "fmt(6.466660200000001, 3)"), "6.47");
    assert_eq!(s(&mut mx, "fmt(1234.5678)"), "1235");
    assert_eq!(s(&mut mx, "repr(6.466660200000001)"), "6.466660200000001");
    assert!(error_of("fmt(1, 0)").contains("digits must be a whole number from 1 to 17"));
    assert_eq!(
        s(&mut mx, "env(\"MX_SURELY_UNSET_VARIABLE_28\") == nil"),
        "true"
    );
    let path = std::env::var("PATH").unwrap();
    assert_eq!(s(&mut mx, "env(\"PATH\")"), path);
    // spans in summaries are rounded, the exact value stays with repr
    let m = s(&mut mx, "str(mu({x: interval(0, 0, 6.466660200000001)}))");
    assert!(m.contains("[0, 6.46666]"), "{m}");
}
