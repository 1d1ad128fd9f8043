//! Issue 44 items 7 and 8: `keys`, `has` and field access agree on every
//! record-like value (SP reports included), and the string built-ins
//! `starts_with`, `ends_with` and `number`.

use std::path::Path;

use mx::Interpreter;
use mx::lang::value::quote;

fn data(name: &str) -> String {
    quote(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("examples/data")
            .join(name)
            .display()
            .to_string(),
    )
}

fn eval(i: &mut Interpreter, src: &str) -> String {
    i.eval_str(src)
        .unwrap_or_else(|d| panic!("{src}: {}", d.render_plain()))
        .repr()
}

fn error(i: &mut Interpreter, src: &str) -> String {
    match i.eval_str(src) {
        Ok(v) => panic!("{src}: no error, got {}", v.repr()),
        Err(d) => d.render_plain(),
    }
}

/// For every key k of `v`: `has(v, k)`, and `v.k`, `v[k]` and `values(v)`
/// read the same value (compared as printed: a scene's `body` is a new body
/// each time); a name not listed is no field, and the error for it offers the
/// listed ones.
fn fields_agree(i: &mut Interpreter, v: &str) {
    let check = format!(
        "let v = {v}\n\
         let ks = keys(v)\n\
         assert(len(ks) > 0, message: \"no keys\")\n\
         assert(fold(map(ks, fn(k) = has(v, k)), true, fn(a, x) = a && x), message: \"has\")\n\
         assert(repr(values(v)) == repr(map(ks, fn(k) = v[k])), message: \"values\")\n\
         !has(v, \"no_such_field\")"
    );
    assert_eq!(eval(i, &check), "true", "{v}");
    let keys = eval(i, &format!("keys({v})"));
    let first = keys
        .trim_start_matches("[\"")
        .split('"')
        .next()
        .unwrap()
        .to_string();
    assert_eq!(
        eval(
            i,
            &format!("repr(({v}).{first}) == repr(({v})[\"{first}\"])")
        ),
        "true",
        "{v}.{first}"
    );
    let e = error(i, &format!("({v}).{first}_x"));
    assert!(
        e.contains("no field")
            && (e.contains(&format!("did you mean `{first}`?")) || e.contains("its fields are:")),
        "{v}: {e}"
    );
    let e = error(i, &format!("({v}).zzzzzzzzzz"));
    assert!(
        e.contains("its fields are:") && e.contains(&first),
        "{v}: {e}"
    );
}

#[test]
fn keys_has_and_fields_agree_on_an_sp_report() {
    let mut i = Interpreter::new();
    eval(
        &mut i,
        &format!(
            "let m = load({})\n\
             let g = clip_in_place(0s, 0.8s, m) + clip_in_place(1.2s, 2s, m)\n\
             let r = sp_report(SP(g, body: body_of(m), samples: 6, iterations: 5))",
            data("walk.bvh")
        ),
    );
    // the issue's form, as written
    let keys = eval(
        &mut i,
        "keys(sp_report(SP(g, body: body_of(m), samples: 6, iterations: 5)))",
    );
    for k in ["groups", "contacts", "text"] {
        assert!(keys.contains(&format!("\"{k}\"")), "{keys}");
    }
    fields_agree(&mut i, "r");
    assert_eq!(eval(&mut i, "r.groups == r[\"groups\"]"), "true");
    assert_eq!(eval(&mut i, "type(r.contacts)"), "\"list\"");
}

#[test]
fn keys_has_and_fields_agree_on_every_value_with_fields() {
    let mut i = Interpreter::new();
    eval(
        &mut i,
        &format!(
            "let m = load({walk})\n\
             let b = body_of(m)\n\
             let knee = load({knee})\n\
             let robot = load({urdf})",
            walk = data("walk.bvh"),
            knee = quote(
                &Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("tests/data/opensim/joints/BallJoint.osim")
                    .display()
                    .to_string()
            ),
            urdf = data("double_pendulum.urdf"),
        ),
    );
    for v in [
        "b",
        "knee",
        "revolute([0, 0, 1])",
        "link(\"a\", parent: \"world\", joint: revolute([0, 0, 1]), mass: 1)",
        "scene(robot, gravity: [0, 0, -9.81])",
        "ik_report(ik(b, clip(0s, 0.2s, m), positions(clip(0s, 0.2s, m), b).only(\"LeftFoot.*\")))",
        "{a: 1, b: 2}",
    ] {
        fields_agree(&mut i, v);
    }
    // optional fields are listed where the value has them, and only there
    assert_eq!(
        eval(&mut i, "[has(b, \"report\"), has(knee, \"report\")]"),
        "[false, true]"
    );
    assert_eq!(
        eval(
            &mut i,
            "keys(b) == filter(keys(knee), fn(k) = k != \"report\" && k != \"defaults\")"
        ),
        "true"
    );
}

#[test]
fn values_without_fields_say_so() {
    let mut i = Interpreter::new();
    eval(&mut i, &format!("let m = load({})", data("walk.bvh")));
    for (src, says) in [
        ("keys(m)", "a record or a value with fields"),
        ("keys(1)", "a record or a value with fields"),
        ("has(m, \"x\")", "a record or a value with fields"),
        ("m.frames", "has no fields"),
        ("m[\"frames\"]", "cannot index"),
    ] {
        let e = error(&mut i, src);
        assert!(e.contains(says), "{src}: {e}");
    }
    // the argument at fault is named
    let e = error(&mut i, "keys(1)");
    assert!(e.contains("`r`"), "{e}");
}

#[test]
fn starts_with_and_ends_with() {
    let mut i = Interpreter::new();
    for (src, want) in [
        ("starts_with(\"LeftFoot\", \"Left\")", "true"),
        ("\"LeftFoot\".starts_with(\"Right\")", "false"),
        ("ends_with(\"walk.bvh\", \".bvh\")", "true"),
        ("\"walk.bvh\".ends_with(\".BVH\")", "false"),
        (
            "[\"a\".starts_with(\"\"), \"a\".ends_with(\"\"), \"\".starts_with(\"a\")]",
            "[true, true, false]",
        ),
        (
            "\"é.bvh\".ends_with(\"h\") && \"éa\".starts_with(\"é\")",
            "true",
        ),
        (
            "filter([\"Hips.Xposition\", \"LeftFoot.Zrotation\"], fn(d) = d.ends_with(\"rotation\"))",
            "[\"LeftFoot.Zrotation\"]",
        ),
    ] {
        assert_eq!(eval(&mut i, src), want, "{src}");
    }
    for (src, names) in [
        ("starts_with(1, \"a\")", "`s`"),
        ("ends_with(\"a\", 1)", "`suffix`"),
        ("starts_with(\"a\", [\"a\"])", "`prefix`"),
    ] {
        let e = error(&mut i, src);
        assert!(e.contains(names), "{src}: {e}");
    }
}

#[test]
fn number_reads_what_a_literal_reads() {
    let mut i = Interpreter::new();
    for (src, want) in [
        ("number(\"3.2\")", "3.2"),
        ("\"3.2\".number()", "3.2"),
        ("number(\" -1e-3\\n\")", "-0.001"),
        ("number(\".5\")", "0.5"),
        ("number(\"250ms\") == 250ms", "true"),
        ("number(\"90deg\") == 90deg", "true"),
        ("number(\"2s\")", "2"),
        ("number(\"−2\")", "-2"),
        ("number(7)", "7"),
        // every number print writes reads back as itself
        (
            "fold(map([0.1, 1e-12, -0, 1e300, 2.5e-320], fn(x) = number(str(x)) == x), true, fn(a, x) = a && x)",
            "true",
        ),
        ("str(number(\"-0\"))", "\"-0\""),
    ] {
        assert_eq!(eval(&mut i, src), want, "{src}");
    }
    for bad in [
        "abc", "3,2", "", "  ", "1.", "nan", "inf", "1e999", "0x10", "2 s", "2sec", "--1",
    ] {
        let e = error(&mut i, &format!("number({})", quote(bad)));
        assert!(
            e.contains("`number`: `s` is")
                && e.contains("not a number")
                && e.contains("number literal"),
            "{bad:?}: {e}"
        );
    }
    let e = error(&mut i, "number([1])");
    assert!(e.contains("`s`") && e.contains("a string"), "{e}");
    // the error points at the argument
    let d = i.eval_str("let t = \"x\"\nnumber(t)").unwrap_err();
    let place = d.place().expect("a place");
    assert_eq!((place.line, place.column), (2, 8), "{place:?}");
}

/// A host value that reads a name it does not list: `Value::field` and
/// `Value::keys` go by the list alone, so field access, `keys` and `has`
/// cannot disagree even when an implementation does.
#[derive(Debug)]
struct Sloppy;

impl mx::lang::HostObject for Sloppy {
    fn type_name(&self) -> &'static str {
        "Sloppy"
    }
    fn summary(&self) -> String {
        "<sloppy>".into()
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &["listed", "absent"]
    }
    fn read_field(&self, name: &str) -> Option<mx::Value> {
        match name {
            "listed" | "unlisted" => Some(mx::Value::Number(1.0)),
            _ => None, // "absent": listed, but this value lacks it
        }
    }
}

#[test]
fn only_listed_fields_exist() {
    let v = mx::Value::object(Sloppy);
    assert_eq!(v.keys(), Some(vec!["listed".to_string()]));
    assert!(v.field("listed").is_some());
    assert!(v.field("unlisted").is_none(), "not listed: no field");
    assert!(v.field("absent").is_none());
    let mut i = Interpreter::new();
    i.set("s", v);
    assert_eq!(
        eval(
            &mut i,
            "[keys(s), has(s, \"unlisted\"), has(s, \"listed\")]"
        ),
        "[[\"listed\"], false, true]"
    );
    let e = error(&mut i, "s.unlisted");
    assert!(e.contains("a Sloppy has no field `unlisted`"), "{e}");
}
