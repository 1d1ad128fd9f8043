"""mx.Motion: sampling to arrays, arrays to motions (exact round trips), the
algebra, files, pandas, and errors, on the shared BVH clips."""

import numpy as np
import pytest

import mx


def test_every_shared_clip_loads_and_samples(bvh_files):
    for path in bvh_files:
        m = mx.load(path)
        assert isinstance(m, mx.Motion) and m.type == "Mu"
        t0, t1 = m.span
        assert t1 > t0
        t = np.linspace(t0, t1, 50)
        x = m.sample(t)
        assert x.shape == (50, len(m.dofs)), path.name
        assert np.all(np.isfinite(x)), path.name
        assert m.gaps() == []


def test_array_motion_array_round_trip_is_exact():
    rng = np.random.default_rng(1)
    times = np.arange(200) / 120.0
    values = rng.normal(size=(200, 5))
    values[40:60, 2] = np.nan  # a hole in one DOF
    names = [f"d{k}" for k in range(5)]
    m = mx.Motion.from_array(names, times, values)
    assert m.dofs == names
    back = m.sample(times)
    assert back.shape == values.shape
    assert np.array_equal(np.isnan(back), np.isnan(values))
    ok = ~np.isnan(values)
    assert np.array_equal(back[ok], values[ok])  # bit for bit
    assert m.gaps() == [("d2", times[39], times[60])]
    # and back through a file, exactly
    assert m.span == (0.0, times[-1])


def test_round_trip_through_json(tmp_path):
    times = np.linspace(0, 1, 31)
    values = np.stack([np.sin(times), np.cos(times)], axis=1)
    m = mx.Motion.from_array(["a", "b"], times, values)
    p = tmp_path / "m.json"
    m.save(p)
    m2 = mx.load(p)
    assert m2 == m
    assert np.array_equal(m2.sample(times), values)
    m.save(tmp_path / "m.csv", rate=30)
    assert np.allclose(mx.load(tmp_path / "m.csv").sample(times), values, atol=1e-12)
    # without rate=, a sampled motion keeps its own frame rate ...
    m.save(tmp_path / "own.csv")
    assert np.allclose(mx.load(tmp_path / "own.csv").sample(times), values, atol=1e-12)
    # ... and one with no samples (a function of time) must be told the rate
    curve = mx.Interpreter().eval("mu({a: interval(fn(t) = sin(t), 0, 1)})")
    with pytest.raises(mx.MxTypeError, match="rate"):
        curve.save(tmp_path / "m2.csv")


def test_derivatives_and_sampling_outside():
    t = np.linspace(0, 2, 201)
    m = mx.Motion.from_array(["x"], t, (t**2)[:, None])
    mid = np.array([0.5, 1.0, 1.5])
    assert np.allclose(m.sample(mid, deriv=1)[:, 0], 2 * mid, atol=1e-6)
    assert np.allclose(m.sample(mid, deriv=2)[:, 0], 2.0, atol=1e-4)
    out = m.sample([-1.0, 3.0, 1.0])  # unsorted, outside the span
    assert np.isnan(out[0, 0]) and np.isnan(out[1, 0]) and out[2, 0] == 1.0
    assert m.sample(1.0).shape == (1,)


def test_algebra_operators_and_methods(walk_path):
    walk = mx.load(walk_path)
    t0, t1 = walk.span
    part = walk.clip_in_place(1.0, 1.5)
    hole = walk - part
    assert len(hole.gaps()) == len(walk.dofs)
    assert all(abs(g[1] - 1.0) < 1e-9 and abs(g[2] - 1.5) < 1e-9 for g in hole.gaps())
    x = hole.sample([1.2])
    assert np.all(np.isnan(x))
    back = hole + part
    assert back.gaps() == []
    assert np.array_equal(back.sample([0.5, 1.2, 2.0]), walk.sample([0.5, 1.2, 2.0]))
    both = walk & part
    assert both.span == pytest.approx((1.0, 1.5))
    with pytest.raises(mx.MxMotionError, match="conflict"):
        (walk + part).sample([1.2])
    assert (walk + part).conflicts()
    c = walk.clip(1.0, 1.5)
    assert c.span == pytest.approx((0.0, 0.5))
    s = walk.affine(2.0, 1.0)
    assert s.span == pytest.approx((t0 + 2.0, t1 + 2.0))
    cat = walk.concatenate(walk)
    assert cat.span[1] == pytest.approx(2 * (t1 - t0) + t0, abs=1e-9)
    hips = walk.only("Hips.*")
    assert hips.dofs and all(d.startswith("Hips.") for d in hips.dofs)
    assert "Hips.Xposition" in walk and len(walk) == len(walk.dofs)
    assert walk["Hips.Xposition"].type == "Dof"
    # prelude functions as methods (mx's method sugar)
    assert walk.shift(0.5).span == pytest.approx((t0 + 0.5, t1 + 0.5))
    with pytest.raises(AttributeError):
        walk.no_such_function
    with pytest.raises(mx.MxTypeError):
        walk + 1
    with pytest.raises(mx.MxMotionError, match="span"):
        walk.clip(t1 + 1, t1 + 2)


def test_to_dataframe(walk_path):
    import pandas as pd  # a test dependency (scripts/test installs it)

    walk = mx.load(walk_path).only("Hips.*")
    df = walk.to_dataframe()
    assert list(df.columns) == walk.dofs
    assert df.index.name == "t"
    assert np.array_equal(df.to_numpy(), walk.sample(df.index.to_numpy()))
    assert isinstance(df, pd.DataFrame)


def test_large_motion_converts_with_one_copy():
    rng = np.random.default_rng(3)
    t = np.arange(7200) / 120.0
    v = rng.normal(size=(7200, 60))
    m = mx.Motion.from_array([f"c{k}" for k in range(60)], t, v)
    x = m.sample(t)
    # written in place: the result is a view of the one buffer mx filled
    assert x.base is not None and x.base.size == x.size and x.flags.f_contiguous
    assert np.array_equal(x, v)


def test_from_array_errors():
    t = np.linspace(0, 1, 10)
    with pytest.raises(mx.MxValueError, match="shape"):
        mx.Motion.from_array(["a", "b"], t, np.zeros((10, 3)))
    with pytest.raises(mx.MxValueError, match="uniform grid"):
        mx.Motion.from_array(["a"], t**2, np.zeros((10, 1)))
    with pytest.raises(mx.MxValueError, match="twice"):
        mx.Motion.from_array(["a", "a"], t, np.zeros((10, 2)))
    with pytest.raises(mx.MxTypeError, match="dtype"):
        mx.Motion.from_array(["a"], t, np.zeros((10, 1), dtype=complex))
    v = np.zeros((10, 1))
    v[5, 0] = np.nan
    v[7, 0] = np.nan
    with pytest.raises(mx.MxValueError, match="isolated"):
        mx.Motion.from_array(["a"], t, v)
    m = mx.Motion.from_array(["a"], t, np.zeros((10, 1)))
    with pytest.raises(mx.MxValueError, match="deriv"):
        m.sample(t, deriv=3)
    with pytest.raises(mx.MxValueError, match="finite"):
        m.sample([0.1, np.nan])


def test_bad_files_raise(tmp_path):
    with pytest.raises(mx.MxIOError):
        mx.load(tmp_path / "missing.bvh")
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n")
    with pytest.raises(mx.MxError) as e:
        mx.load(bad)
    assert "bad.bvh" in str(e.value) or e.value.message
    with pytest.raises(mx.MxError, match="format|extension"):
        mx.load(tmp_path / "x.unknownext")


def test_html_repr(walk_path):
    walk = mx.load(walk_path)
    html = walk._repr_html_()
    assert html.startswith("<iframe") and "srcdoc" in html
    small = mx.Motion.from_array(["a"], np.linspace(0, 1, 5), np.zeros((5, 1)))
    assert "<table>" in small._repr_html_()
