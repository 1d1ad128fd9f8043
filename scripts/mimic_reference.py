#!/usr/bin/env python3
"""Reference dynamics of tests/data/mimic_gripper.urdf with mimic joints as
coupled coordinates, computed by Pinocchio (PyPI `pin`, 4.1):
`pinocchio.buildModelFromXML(urdf, mimic=True)`.

Writes tests/data/mimic_gripper.json: per case q, v, a (the independent
coordinates, Pinocchio's order), tau = rnea(q, v, a), M = crba(q) (made
symmetric from its upper triangle, Pinocchio's contract), and for a torque
tau_in the accelerations qdd = M⁻¹ (tau_in − nle(q, v)). Pinocchio 4.1's
`aba` refuses mimic joints ("does not support Joint Mimic"), so the forward
dynamics reference is Pinocchio's own M and nonlinear effects solved densely.
The script also checks that crba equals the columns of rnea, and that rnea with mimic equals Gᵀ rnea of the plain model
at the expanded state (q_full = G q + offset), so the coupled τ is the
generalised force on the independent coordinates.

    python3 -m venv /tmp/pin && /tmp/pin/bin/pip install pin
    /tmp/pin/bin/python scripts/mimic_reference.py
"""

import json
import pathlib

import numpy as np
import pinocchio as pin

HERE = pathlib.Path(__file__).resolve().parent.parent / "tests" / "data"
URDF = HERE / "mimic_gripper.urdf"


def main():
    xml = URDF.read_text()
    m = pin.buildModelFromXML(xml, mimic=True)
    full = pin.buildModelFromXML(xml)
    d, df = m.createData(), full.createData()
    names = [n for n in m.names[1:] if m.joints[m.getJointId(n)].nq > 0]
    full_names = list(full.names[1:])
    # The coupling q_full = G q + b, from the URDF's <mimic> tags.
    import xml.etree.ElementTree as ET

    mimic = {}
    for j in ET.fromstring(xml).iter("joint"):
        t = j.find("mimic")
        if t is not None:
            mimic[j.get("name")] = (
                t.get("joint"),
                float(t.get("multiplier", "1")),
                float(t.get("offset", "0")),
            )
    G = np.zeros((full.nv, m.nv))
    b = np.zeros(full.nq)
    for k, n in enumerate(full_names):
        if n in mimic:
            src, mul, off = mimic[n]
            G[k, names.index(src)] = mul
            b[k] = off
        else:
            G[k, names.index(n)] = 1.0

    rng = np.random.default_rng(14)
    cases = []
    for _ in range(6):
        q = rng.uniform(-1.2, 1.2, m.nq)
        q[-1] = rng.uniform(0.0, 0.04)  # finger_left, a prismatic joint in metres
        v = rng.uniform(-2.0, 2.0, m.nv)
        a = rng.uniform(-3.0, 3.0, m.nv)
        tau = pin.rnea(m, d, q, v, a).copy()
        tau_full = pin.rnea(full, df, G @ q + b, G @ v, G @ a)
        assert np.allclose(G.T @ tau_full, tau, atol=1e-10), (G.T @ tau_full, tau)
        # A fresh Data for crba: with mimic joints, Pinocchio 4.1's crba on a
        # Data that rnea used before returns wrong entries (up to 0.16 here).
        M = pin.crba(m, m.createData(), q).copy()
        M = np.triu(M) + np.triu(M, 1).T
        Mf = pin.crba(full, full.createData(), G @ q + b).copy()
        Mf = np.triu(Mf) + np.triu(Mf, 1).T
        z = np.zeros(m.nv)
        Mr = np.array([pin.rnea(m, d, q, z, e) - pin.rnea(m, d, q, z, z) for e in np.eye(m.nv)]).T
        assert np.allclose(Mr, M, atol=1e-10), Mr - M
        assert np.allclose(G.T @ Mf @ G, M, atol=1e-10), G.T @ Mf @ G - M
        tau_in = rng.uniform(-2.0, 2.0, m.nv)
        nle = pin.nonLinearEffects(m, d, q, v)
        qdd = np.linalg.solve(M, tau_in - nle)
        cases.append(
            {
                "q": q.tolist(),
                "v": v.tolist(),
                "a": a.tolist(),
                "tau": tau.tolist(),
                "M": M.tolist(),
                "tau_in": tau_in.tolist(),
                "qdd": qdd.tolist(),
            }
        )
    out = {
        "source": "scripts/mimic_reference.py",
        "pinocchio": pin.__version__,
        "urdf": URDF.name,
        "coordinates": names,
        "gravity": list(m.gravity.linear),
        "cases": cases,
    }
    (HERE / "mimic_gripper.json").write_text(json.dumps(out, indent=1) + "\n")
    print(f"{len(cases)} cases, coordinates {names}")


if __name__ == "__main__":
    main()
