"""mx.Interpreter: evaluation, globals both ways, Python callbacks, limits,
file root, errors as exceptions with their diagnostics, and SP with Ctrl-C."""

import _thread
import re
import threading
import time

import numpy as np
import pytest

import mx

from conftest import REPO


def test_eval_keeps_globals_and_converts_values():
    i = mx.Interpreter()
    assert i.eval("1 + 2 * 3") == 7.0
    assert i.eval("let xs = [1, 2, 3]") is None
    assert i.get("xs") == [1.0, 2.0, 3.0]
    assert i.eval('{a: 1, "b c": [true, "s"], n: nil}') == {"a": 1.0, "b c": [True, "s"], "n": None}
    i.set("k", 4)
    i.set("r", {"x": [1.5, False], "name": "walk"})
    i["arr"] = np.array([1.0, 2.0])
    assert i.eval("k * 2 + r.x[0] + sum(arr)") == 12.5
    assert i.eval("r.name + str(r.x[1])") == "walkfalse"
    assert "k" in i and "nothere" not in i
    with pytest.raises(KeyError):
        i.get("nothere")
    f = i.eval("fn(x, y = 1) = x * 10 + y")
    assert isinstance(f, mx.Function)
    assert f(2) == 21.0 and f(2, y=5) == 25.0
    with pytest.raises(mx.MxTypeError):
        i.set("bad", object())
    with pytest.raises(mx.MxTypeError, match="string keys"):
        i.set("bad", {1: 2})


def test_print_goes_to_python_stdout(capsys):
    mx.Interpreter().eval('print("hello", 1e-12)')
    assert capsys.readouterr().out == "hello 1e-12\n"


def test_motions_and_bodies_cross_the_boundary(walk_path):
    i = mx.Interpreter()
    walk = mx.load(walk_path)
    i.set("walk", walk)
    hips = i.eval('walk.only("Hips.*")')
    assert isinstance(hips, mx.Motion)
    assert hips == walk.only("Hips.*")
    b = i.eval("body_of(walk)")
    assert isinstance(b, mx.Body) and b.nq > 0
    j = i.eval("revolute([0, 0, 1])")
    assert isinstance(j, mx.Object) and j.type == "Joint"
    # the fields are mx's keys(j): what j.name reads, listed by keys() and dir()
    assert j.keys() == i.eval("keys(revolute([0, 0, 1]))") == ["kind", "dof"]
    assert j.kind == "revolute" and j.dof == 1 and "kind" in dir(j)


def test_register_python_function():
    i = mx.Interpreter()

    def twice(x):
        """Double x."""
        return 2 * x

    i.register("twice", twice)
    assert i.eval("twice(21)") == 42.0
    assert "Double x." in i.help("twice")
    i.register("kw", lambda a, scale=1.0: [a, scale], "a and scale")
    assert i.eval("kw(1, scale: 3)") == [1.0, 3.0]
    i.register("arr", lambda n: np.arange(n) * 0.5)
    assert i.eval("sum(arr(4))") == 3.0
    with pytest.raises(mx.MxTypeError):
        i.register("nope", 3)


def test_callback_that_raises_becomes_an_mx_error_with_its_cause():
    i = mx.Interpreter()

    def boom(x):
        raise ValueError(f"bad x {x}")

    i.register("boom", boom)
    i.eval("let y = 1")
    with pytest.raises(mx.MxError) as e:
        i.eval("let z = 0\nboom(y + 1)")
    assert "ValueError: bad x 2.0" in str(e.value)
    assert isinstance(e.value.__cause__, ValueError)
    assert e.value.line == 2 and e.value.file == "<input>"
    # the interpreter survives
    assert i.eval("y + 1") == 2.0


def test_syntax_and_name_errors_carry_the_diagnostic():
    i = mx.Interpreter()
    with pytest.raises(mx.MxSyntaxError) as e:
        i.eval("let x = (1 +", name="script.mx")
    assert e.value.file == "script.mx" and e.value.line == 1 and e.value.column is not None
    assert "script.mx" in str(e.value)
    i.eval("let walk = 1")
    with pytest.raises(mx.MxNameError) as e:
        i.eval("wolk + 1")
    assert "walk" in (e.value.help or "") and isinstance(e.value, NameError)
    with pytest.raises(mx.MxValueError, match="division by zero"):
        i.eval("1 / 0")
    with pytest.raises(mx.MxTypeError) as e:
        i.eval('sin("x")')
    assert e.value.kind == "type" and "sin" in e.value.message


def test_step_budget_and_file_root(tmp_path):
    i = mx.Interpreter(steps=10_000, max_depth=1_000_000)
    with pytest.raises(mx.MxLimitError):
        i.eval("fn f(n) = f(n + 1)\nf(0)")
    (tmp_path / "s.mx").write_text('let m = mu({"x": interval(1, 0s, 1s)})\nsave(m, "m.json")\n42\n')
    j = mx.Interpreter(root=tmp_path)
    assert j.run(tmp_path / "s.mx") == 42.0
    assert (tmp_path / "m.json").exists()
    with pytest.raises(mx.MxError, match="outside|root"):
        j.eval('load("../elsewhere.json")')
    with pytest.raises(mx.MxIOError):
        j.run(tmp_path / "missing.mx")


def test_eval_is_interruptible():
    i = mx.Interpreter()
    threading.Timer(0.3, _thread.interrupt_main).start()
    t = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        i.eval("sum(map(range(20000), fn(i) = sum(map(range(20000), fn(j) = i * j))))")
    assert time.monotonic() - t < 10
    assert i.eval("1 + 1") == 2.0


def _arm_gap(walk_path):
    walk = mx.load(walk_path)
    arm = walk.only("UpperArm_R.*", "LowerArm_R.*")
    return walk - arm.clip_in_place(1.0, 1.4), mx.body_of(walk)


def test_sp_fills_the_gap_and_reports(walk_path):
    holed, body = _arm_gap(walk_path)
    assert holed.gaps()
    filled, report = mx.sp(holed, body, progress=False)
    assert isinstance(filled, mx.Motion) and filled.gaps() == []
    assert isinstance(report, dict) and report["groups"] and "text" in report
    g = report["groups"][0]
    assert g["energy"] <= g["initial_energy"]
    assert np.all(np.isfinite(filled.sample(np.linspace(1.0, 1.4, 9))))
    assert "SP(" in mx.sp.__doc__  # mx's :help text
    assert "body_of(clip" in mx.body_of.__doc__ and mx.help_text("sin").startswith("sin(x)")
    with pytest.raises(mx.MxTypeError):
        mx.sp(holed, body, no_such_option=1)


def _report_fields():
    """The field names of `sp_report(m)`, read from the report's own table in
    the Rust source (src/lang/host/sp_report.rs), not from the bindings."""
    src = (REPO / "src" / "lang" / "host" / "sp_report.rs").read_text()
    table = src[src.index("const TABLE"):]
    table = table[: table.index("];")]
    names = re.findall(r'^\s*\("(\w+)",', table, re.M)
    assert len(names) >= 8, f"no field list found in sp_report.rs: {names}"
    return names


def test_sp_report_dict_has_every_field_of_sp_report(walk_path):
    holed, body = _arm_gap(walk_path)
    _, report = mx.sp(holed, body, progress=False)
    fields = _report_fields()
    assert "constant" in fields and "contacts" in fields
    assert list(report) == fields, "mx.sp's report has exactly sp_report's fields, in its order"
    # and each holds what mx's own sp_report(m).field holds
    i = mx.Interpreter()
    i["h"], i["b"] = holed, body
    i.eval("let r = sp_report(SP(h, body: b))")
    for f in fields:
        if f == "groups":  # seconds and evaluation counts differ between two solves
            assert [g["dofs"] for g in report[f]] == [g["dofs"] for g in i.eval(f"r.{f}")]
        elif f == "text":  # ends in the solve's milliseconds
            assert report[f].split(":")[0] == i.eval(f"r.{f}").split(":")[0]
        else:
            assert report[f] == i.eval(f"r.{f}"), f


def test_keyboard_interrupt_cancels_sp(walk_path):
    walk = mx.load(walk_path)
    holed = walk - walk.clip_in_place(0.5, 2.5)
    body = mx.body_of(walk)
    threading.Timer(1.0, _thread.interrupt_main).start()
    t = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        # Rose's objective alone at 20 coefficients runs long (the default converges in a blink)
        mx.sp(holed, body, objective="torque", coefficients=20, iterations=100000, tolerance=1e-12, progress=False)
    assert time.monotonic() - t < 30
    # nothing is left cancelled: the next call works
    assert mx.Interpreter().eval("2") == 2.0


def test_an_errors_place_is_data():
    # a name with colons and " (", which a rendered `file:line:col` cannot
    # carry unambiguously, and a non-ASCII character before the error
    name = "C:/takes (draft):2.mx"
    src = 'let s = "é—"\nlet x = 1 + "two"'
    with pytest.raises(mx.MxError) as e:
        mx.Interpreter().eval(src, name=name)
    err = e.value
    assert err.file == name and err.line == 2 and err.end_line == 2
    start, end = err.span
    bad = src[start:end]
    assert '"two"' in bad, bad
    line2 = src.split("\n")[1]
    assert err.column == line2.index(bad) + 1
    assert err.end_column == err.column + len(bad)
    # an error about values given from Python has no place
    with pytest.raises(mx.MxError) as e:
        mx.Motion.from_array(["a", "b"], [0.0, 1.0], [[1.0], [2.0]])
    assert e.value.span is None and e.value.line is None
