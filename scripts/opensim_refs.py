#!/usr/bin/env python3
"""OpenSim reference data for mx's .osim reader (issue 19).

Run by hand (cargo test only reads what this writes):

    python3 -m venv /tmp/osim-venv && /tmp/osim-venv/bin/pip install opensim mpmath   # 4.6, CPython 3.11
    /tmp/osim-venv/bin/python scripts/opensim_refs.py [--shared /work/shared]
    /tmp/osim-venv/bin/python scripts/opensim_refs.py --timing      # load + ID per state, OpenSim beside mx
    /tmp/osim-venv/bin/python scripts/opensim_refs.py --check-mot X.mot   # OpenSim reads a .mot mx wrote

Writes
  tests/data/opensim/<stem>.json          for every .osim in $MX_SHARED/data/opensim
  tests/data/opensim/joints/<type>.osim   a small model per joint type, built with OpenSim's API
  tests/data/opensim/joints/<type>.json   its references
  tests/data/opensim/couplers/<name>.osim  models with CoordinateCouplerConstraints
  tests/data/opensim/couplers/<name>.json  their references in the independent coordinates
  tests/data/opensim/functions/gcvspline.json  GCVSpline values and derivatives
  tests/data/opensim/mot/opensim_written.mot  a Storage file written by OpenSim, with the values
  tests/data/opensim/mot/opensim_written.json

Every reference is per state, in the model's CoordinateSet order (the order
mx gives the coordinates): q, qdot (= N u), u, N (qdot = N u, so mx's M_q and
tau_q relate by M_u = N^T M_q N, tau_u = N^T tau_q), M_u (calcM), udot_fd and
qdotdot_fd (forward dynamics with no applied force: every force is disabled,
gravity acts), udot (random) and tau_u (InverseDynamicsSolver at udot), and the
ground pose of every body. Also timings: model load + initSystem, and
InverseDynamicsSolver.solve per state, so mx's timings can be quoted as ratios.
"""
import argparse
import json
import os
import sys
import time

import numpy as np
import opensim as osim

osim.Logger.removeFileSink()  # no opensim.log in the working folder

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "tests", "data", "opensim")


def vec(v):
    return [v.get(i) for i in range(v.size())]


def mat(m):
    return [[m.get(i, j) for j in range(m.ncol())] for i in range(m.nrow())]


def disable_forces(model):
    fs = model.getForceSet()
    for i in range(fs.getSize()):
        fs.get(i).set_appliesForce(False)


def index_maps(model, state):
    """For each coordinate (CoordinateSet order), its index in state Q and U."""
    cs = model.getCoordinateSet()
    n = cs.getSize()
    qi, ui = [], []
    for k in range(n):
        c = cs.get(k)
        q0 = np.array(vec(state.getQ()))
        v = c.getValue(state)
        c.setValue(state, v + 0.123, False)
        q1 = np.array(vec(state.getQ()))
        c.setValue(state, v, False)
        d = np.nonzero(np.abs(q1 - q0) > 1e-12)[0]
        assert len(d) == 1, (c.getName(), d)
        qi.append(int(d[0]))
        u0 = np.array(vec(state.getU()))
        s = c.getSpeedValue(state)
        c.setSpeedValue(state, s + 0.5)
        u1 = np.array(vec(state.getU()))
        c.setSpeedValue(state, s)
        d = np.nonzero(np.abs(u1 - u0) > 1e-12)[0]
        assert len(d) == 1, (c.getName(), d)
        ui.append(int(d[0]))
    return qi, ui


def random_state(model, state, rng):
    cs = model.getCoordinateSet()
    q, u = [], []
    for k in range(cs.getSize()):
        c = cs.get(k)
        lo, hi = c.getRangeMin(), c.getRangeMax()
        if c.getMotionType() == osim.Coordinate.Rotational:
            lo, hi = max(lo, -1.2), min(hi, 1.2)
        else:
            lo, hi = max(lo, -0.5), min(hi, 0.5)
        if not lo < hi:
            lo, hi = -0.5, 0.5
        q.append(float(rng.uniform(lo, hi)))
        u.append(float(rng.uniform(-2.0, 2.0)))
    return q, u


def references(model, nstates, seed):
    disable_forces(model)
    t0 = time.perf_counter()
    state = model.initSystem()
    init_s = time.perf_counter() - t0
    cs = model.getCoordinateSet()
    n = cs.getSize()
    names = [cs.get(k).getName() for k in range(n)]
    qi, ui = index_maps(model, state)
    matter = model.getMatterSubsystem()
    idsolver = osim.InverseDynamicsSolver(model)
    rng = np.random.default_rng(seed)
    bodies = [b.getName() for b in model.getBodySet()]
    states = []
    id_times = []
    for _ in range(nstates):
        q, u = random_state(model, state, rng)
        Q = osim.Vector(state.getNQ(), 0.0)
        U = osim.Vector(state.getNU(), 0.0)
        for k in range(n):
            Q.set(qi[k], q[k])
            U.set(ui[k], u[k])
        state.setQ(Q)
        state.setU(U)
        model.realizeAcceleration(state)
        qd = vec(state.getQDot())
        qdd = vec(state.getQDotDot())
        ud = vec(state.getUDot())
        # N: qdot = N u, columns from unit speeds
        N = np.zeros((n, n))
        for k in range(n):
            e = osim.Vector(state.getNU(), 0.0)
            e.set(ui[k], 1.0)
            out = osim.Vector(state.getNQ(), 0.0)
            matter.multiplyByN(state, False, e, out)
            for i in range(n):
                N[i, k] = out.get(qi[i])
        M = osim.Matrix()
        matter.calcM(state, M)
        Mm = mat(M)
        udot = [float(x) for x in rng.uniform(-3.0, 3.0, n)]
        UD = osim.Vector(state.getNU(), 0.0)
        for k in range(n):
            UD.set(ui[k], udot[k])
        t1 = time.perf_counter()
        tau = idsolver.solve(state, UD)
        id_times.append(time.perf_counter() - t1)
        poses = {}
        for b in model.getBodySet():
            X = b.getTransformInGround(state)
            R = X.R()
            poses[b.getName()] = {
                "R": [[R.get(i, j) for j in range(3)] for i in range(3)],
                "p": [X.p().get(i) for i in range(3)],
            }
        states.append({
            "q": q,
            "u": u,
            "qdot": [qd[qi[k]] for k in range(n)],
            "N": N.tolist(),
            "M_u": [[Mm[ui[i]][ui[j]] for j in range(n)] for i in range(n)],
            "udot_fd": [ud[ui[k]] for k in range(n)],
            "qdotdot_fd": [qdd[qi[k]] for k in range(n)],
            "udot": udot,
            "tau_u": [tau.get(ui[k]) for k in range(n)],
            "body_in_ground": poses,
        })
    # ID per state, timed again over many calls (steady state)
    reps = 200
    t1 = time.perf_counter()
    for _ in range(reps):
        idsolver.solve(state, UD)
    id_per_state = (time.perf_counter() - t1) / reps
    g = model.getGravity()
    return {
        "generator": "scripts/opensim_refs.py",
        "opensim_version": osim.__version__,
        "coordinates": names,
        "motion_types": [{1: "rotational", 2: "translational", 3: "coupled"}[cs.get(k).getMotionType()]
                         for k in range(n)],
        "bodies": bodies,
        "gravity": [g.get(0), g.get(1), g.get(2)],
        "forces_disabled": True,
        "timing_s": {"init_system": init_s, "inverse_dynamics_per_state": id_per_state},
        "states": states,
    }


def timed_load(path):
    t0 = time.perf_counter()
    m = osim.Model(path)
    m.initSystem()
    return time.perf_counter() - t0


# ---- small per-joint models ----

def inertia_body(name, mass, com, I):
    return osim.Body(name, mass, osim.Vec3(*com), osim.Inertia(*I))


def custom_transform():
    """Coordinates a, b, c with linear functions; `custom_axes_xml` then gives
    them every function type (OpenSim's Python wrapper crashes when a
    SpatialTransform's axes get functions built in Python, so the functions are
    written into the printed model, which OpenSim then loads and checks)."""
    st = osim.SpatialTransform()
    for upd, coord in [(st.upd_rotation1, "a"), (st.upd_translation1, "b"), (st.upd_translation3, "c")]:
        upd().setCoordinateNames(osim.ArrayStr(coord, 1))
        upd().set_function(osim.LinearFunction(1, 0))
    return st


CUSTOM_AXES = [
    ("rotation1", "a", "0 0 1",
     "<SimmSpline name=\"function\"><x>-1.5 -0.7 0 0.6 1.5</x><y>-1.2 -0.5 0.1 0.5 1.3</y></SimmSpline>"),
    ("rotation2", "b", "1 0 0",
     "<PolynomialFunction name=\"function\"><coefficients>0.1 -0.2 0.9 0.05</coefficients></PolynomialFunction>"),
    ("rotation3", "c", "0 1 0",
     "<MultiplierFunction name=\"function\"><function><LinearFunction><coefficients>1 0</coefficients>"
     "</LinearFunction></function><scale>0.3</scale></MultiplierFunction>"),
    ("translation1", "b", "1 0 0",
     "<PiecewiseLinearFunction name=\"function\"><x>-1.5 -0.2 0.4 1.5</x><y>-0.05 0.01 0.03 0.08</y>"
     "</PiecewiseLinearFunction>"),
    ("translation2", "", "0 1 0", "<Constant name=\"function\"><value>-0.02</value></Constant>"),
    ("translation3", "c", "0.2 0.1 1", "<LinearFunction name=\"function\"><coefficients>0.5 0.01</coefficients></LinearFunction>"),
]


def custom_axes_xml(path, shared_rotation=False):
    """shared_rotation: rotation3 reads `a` as rotation1 does. Simbody's
    FunctionBased mobilizer then gets velocity terms that disagree with the
    Lagrangian of its own mass matrix (see `lagrange_bias`), so that model's
    reference carries the Lagrangian velocity terms instead."""
    import re
    text = open(path).read()
    axes = "".join(
        f"<TransformAxis name=\"{n}\"><coordinates>{'a' if shared_rotation and n == 'rotation3' else c}"
        f"</coordinates><axis>{a}</axis>{f}</TransformAxis>"
        for n, c, a, f in CUSTOM_AXES)
    text, k = re.subn(r"<SpatialTransform>.*?</SpatialTransform>",
                      f"<SpatialTransform>{axes}</SpatialTransform>", text, flags=re.S)
    assert k == 1
    with open(path, "w") as f:
        f.write(text)


def joint_model(kind):
    kind = "CustomJoint" if kind.startswith("CustomJoint") else kind
    m = osim.Model()
    m.setName(f"{kind}_model")
    a = inertia_body("a", 2.3, (0.05, -0.21, 0.03), (0.041, 0.012, 0.037, 0.002, -0.003, 0.001))
    b = inertia_body("b", 1.1, (0.01, -0.15, -0.02), (0.011, 0.004, 0.013, -0.001, 0.0005, 0.0007))
    m.addBody(a)
    m.addBody(b)
    lp, op = osim.Vec3(0.1, 0.9, -0.05), osim.Vec3(0.2, -0.3, 0.1)
    lc, oc = osim.Vec3(0.02, 0.15, 0.01), osim.Vec3(-0.1, 0.25, 0.05)
    g = m.getGround()
    if kind == "CustomJoint":
        j = osim.CustomJoint("j", g, lp, op, a, lc, oc, custom_transform())
    else:
        cls = getattr(osim, kind)
        j = cls("j", g, lp, op, a, lc, oc)
    m.addJoint(j)
    pin = osim.PinJoint("pin", a, osim.Vec3(0.0, -0.4, 0.02), osim.Vec3(0.1, 0.0, 0.3),
                        b, osim.Vec3(0.0, 0.05, 0.0), osim.Vec3(0.0, 0.2, 0.0))
    m.addJoint(pin)
    for k in range(j.numCoordinates()):
        c = j.upd_coordinates(k)
        if c.getMotionType() == osim.Coordinate.Rotational:
            c.setRangeMin(-1.0)
            c.setRangeMax(1.0)
        else:
            c.setRangeMin(-0.3)
            c.setRangeMax(0.3)
    m.finalizeConnections()
    return m


JOINTS = ["PinJoint", "SliderJoint", "WeldJoint", "BallJoint", "FreeJoint", "UniversalJoint",
          "GimbalJoint", "PlanarJoint", "CustomJoint", "CustomJointSharedRotation"]


def lagrange_bias(model, ref, h=1e-5):
    """Velocity terms C(q, u) u = Mdot u - 1/2 d(u^T M u)/dq from central
    differences of OpenSim's calcM (u = qdot here), per state, beside
    OpenSim's own (InverseDynamicsSolver at udot = 0, gravity removed)."""
    state = model.initSystem()
    matter = model.getMatterSubsystem()
    idsolver = osim.InverseDynamicsSolver(model)
    n = len(ref["coordinates"])
    qi, ui = index_maps(model, state)
    assert qi == list(range(n)) and ui == list(range(n))

    def setq(q, u):
        state.setQ(osim.Vector(list(q)))
        state.setU(osim.Vector(list(u)))
        model.realizeVelocity(state)

    def M(q):
        setq(q, [0.0] * n)
        Mm = osim.Matrix()
        matter.calcM(state, Mm)
        return np.array(mat(Mm))

    def ID(q, u):
        setq(q, u)
        return np.array(vec(idsolver.solve(state, osim.Vector(n, 0.0))))

    for st in ref["states"]:
        q, u = np.array(st["q"]), np.array(st["u"])
        dM = [(M(q + h * e) - M(q - h * e)) / (2 * h) for e in np.eye(n)]
        mdot = sum(dM[k] * u[k] for k in range(n))
        lag = mdot @ u - 0.5 * np.array([u @ dM[k] @ u for k in range(n)])
        st["bias_lagrange_from_calcM"] = lag.tolist()
        st["bias_opensim"] = (ID(q, u) - ID(q, np.zeros(n))).tolist()


V3_MODEL = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="30000">
  <Model name="v3_model">
    <gravity>0 -9.80665 0</gravity>
    <BodySet><objects>
      <Body name="ground"><mass>0</mass><mass_center>0 0 0</mass_center>
        <inertia_xx>0</inertia_xx><inertia_yy>0</inertia_yy><inertia_zz>0</inertia_zz>
        <inertia_xy>0</inertia_xy><inertia_xz>0</inertia_xz><inertia_yz>0</inertia_yz><Joint/></Body>
      <Body name="thigh"><mass>7.5</mass><mass_center>0.01 -0.17 0.005</mass_center>
        <inertia_xx>0.11</inertia_xx><inertia_yy>0.03</inertia_yy><inertia_zz>0.12</inertia_zz>
        <inertia_xy>0.002</inertia_xy><inertia_xz>-0.001</inertia_xz><inertia_yz>0.003</inertia_yz>
        <Joint><PinJoint name="hip">
          <parent_body>ground</parent_body>
          <location_in_parent>0.05 0.9 -0.02</location_in_parent>
          <orientation_in_parent>0.1 -0.2 0.3</orientation_in_parent>
          <location>0.01 0.02 0</location><orientation>0 0.15 -0.1</orientation>
          <CoordinateSet><objects><Coordinate name="hip_flexion">
            <motion_type>rotational</motion_type><default_value>0</default_value>
            <range>-1.2 1.2</range><clamped>false</clamped><locked>false</locked>
          </Coordinate></objects></CoordinateSet>
          <reverse>false</reverse>
        </PinJoint></Joint></Body>
      <Body name="shank"><mass>3.2</mass><mass_center>0 -0.19 0.01</mass_center>
        <inertia_xx>0.05</inertia_xx><inertia_yy>0.006</inertia_yy><inertia_zz>0.051</inertia_zz>
        <inertia_xy>0.001</inertia_xy><inertia_xz>0</inertia_xz><inertia_yz>-0.0005</inertia_yz>
        <Joint><CustomJoint name="knee">
          <parent_body>thigh</parent_body>
          <location_in_parent>0 -0.4 0.01</location_in_parent>
          <orientation_in_parent>0 0 0.05</orientation_in_parent>
          <location>0 0 0</location><orientation>0 0 0</orientation>
          <CoordinateSet><objects>
            <Coordinate name="knee_angle"><motion_type>rotational</motion_type><default_value>0</default_value>
              <range>-2 0.2</range><clamped>true</clamped><locked>false</locked></Coordinate>
            <Coordinate name="knee_add"><motion_type>rotational</motion_type><default_value>0</default_value>
              <range>-0.3 0.3</range><clamped>false</clamped><locked>false</locked></Coordinate>
          </objects></CoordinateSet>
          <reverse>false</reverse>
          <SpatialTransform>
            <TransformAxis name="rotation1"><function><LinearFunction><coefficients>1 0</coefficients></LinearFunction></function>
              <coordinates>knee_angle</coordinates><axis>0 0 1</axis></TransformAxis>
            <TransformAxis name="rotation2"><function><LinearFunction><coefficients>1 0</coefficients></LinearFunction></function>
              <coordinates>knee_add</coordinates><axis>1 0 0</axis></TransformAxis>
            <TransformAxis name="rotation3"><function><Constant><value>0</value></Constant></function>
              <coordinates></coordinates><axis>0 1 0</axis></TransformAxis>
            <TransformAxis name="translation1"><function><SimmSpline><x>-2.1 -1.2 -0.5 0 0.3</x>
              <y>-0.0032 0.00179 0.00411 -0.0045 -0.0052</y></SimmSpline></function>
              <coordinates>knee_angle</coordinates><axis>1 0 0</axis></TransformAxis>
            <TransformAxis name="translation2"><function><SimmSpline><x>-2.1 -1.2 -0.5 0 0.3</x>
              <y>-0.4226 -0.4082 -0.399 -0.3958 -0.3952</y></SimmSpline></function>
              <coordinates>knee_angle</coordinates><axis>0 1 0</axis></TransformAxis>
            <TransformAxis name="translation3"><function><Constant><value>0</value></Constant></function>
              <coordinates></coordinates><axis>0 0 1</axis></TransformAxis>
          </SpatialTransform>
        </CustomJoint></Joint></Body>
    </objects></BodySet>
  </Model>
</OpenSimDocument>
"""


# ---- CoordinateCouplerConstraints ----

def coupler_model():
    """hip pin `a` and a side pin `e` independent; knee pin `b` = 0.7 a + 0.1
    (LinearFunction), slider `c` = SimmSpline(a), pin `d` on the knee's body
    = Polynomial(e): the nonlinear couplings give q-dependent G and the
    f'' q̇² terms."""
    m = osim.Model()
    m.setName("coupler_model")
    bodies = {
        "a": inertia_body("a", 2.3, (0.05, -0.21, 0.03), (0.041, 0.012, 0.037, 0.002, -0.003, 0.001)),
        "b": inertia_body("b", 1.1, (0.01, -0.15, -0.02), (0.011, 0.004, 0.013, -0.001, 0.0005, 0.0007)),
        "c": inertia_body("c", 0.6, (0.02, 0.01, -0.03), (0.004, 0.003, 0.005, 0.0002, -0.0001, 0.0003)),
        "s": inertia_body("s", 0.9, (-0.03, 0.05, 0.01), (0.006, 0.007, 0.004, 0.0003, 0.0002, -0.0004)),
        "t": inertia_body("t", 0.4, (0.0, -0.08, 0.02), (0.002, 0.001, 0.002, 0.0, 0.0001, 0.0)),
    }
    for b in bodies.values():
        m.addBody(b)
    V = osim.Vec3
    joints = [
        osim.PinJoint("hip", m.getGround(), V(0.1, 0.9, -0.05), V(0.2, -0.3, 0.1), bodies["a"], V(0.02, 0.15, 0.01), V(-0.1, 0.25, 0.05)),
        osim.PinJoint("knee", bodies["a"], V(0.0, -0.4, 0.02), V(0.1, 0.0, 0.3), bodies["b"], V(0.0, 0.05, 0.0), V(0.0, 0.2, 0.0)),
        osim.SliderJoint("slide", bodies["b"], V(0.01, -0.3, 0.0), V(0.0, 0.4, -0.2), bodies["c"], V(0.0, 0.0, 0.02), V(0.1, 0.0, 0.0)),
        osim.PinJoint("side", bodies["a"], V(0.05, -0.1, 0.08), V(1.2, 0.1, 0.0), bodies["s"], V(0.0, 0.03, 0.0), V(0.0, 0.0, 0.1)),
        osim.PinJoint("toe", bodies["b"], V(0.0, -0.35, 0.04), V(0.0, 0.6, 0.2), bodies["t"], V(0.01, 0.0, 0.0), V(0.3, 0.0, 0.0)),
    ]
    for j, name in zip(joints, ["a", "b", "c", "e", "d"]):
        m.addJoint(j)
        c = j.upd_coordinates(0)
        c.setName(name)
        c.setRangeMin(-1.0)
        c.setRangeMax(1.0)
    spline = osim.SimmSpline()
    for x, y in zip([-1.5, -0.7, 0.0, 0.6, 1.5], [-0.05, 0.02, 0.04, 0.01, 0.06]):
        spline.addPoint(x, y)
    poly = osim.PolynomialFunction(osim.Vector([0.4, -0.3, 0.8, 0.05]))
    for name, dep, ind, f in [("b_follows_a", "b", "a", osim.LinearFunction(0.7, 0.1)),
                              ("c_follows_a", "c", "a", spline),
                              ("d_follows_e", "d", "e", poly)]:
        k = osim.CoordinateCouplerConstraint()
        k.setName(name)
        k.setIndependentCoordinateNames(osim.ArrayStr(ind, 1))
        k.setDependentCoordinateName(dep)
        k.setFunction(f)
        m.addConstraint(k)
    m.finalizeConnections()
    return m


def coupler_references(model, nstates, seed):
    """Per state, in the independent coordinates (the CoordinateSet order with
    the dependent ones left out): q, u, the full q (each dependent one
    OpenSim's function of its independent one), M = Gᵀ calcM G, τ = Gᵀ τ_full
    (InverseDynamicsSolver at the full u̇ = G u̇ + c, c = f'' u²), and
    udot_fd: Simbody's forward dynamics with the constraints enforced (every
    force disabled, gravity acts), the check that does not go through G."""
    disable_forces(model)
    state = model.initSystem()
    cs = model.getCoordinateSet()
    n = cs.getSize()
    names = [cs.get(k).getName() for k in range(n)]
    qi, ui = index_maps(model, state)
    cons = model.getConstraintSet()
    follows = {}
    for i in range(cons.getSize()):
        k = osim.CoordinateCouplerConstraint.safeDownCast(cons.get(i))
        ind = k.getIndependentCoordinateNames()
        assert ind.getSize() == 1
        follows[k.getDependentCoordinateName()] = (ind.get(0), k.getFunction())
    indep = [x for x in names if x not in follows]
    matter = model.getMatterSubsystem()
    idsolver = osim.InverseDynamicsSolver(model)
    rng = np.random.default_rng(seed)
    states = []
    for _ in range(nstates):
        qind = {x: float(rng.uniform(-1.0, 1.0)) for x in indep}
        uind = {x: float(rng.uniform(-2.0, 2.0)) for x in indep}
        udind = {x: float(rng.uniform(-3.0, 3.0)) for x in indep}
        q, u, ud = np.zeros(n), np.zeros(n), np.zeros(n)
        G = np.zeros((n, len(indep)))
        for k, x in enumerate(names):
            if x in follows:
                src, f = follows[x]
                arg = osim.Vector(1, qind[src])
                d1 = f.calcDerivative(osim.StdVectorInt([0]), arg)
                d2 = f.calcDerivative(osim.StdVectorInt([0, 0]), arg)
                q[k] = f.calcValue(arg)
                u[k] = d1 * uind[src]
                ud[k] = d1 * udind[src] + d2 * uind[src] ** 2
                G[k, indep.index(src)] = d1
            else:
                q[k], u[k], ud[k] = qind[x], uind[x], udind[x]
                G[k, indep.index(x)] = 1.0
        Q = osim.Vector(state.getNQ(), 0.0)
        U = osim.Vector(state.getNU(), 0.0)
        UD = osim.Vector(state.getNU(), 0.0)
        for k in range(n):
            Q.set(qi[k], float(q[k]))
            U.set(ui[k], float(u[k]))
            UD.set(ui[k], float(ud[k]))
        state.setQ(Q)
        state.setU(U)
        model.realizeAcceleration(state)
        qerr = max([abs(state.getQErr().get(i)) for i in range(state.getNQErr())] + [0.0])
        uerr = max([abs(state.getUErr().get(i)) for i in range(state.getNUErr())] + [0.0])
        assert qerr < 1e-12 and uerr < 1e-12, (qerr, uerr)
        udot = vec(state.getUDot())
        udot_fd = [udot[ui[names.index(x)]] for x in indep]
        Mm = osim.Matrix()
        matter.calcM(state, Mm)
        Mf = np.array(mat(Mm))[np.ix_(ui, ui)]
        tau = idsolver.solve(state, UD)
        tf = np.array([tau.get(ui[k]) for k in range(n)])
        states.append({
            "q": [qind[x] for x in indep],
            "u": [uind[x] for x in indep],
            "udot": [udind[x] for x in indep],
            "q_full": q.tolist(),
            "M": (G.T @ Mf @ G).tolist(),
            "tau": (G.T @ tf).tolist(),
            "udot_fd": udot_fd,
        })
    g = model.getGravity()
    return {
        "generator": "scripts/opensim_refs.py",
        "opensim_version": osim.__version__,
        "coordinates": indep,
        "all_coordinates": names,
        "gravity": [g.get(0), g.get(1), g.get(2)],
        "forces_disabled": True,
        "states": states,
    }


# ---- GCVSpline ----

GCV_CASES = [  # (half order, number of points, seed); seed 0: a jittered grid, as models' splines are
    (1, 6, 1), (2, 7, 2), (2, 12, 3), (3, 6, 4), (3, 9, 5), (3, 15, 6), (3, 11, 0), (2, 11, 0),
]


def natural_spline_exact(x, y, m, ts):
    """The interpolating natural spline of order 2m at ts, with 50 digits
    (mpmath): s(t) = Σ a_i |t − x_i|^(2m−1) + p(t), deg p < m, Σ a_i x_i^j = 0
    (j < m). OpenSim's GCVSPL and mx are both compared with it, since with
    close points GCVSPL's own rounding reaches ~1e-11."""
    import mpmath as mp
    mp.mp.dps = 50
    x = [mp.mpf(float(v)) for v in x]
    y = [mp.mpf(float(v)) for v in y]
    n, k = len(x), 2 * m - 1
    A = mp.matrix(n + m, n + m)
    b = mp.matrix(n + m, 1)
    for i in range(n):
        for j in range(n):
            A[i, j] = abs(x[i] - x[j]) ** k
        for j in range(m):
            A[i, n + j] = x[i] ** j
        b[i] = y[i]
    for j in range(m):
        for i in range(n):
            A[n + j, i] = x[i] ** j
    c = mp.lu_solve(A, b)

    def d(t, order):
        t = mp.mpf(t)
        s = mp.mpf(0)
        for i in range(n):
            if order > k:
                continue
            r = t - x[i]
            # d^o/dt^o |r|^k = k!/(k−o)! |r|^(k−o) sign(r)^o (right derivative at r = 0)
            sign = 1 if r >= 0 else -1
            s += c[i] * mp.ff(k, order) * abs(r) ** (k - order) * sign ** order
        for j in range(order, m):
            s += c[n + j] * mp.ff(j, order) * t ** (j - order)
        return float(s)
    return [[d(t, o) for t in ts] for o in range(3)]


def gcvspline_reference():
    """OpenSim's GCVSpline (error_variance 0: the interpolating natural spline
    of order 2·half_order) read from XML, evaluated with its first and second
    derivatives at points inside and outside the knots."""
    cases = []
    for m, n, seed in GCV_CASES:
        rng = np.random.default_rng(seed)
        if seed == 0:
            x = np.linspace(-1.8, 1.6, n) + rng.uniform(-0.05, 0.05, n)
        else:
            x = np.sort(rng.uniform(-1.8, 1.6, n))
        y = np.sin(1.3 * x) + 0.1 * x * x + 0.05 * rng.standard_normal(n)
        num = lambda v: " ".join(repr(float(a)) for a in v)
        xml = (f"<GCVSpline name=\"f\"><half_order>{m}</half_order><error_variance>0</error_variance>"
               f"<x>{num(x)}</x><y>{num(y)}</y><weights>{' '.join('1' for _ in x)}</weights></GCVSpline>")
        tmp = os.path.join(OUT, "gcv_tmp.xml")
        with open(tmp, "w") as f:
            f.write(f'<?xml version="1.0" encoding="UTF-8" ?>\n<OpenSimDocument Version="40600">{xml}</OpenSimDocument>\n')
        g = osim.GCVSpline.safeDownCast(osim.OpenSimObject.makeObjectFromFile(tmp))
        os.remove(tmp)
        ts = sorted(set(np.linspace(x[0] - 0.6, x[-1] + 0.6, 57).tolist() + x.tolist()))
        at = lambda t: osim.Vector(1, float(t))
        exact = natural_spline_exact(x, y, m, ts)
        cases.append({
            "xml": xml,
            "half_order": m,
            "t": ts,
            "value": [g.calcValue(at(t)) for t in ts],
            "d1": [g.calcDerivative(osim.StdVectorInt([0]), at(t)) for t in ts],
            "d2": [g.calcDerivative(osim.StdVectorInt([0, 0]), at(t)) for t in ts],
            "value_exact": exact[0],
            "d1_exact": exact[1],
            "d2_exact": exact[2],
        })
    d = os.path.join(OUT, "functions")
    os.makedirs(d, exist_ok=True)
    write_json(os.path.join(d, "gcvspline.json"), {"generator": "scripts/opensim_refs.py",
                                                   "opensim_version": osim.__version__, "cases": cases})


def reversed_reference(nstates):
    """The OpenSim 3.x model with both joints reversed (<reverse>true</reverse>),
    as OpenSim 4's updater reads it: parent and child frames swapped, so the
    joint's transform runs from the child body to the parent."""
    text = V3_MODEL.replace("<reverse>false</reverse>", "<reverse>true</reverse>")
    assert text.count("<reverse>true</reverse>") == 2
    text = text.replace('name="v3_model"', 'name="v3_reversed"')
    p = os.path.join(OUT, "joints", "OpenSim3Reversed.osim")
    with open(p, "w") as f:
        f.write(text)
    ref = references(osim.Model(p), nstates, seed=5)
    ref["model"] = "OpenSim3Reversed.osim (format 30000, both joints reversed, updated by OpenSim when loaded)"
    write_json(os.path.join(OUT, "joints", "OpenSim3Reversed.json"), ref)


def write_json(path, obj):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(obj, f, indent=1)
        f.write("\n")
    os.replace(tmp, path)


def mot_reference():
    """A Storage (.mot) written by OpenSim's STOFileAdapter, in degrees, with the values."""
    table = osim.TimeSeriesTable()
    labels = ["knee_angle_r", "pelvis_tx", "hip_flexion_r"]
    table.setColumnLabels(labels)
    rng = np.random.default_rng(7)
    rows = []
    for k in range(11):
        t = 0.01 * k
        r = [float(x) for x in rng.uniform(-60, 60, 3)]
        r[1] = r[1] / 100.0  # metres
        rows.append((t, r))
        table.appendRow(t, osim.RowVector(r))
    table.addTableMetaDataString("inDegrees", "yes")
    d = os.path.join(OUT, "mot")
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "opensim_written.mot")
    osim.STOFileAdapter.write(table, path)
    write_json(os.path.join(d, "opensim_written.json"), {
        "generator": "scripts/opensim_refs.py",
        "in_degrees": True,
        "labels": labels,
        "time": [t for t, _ in rows],
        "values": [r for _, r in rows],
    })


def check_mx_mot(path):
    """Reads a .mot written by mx with OpenSim's STOFileAdapter. When it is mx's
    copy of mot/opensim_written.mot (load it with the gait2392 body, save it:
    tests/it/opensim_files.rs does), its values must be OpenSim's to 1e-12."""
    t = osim.TimeSeriesTable(path)
    labels = list(t.getColumnLabels())
    times = list(t.getIndependentColumn())
    rows = [[t.getRowAtIndex(k)[i] for i in range(t.getNumColumns())] for k in range(t.getNumRows())]
    deg = t.getTableMetaDataAsString("inDegrees") if t.hasTableMetaDataKey("inDegrees") else "?"
    print(f"OpenSim read {path}: {len(rows)} rows, labels {labels}, inDegrees={deg}")
    ref = json.load(open(os.path.join(OUT, "mot", "opensim_written.json")))
    if labels == ref["labels"]:
        err = max(abs(a - b) / max(1.0, abs(b)) for r, s in zip(rows, ref["values"]) for a, b in zip(r, s))
        terr = max(abs(a - b) for a, b in zip(times, ref["time"]))
        print(f"against the values OpenSim wrote: max relative error {err:.1e}, time {terr:.1e}")
        assert err <= 1e-12 and terr <= 1e-12 and deg == "yes"


def timing(shared):
    """Load time and inverse dynamics per state on every shared model:
    OpenSim here, mx by its release example, in the same session."""
    import subprocess
    exe = os.path.join(ROOT, "target", "release", "examples", "opensim_timing")
    if not os.path.exists(exe):
        subprocess.run(["cargo", "build", "--release", "--example", "opensim_timing"], cwd=ROOT, check=True)
    src = os.path.join(shared, "data", "opensim")
    for f in sorted(os.listdir(src)):
        if not f.endswith(".osim"):
            continue
        path = os.path.join(src, f)
        for round_ in range(3):
            load = min(timed_load(path) for _ in range(5))
            model = osim.Model(path)
            disable_forces(model)
            state = model.initSystem()
            n = state.getNU()
            idsolver = osim.InverseDynamicsSolver(model)
            rng = np.random.default_rng(round_)
            # A new state per call (setQ/setU invalidate Simbody's cached
            # kinematics, as a new state does), vectors built beforehand.
            k = 100
            qs = [osim.Vector([float(x) for x in rng.uniform(-1, 1, state.getNQ())]) for _ in range(k)]
            us = [osim.Vector([float(x) for x in rng.uniform(-2, 2, n)]) for _ in range(k)]
            ud = osim.Vector([float(x) for x in rng.uniform(-3, 3, n)])
            reps = 5000
            t0 = time.perf_counter()
            for i in range(reps):
                state.setQ(qs[i % k])
                state.setU(us[i % k])
                idsolver.solve(state, ud)
            t_id = time.perf_counter() - t0
            t0 = time.perf_counter()
            for i in range(reps):  # the same loop without the solve: Python's and setQ/setU's share
                state.setQ(qs[i % k])
                state.setU(us[i % k])
            t_set = time.perf_counter() - t0
            idt = (t_id - t_set) / reps
            out = subprocess.run([exe, path], capture_output=True, text=True, check=True).stdout
            mx = json.loads(out)
            print(f"{f} round {round_ + 1}: load OpenSim {load * 1e3:.1f} ms, mx {mx['load_s'] * 1e3:.2f} ms "
                  f"(ratio mx/OpenSim {mx['load_s'] / load:.3f}); inverse dynamics per state OpenSim "
                  f"{idt * 1e6:.2f} us (from Python, setting the state not counted), mx {mx['inverse_dynamics_per_state_s'] * 1e6:.2f} us "
                  f"(ratio {mx['inverse_dynamics_per_state_s'] / idt:.3f})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shared", default=os.environ.get("MX_SHARED", os.path.join(ROOT, "..", "shared")))
    ap.add_argument("--states", type=int, default=4)
    ap.add_argument("--check-mot", help="read an mx-written .mot with OpenSim and print it")
    ap.add_argument("--timing", action="store_true", help="time load and inverse dynamics, OpenSim beside mx")
    ap.add_argument("--only", choices=["couplers", "gcvspline", "reversed"], help="write only these references")
    args = ap.parse_args()
    if args.timing:
        timing(args.shared)
        return
    if args.check_mot:
        check_mx_mot(args.check_mot)
        return
    if args.only == "reversed":
        reversed_reference(args.states)
        return
    if args.only == "gcvspline":
        gcvspline_reference()
        return
    if args.only == "couplers":
        d = os.path.join(OUT, "couplers")
        os.makedirs(d, exist_ok=True)
        p = os.path.join(d, "Couplers.osim")
        coupler_model().printToXML(p)
        ref = coupler_references(osim.Model(p), args.states, seed=11)
        ref["model"] = "Couplers.osim"
        write_json(os.path.join(d, "Couplers.json"), ref)
        return
    os.makedirs(os.path.join(OUT, "joints"), exist_ok=True)
    src = os.path.join(args.shared, "data", "opensim")
    for f in sorted(os.listdir(src)):
        if not f.endswith(".osim"):
            continue
        path = os.path.join(src, f)
        load_s = min(timed_load(path) for _ in range(3))
        ref = references(osim.Model(path), args.states, seed=19)
        ref["model"] = f
        ref["timing_s"]["load_and_init"] = load_s
        write_json(os.path.join(OUT, f[:-5] + ".json"), ref)
        print("wrote", f, file=sys.stderr)
    for kind in JOINTS:
        m = joint_model(kind)
        p = os.path.join(OUT, "joints", kind + ".osim")
        m.printToXML(p)
        if kind.startswith("CustomJoint"):
            custom_axes_xml(p, shared_rotation=kind == "CustomJointSharedRotation")
        ref = references(osim.Model(p), args.states, seed=len(kind))
        ref["model"] = kind + ".osim"
        if kind == "CustomJointSharedRotation":
            lagrange_bias(osim.Model(p), ref)
        write_json(os.path.join(OUT, "joints", kind + ".json"), ref)
        print("wrote", kind, file=sys.stderr)
    p = os.path.join(OUT, "joints", "OpenSim3Format.osim")
    with open(p, "w") as f:
        f.write(V3_MODEL)
    ref = references(osim.Model(p), args.states, seed=3)
    ref["model"] = "OpenSim3Format.osim (format 30000, written by hand, updated by OpenSim when loaded)"
    write_json(os.path.join(OUT, "joints", "OpenSim3Format.json"), ref)
    reversed_reference(args.states)
    d = os.path.join(OUT, "couplers")
    os.makedirs(d, exist_ok=True)
    p = os.path.join(d, "Couplers.osim")
    coupler_model().printToXML(p)
    ref = coupler_references(osim.Model(p), args.states, seed=11)
    ref["model"] = "Couplers.osim"
    write_json(os.path.join(d, "Couplers.json"), ref)
    gcvspline_reference()
    mot_reference()


if __name__ == "__main__":
    main()
