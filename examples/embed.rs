//! Embedding mx in a Rust program: evaluate source, read values back,
//! register a host function, limit the work a script may do and confine its
//! file access to one folder.
//!
//! Run with `cargo run --example embed`.

use mx::lang::{ErrorKind, MxError};
use mx::{Interpreter, Value};

fn main() {
    let mut mx = Interpreter::new();

    // A host function: one line to register, arguments by name with checked types.
    mx.register(
        "scale_all(xs, k)",
        "Multiply every number of xs by k.",
        |a, _| {
            let xs = a.list_of_numbers("xs")?;
            let k = a.number("k")?;
            Ok(Value::list(
                xs.into_iter().map(|x| Value::Number(x * k)).collect(),
            ))
        },
    );
    mx.register(
        "host_fail()",
        "Always fails (shows errors from the host).",
        |a, _| {
            Err(MxError::host("the host refused")
                .at(a.call_span())
                .help("nothing to do, it is a demo"))
        },
    );

    // Evaluate, keep bindings, read values back.
    mx.eval_str("let base = [1, 2, 3]\nfn twice(x) = 2 * x")
        .expect("valid source");
    let v = mx.eval_str("scale_all(base, 10).map(twice)").expect("runs");
    println!("scale_all(base, 10).map(twice) = {}", v.repr());
    let nums: Vec<f64> = v
        .as_list()
        .unwrap_or(&[])
        .iter()
        .filter_map(Value::as_number)
        .collect();
    assert_eq!(nums, vec![20.0, 40.0, 60.0]);
    println!("base = {:?}", mx.get("base").map(|v| v.repr()));

    // Call an mx function from Rust.
    let twice = mx.get("twice").expect("defined above");
    let r = mx
        .call(&twice, vec![Value::Number(21.0)])
        .expect("callable");
    println!("twice(21) = {}", r.repr());

    // Errors come back as diagnostics with the source and span.
    if let Err(d) = mx.eval_str("host_fail()") {
        eprint!("{}", d.render_plain());
    }

    // A step budget stops runaway scripts with a clear error.
    mx.set_step_budget(Some(100_000));
    mx.set_max_depth(1_000_000);
    match mx.eval_str("fn forever(n) = forever(n + 1)\nforever(0)") {
        Err(d) if d.kind() == ErrorKind::StepBudget => {
            println!("runaway script stopped: {}", d.error().message)
        }
        other => println!("unexpected: {:?}", other.map(|v| v.repr())),
    }
    mx.set_step_budget(None);

    // Confine load/save to one folder.
    let root = std::env::temp_dir().join("mx-embed-example");
    mx.set_file_root(Some(root.clone()));
    mx.eval_str("save(mu({x: interval(fn(t) = t * t, 0, 1)}), \"motion.json\")")
        .expect("inside the root");
    println!("wrote {}", root.join("motion.json").display());
    match mx.eval_str("save(mu({x: interval(1, 0, 1)}), \"../escape.json\")") {
        Err(d) => println!("refused: {}", d.error().message),
        Ok(_) => println!("unexpected: write outside the root succeeded"),
    }
}
