"""mx.ground_forces: the contact forces per point and the residual as NumPy
arrays, the same numbers as mx's ground_forces and ground_residual."""

import numpy as np
import pytest

import mx
from conftest import REPO

WALK = REPO / "examples" / "data" / "walk.bvh"


def test_ground_forces_are_arrays_of_frames_by_points_by_3():
    clip = mx.load(WALK)
    body = mx.body_of(clip)
    g = mx.ground_forces(clip, body)
    t, p = len(g["times"]), len(g["points"])
    assert t == 61 and p == 2 and g["points"] == ["LeftFoot", "RightFoot"]
    assert g["forces"].shape == (t, p, 3) and g["forces"].dtype == np.float64
    assert g["in_contact"].shape == (t, p) and g["in_contact"].dtype == bool
    for key in ("residual_force", "residual_moment", "com"):
        assert g[key].shape == (t, 3)
    # a point off the floor carries nothing; every force pushes, inside its cone (y up)
    assert np.all(g["forces"][~g["in_contact"]] == 0.0)
    f = g["forces"]
    assert np.all(f[..., 1] >= -1e-6 * g["weight"])
    assert np.all(np.hypot(f[..., 0], f[..., 2]) <= 0.8 * f[..., 1] + 1e-6 * g["weight"])
    # % BW is the residual force over the weight, and ground_residual's numbers
    pct = np.linalg.norm(g["residual_force"], axis=1) / g["weight"] * 100
    np.testing.assert_allclose(g["percent_bw"], pct, rtol=1e-12)
    it = mx.Interpreter()
    it.set("w", clip)
    it.set("b", body)
    res = np.array(it.eval("ground_residual(w, b).force"))
    np.testing.assert_allclose(g["percent_bw"], res, rtol=0, atol=1e-9)
    # the mx value's DOFs, frame by frame
    mu = it.eval("ground_forces(w, b)")
    fy = mu.sample(g["times"])[:, mu.dofs.index("LeftFoot.Fy")]
    np.testing.assert_allclose(fy, g["forces"][:, 0, 1], atol=1e-9)


def test_ground_forces_bad_options_raise_naming_them():
    clip = mx.load(WALK)
    body = mx.body_of(clip)
    with pytest.raises(mx.MxValueError, match="friction"):
        mx.ground_forces(clip, body, friction=-1)
    with pytest.raises(mx.MxValueError, match="Nose"):
        mx.ground_forces(clip, body, points=["Nose"])
    with pytest.raises(mx.MxTypeError, match="floor"):
        mx.ground_forces(clip, body, floor=[1, 2])


def test_a_glb_round_trip_keeps_the_forces(tmp_path):
    """save(…, forces: true) writes ground_forces' numbers into the glTF
    file; mx.ground_forces(path) and mx.load(path, forces=True) give them
    back exactly, on the animation's frames from 0 s."""
    import json

    clip = mx.load(WALK)
    body = mx.body_of(clip)
    g = mx.ground_forces(clip, body)
    out, plain = tmp_path / "walk.glb", tmp_path / "plain.glb"
    it = mx.Interpreter()
    it.set("w", clip)
    it.set("b", body)
    it.eval(f"save(w, {json.dumps(str(out))}, body: b, forces: true)")
    it.eval(f"save(w, {json.dumps(str(plain))}, body: b)")
    back = mx.ground_forces(out)
    assert back["points"] == g["points"] and back["animation"] == "walk"
    for key in ("forces", "residual_force", "residual_moment", "percent_bw"):
        assert back[key].shape == g[key].shape
        np.testing.assert_array_equal(back[key], g[key], err_msg=key)
    np.testing.assert_allclose(back["times"], g["times"] - g["times"][0], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(back["up"], [0.0, 1.0, 0.0])
    mu = mx.load(out, forces=True)
    fy = mu.sample(back["times"])[:, mu.dofs.index("RightFoot.Fy")]
    np.testing.assert_array_equal(fy, g["forces"][:, 1, 1])
    # a file saved without forces says so, naming the file
    with pytest.raises(mx.MxIOError, match="carries no contact forces") as e:
        mx.ground_forces(plain)
    assert "plain.glb" in str(e.value)
    with pytest.raises(mx.MxTypeError, match="path"):
        mx.ground_forces(42)
