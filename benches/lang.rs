//! Language benchmarks (not timed tests):
//! - parse a 5,000-line script;
//! - evaluate a composite motion expression over a 60-DOF, 60 s motion and
//!   sample it at 120 Hz, for sampled-data DOFs (like motion capture) and for
//!   DOFs defined by mx functions of time (interpreted on every sample).
//!
//! Run with `cargo bench --bench lang`.

use divan::Bencher;
use mx::Interpreter;
use mx::lang::builtins::motion::as_mu;
use mx::lang::parser::parse_program;

fn main() {
    divan::main();
}

/// A 5,000-line script mixing every statement form.
fn script_5000_lines() -> String {
    let mut s = String::new();
    for i in 0..1000 {
        s.push_str(&format!(
            "let a{i} = {{x: [1, 2.5, 250ms], \"Hips.X{i}\": 90deg}}\n"
        ));
        s.push_str(&format!(
            "fn f{i}(t, k = 2) = if t < 1 {{ k * sin(2 * pi * t) }} else {{ -t / 3 + k }}\n"
        ));
        s.push_str(&format!("let m{i} = mu({{x: interval(f{i}, 0s, 2s)}}).only(\"x\") + shift(mu({{x: interval(1, 0, 1)}}), 2)\n"));
        s.push_str("// a comment line\n");
        s.push_str(&format!(
            "print(a{i}.x[1] * 3 - 1 >= 2 && true, map(range(3), fn(j) = j * {i}))\n"
        ));
    }
    s
}

#[divan::bench]
fn parse_5000_line_script(b: Bencher) {
    let src = script_5000_lines();
    assert_eq!(src.lines().count(), 5000);
    b.bench(|| {
        parse_program(divan::black_box(&src), 0)
            .map(|p| p.stmts.len())
            .unwrap_or(0)
    });
}

const DOFS: usize = 60;
const RATE: f64 = 120.0;

/// An interpreter holding `walk` and `dance`, 60-DOF motions over 60 s.
fn setup(sampled: bool) -> Interpreter {
    let mut mx = Interpreter::new();
    mx.capture_output();
    let def = if sampled {
        // 120 Hz data, as from motion capture.
        "fn dof_curve(i) = samples(map(range(7201), fn(k) = sin(k / 120 * (1 + i / 10))), 120)"
    } else {
        "fn dof_curve(i) = interval(fn(t) = sin(t * (1 + i / 10)), 0s, 60s)"
    };
    let src = format!(
        "{def}\n\
         let names = map(range({DOFS}), fn(i) = \"Joint\" + str(i) + \".Zrotation\")\n\
         let walk = mu(fold(range({DOFS}), {{}}, fn(r, i) = with(r, names[i], dof_curve(i))))\n\
         let dance = shift(walk, 0.5)"
    );
    if let Err(d) = mx.eval_str(&src) {
        panic!("{}", d.render_plain());
    }
    mx
}

/// walk with 20–30 s replaced by a slowed-down piece of dance, cut at 40 s
/// and followed by the end of dance, minus its last second: every operation
/// of the algebra on all 60 DOFs.
const COMPOSITE: &str = "let hole = walk - clip_in_place(20s, 30s, walk)\n\
     let piece = affine(20s, 2, clip(10s, 15s, dance))\n\
     let c = hole + piece\n\
     concatenate(clip(0s, 40s, c), clip(40s, 60s, dance)) - clip_in_place(59s, 60s, walk)";

fn composite_and_sample(b: Bencher, sampled: bool) {
    let mut mx = setup(sampled);
    b.bench_local(|| {
        let v = mx.eval_str(COMPOSITE).expect("composite evaluates");
        let mu = as_mu(&v).expect("a Mu");
        let grid = mx::motion::sample_grid(mu, RATE, None).expect("samples");
        assert_eq!(grid.names.len(), DOFS);
        grid.times.len()
    });
}

#[divan::bench(sample_count = 10)]
fn composite_60dof_60s_at_120hz_sampled_data(b: Bencher) {
    composite_and_sample(b, true);
}

#[divan::bench(sample_count = 5)]
fn composite_60dof_60s_at_120hz_mx_functions(b: Bencher) {
    composite_and_sample(b, false);
}

/// The small helpers the prelude may define in mx (`clamp`, `lerp`, `sign`,
/// `zip`, `values`), called 20,000 times each from an mx loop: what moving
/// them from Rust to mx costs a script that leans on them.
#[divan::bench(sample_count = 10)]
fn prelude_helpers_20000_calls(b: Bencher) {
    let mut mx = Interpreter::new();
    mx.capture_output();
    let src = "let r = {a: 1, b: 2, c: 3}\n\
               fold(range(20000), 0, fn(acc, i) = acc + clamp(lerp(-1, 2, i / 20000), 0, 1) \
               + sign(i - 10000) + len(zip([i, 1], [2, 3])) + len(values(r)))";
    b.bench_local(|| {
        let v = mx.eval_str(src).expect("the helpers evaluate");
        v.as_number().expect("a number")
    });
}
