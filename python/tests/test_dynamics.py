"""mx.Body: dynamics through Python against Pinocchio 4.1's numbers, batched
against per-call, shapes, dtypes and NaN input."""

import numpy as np
import pytest

import mx


def err(x, ref):
    ref = np.asarray(ref)
    return np.max(np.abs(np.asarray(x) - ref)) / max(1.0, np.max(np.abs(ref)))


def permutation(body, ref):
    """Index into the reference's joint order for each of the body's coordinates."""
    names = [j["name"] for j in ref["joints"]]
    assert sorted(body.coordinates) == sorted(names)
    return [names.index(c) for c in body.coordinates]


def stacked(ref, key, p):
    return np.array([np.asarray(s[key])[p] for s in ref["samples"]])


def test_every_reference_agrees_per_call_and_batched(references):
    assert references, "no reference files"
    for urdf, ref in references:
        body = mx.Body.from_urdf(urdf)
        assert body.nq == ref["nq"]
        assert abs(body.mass - ref["total_mass"]) < 1e-10 * max(1.0, ref["total_mass"])
        p = permutation(body, ref)
        q, v, a = (stacked(ref, k, p) for k in ("q", "v", "a"))
        tau_ref = stacked(ref, "tau", p)
        tau = body.inverse_dynamics(q, v, a)
        assert tau.shape == q.shape
        for k, s in enumerate(ref["samples"]):
            one = body.inverse_dynamics(q[k], v[k], a[k])
            assert one.shape == (body.nq,)
            assert err(one, tau_ref[k]) < 1e-10, (urdf.name, k)
            # batched against per-call: the same arithmetic
            assert np.max(np.abs(tau[k] - one)) <= 1e-12 * max(1.0, np.max(np.abs(one)))
            M_ref = np.asarray(s["M"])[np.ix_(p, p)]
            assert err(body.mass_matrix(q[k]), M_ref) < 1e-10, (urdf.name, k)
        ddq = body.forward_dynamics(q, v, tau_ref)
        M = body.mass_matrix(q)
        assert M.shape == (len(q), body.nq, body.nq)
        for k in range(len(q)):
            # conditioning-free check of ABA (README of the references)
            r = M[k] @ (ddq[k] - a[k])
            assert np.max(np.abs(r)) / max(1.0, np.max(np.abs(tau_ref[k]))) < 1e-10, (urdf.name, k)
            assert np.max(np.abs(ddq[k] - body.forward_dynamics(q[k], v[k], tau_ref[k]))) <= 1e-12 * max(
                1.0, np.max(np.abs(ddq[k]))
            )


def test_large_batch_matches_per_call(references):
    urdf, ref = next((u, r) for u, r in references if r["nq"] == 44)
    body = mx.Body.from_urdf(urdf)
    rng = np.random.default_rng(7)
    n = 2000
    q = rng.uniform(-1, 1, (n, body.nq))
    v = rng.uniform(-2, 2, (n, body.nq))
    a = rng.uniform(-5, 5, (n, body.nq))
    tau = body.inverse_dynamics(q, v, a)
    for k in range(0, n, 97):
        one = body.inverse_dynamics(q[k], v[k], a[k])
        assert np.max(np.abs(tau[k] - one)) <= 1e-12 * max(1.0, np.max(np.abs(one)))
    # gravity option: zero gravity, zero velocity and acceleration → zero torque
    z = np.zeros(body.nq)
    assert np.max(np.abs(body.inverse_dynamics(q[0], z, z, gravity=[0, 0, 0]))) == 0.0
    assert np.max(np.abs(body.inverse_dynamics(q[0], z, z))) > 1.0


def test_integer_and_list_input_is_accepted(references):
    urdf, _ = references[0]
    body = mx.Body.from_urdf(urdf)
    rng = np.random.default_rng(2)
    Q = rng.uniform(-1, 1, (body.nq, 3))  # columns: strided 1-D views
    assert np.array_equal(
        body.inverse_dynamics(Q[:, 0], Q[:, 1], Q[:, 2]),
        body.inverse_dynamics(Q[:, 0].copy(), Q[:, 1].copy(), Q[:, 2].copy()),
    )
    QT = Q.T  # a strided batch
    assert np.array_equal(
        body.inverse_dynamics(QT, QT, QT), body.inverse_dynamics(QT.copy(), QT.copy(), QT.copy())
    )
    zi = np.zeros(body.nq, dtype=np.int64)
    assert np.array_equal(body.inverse_dynamics(zi, zi, zi), body.inverse_dynamics([0.0] * body.nq, zi, zi))


def test_bad_shapes_dtypes_and_nan_raise(references):
    urdf, _ = references[0]
    body = mx.Body.from_urdf(urdf)
    n = body.nq
    z = np.zeros(n)
    with pytest.raises(mx.MxValueError, match=r"expected \(%d,\)" % n):
        body.inverse_dynamics(np.zeros(n + 1), z, z)
    with pytest.raises(ValueError, match="shape"):
        body.inverse_dynamics(np.zeros((3, n)), np.zeros((4, n)), np.zeros((3, n)))
    with pytest.raises(mx.MxValueError):
        body.mass_matrix(np.zeros((2, 2, n)))
    with pytest.raises(mx.MxTypeError, match="complex"):
        body.inverse_dynamics(z.astype(complex), z, z)
    with pytest.raises(TypeError, match="real numbers"):
        body.mass_matrix(np.array(["a"] * n))
    bad = np.zeros((5, n))
    bad[3, 2] = np.nan
    with pytest.raises(mx.MxValueError, match=r"q\[3, 2\].*NaN.*finite") as e:
        body.inverse_dynamics(bad, np.zeros((5, n)), np.zeros((5, n)))
    assert body.coordinates[2] in str(e.value)
    # one state (the path that reads the arrays in place) names the entry too
    one = np.zeros(n)
    one[2] = np.inf
    with pytest.raises(mx.MxValueError, match=r"v\[2\].*inf.*finite"):
        body.inverse_dynamics(z, one, z)
    with pytest.raises(mx.MxValueError, match=r"tau\[2\].*inf.*finite"):
        body.forward_dynamics(z, z, one)
    with pytest.raises(mx.MxValueError, match="gravity"):
        body.inverse_dynamics(z, z, z, gravity=[0, 1])


def test_bad_urdf_raises_io_error(tmp_path):
    p = tmp_path / "broken.urdf"
    p.write_text("<robot name='x'><link name='a'/><joint")
    with pytest.raises(mx.MxIOError):
        mx.Body.from_urdf(p)
    with pytest.raises(OSError):
        mx.Body.from_urdf(tmp_path / "missing.urdf")
    with pytest.raises(mx.MxValueError, match="not a .urdf"):
        mx.Body.from_urdf(tmp_path / "x.txt")


def test_body_from_clip_positions_and_repr(walk_path):
    clip = mx.load(walk_path)
    body = mx.body_of(clip)
    assert isinstance(body, mx.Body)
    assert set(body.coordinates) <= set(clip.dofs)
    p = body.positions(clip)
    T, J = len(p["times"]), len(p["joints"])
    assert p["xyz"].shape == (T, J, 3) and J > 10
    assert p["parents"][0] is None
    # the same numbers as mx's own positions(m, body)
    i = mx.Interpreter()
    i.set("clip", clip)
    i.set("body", body)
    pm = i.eval("positions(clip, body)")
    for j in (0, J // 2, J - 1):
        name = p["joints"][j]
        cols = pm.only(f"{name}.x", f"{name}.y", f"{name}.z").sample(p["times"])
        assert np.max(np.abs(cols - p["xyz"][:, j])) < 1e-12, name
    assert np.max(np.ptp(p["xyz"][:, :, 0], axis=0)) > 0.1  # the figure moves
    assert "<table>" in body._repr_html_() and repr(body).startswith("Body")
    # dynamics on the clip's own states
    t = p["times"][:50]
    q, v, a = (clip.only(*body.coordinates).sample(t, deriv=k) for k in range(3))
    order = [clip.only(*body.coordinates).dofs.index(c) for c in body.coordinates]
    tau = body.inverse_dynamics(q[:, order], v[:, order], a[:, order])
    assert tau.shape == (50, body.nq) and np.all(np.isfinite(tau))
