"""Simulated identification data for `inertiaproof identify`, made by Pinocchio (pin.rnea), not the project's dynamics.

    python bench/identify_data.py ROBOT.urdf OUT.csv [--samples 10000] [--rate 100] [--noise 0.05] [--seed 0]
        [--joints J1,J2,...] [--payload LINK --payload-mass 1.5 --payload-com X Y Z] [--pickup T --ramp R]
        [--still J] [--no-rates]

The trajectory is a sum of sinusoids per joint (5 harmonics of 0.1 Hz with random amplitudes and phases, fixed
seed), q, qd, qdd analytic; tau = rnea(q, qd, qdd) + Gaussian noise of standard deviation ``--noise`` (N m) per
sample and joint. Joints of the URDF not in ``--joints`` (default: the first chain's, as `identify` reads numbered
columns) are locked at 0 (pin.buildReducedModel). ``--payload``: a solid box of that mass (0.08 x 0.06 x 0.04 m)
at the CoM given in the link's frame is welded to the link (the model of `identify` omits it); ``--pickup T``:
taken up at time T, over ``--ramp`` seconds with the smootherstep profile s(t), the generalized equation's
M(q, s' Phi_p) qd added (Thetadot). Columns q_J, qd_J, qdd_J, tau_J by joint name (numbers with ``--numbered``).
"""

from __future__ import annotations

import argparse
import csv
import sys

import numpy as np
import pinocchio as pin

HARMONICS = 5
BASE_HZ = 0.1
BOX = (0.08, 0.06, 0.04)


def trajectory(t, n, seed, amplitude=0.6, still=()):
    """q, qd, qdd (S, n) of a sum of sinusoids, amplitude of each joint at most ``amplitude`` rad."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi * BASE_HZ * np.arange(1, HARMONICS + 1)
    a = rng.uniform(-1, 1, (n, HARMONICS)) / np.arange(1, HARMONICS + 1)
    a *= amplitude / np.abs(a).sum(1, keepdims=True)
    phase = rng.uniform(0, 2 * np.pi, (n, HARMONICS))
    offset = rng.uniform(-0.3, 0.3, n)
    arg = t[:, None, None] * w + phase[None]
    q = offset + (a * np.sin(arg)).sum(-1)
    qd = (a * w * np.cos(arg)).sum(-1)
    qdd = -(a * w**2 * np.sin(arg)).sum(-1)
    for k in still:
        q[:, k], qd[:, k], qdd[:, k] = offset[k], 0.0, 0.0
    return q, qd, qdd


def reduced_model(urdf, joints=None):
    """(model, joint names kept) of a URDF in Pinocchio, the joints not kept locked at 0."""
    full = pin.buildModelFromUrdf(str(urdf))
    names = [full.names[i] for i in range(1, full.njoints)]
    if joints is None:
        joints = default_joints(urdf)
    lock = [full.getJointId(n) for n in names if n not in joints]
    model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
    kept = [model.names[i] for i in range(1, model.njoints)]
    assert all(model.nqs[i] == 1 for i in range(1, model.njoints)), "continuous joints are not supported here"
    return model, kept


def default_joints(urdf):
    """The first chain's movable joints, as inertiaproof's kinematic tree orders them."""
    from inertiaproof.audit.document import read_robot
    from inertiaproof.audit.kinematic_tree import kinematic_tree

    return [j.name for j in kinematic_tree(read_robot(urdf)).chains[0].chain.joints]


def box_inertia(mass, com):
    return pin.Inertia(mass, np.asarray(com, float), np.diag([mass / 12 * (BOX[1]**2 + BOX[2]**2),
                                                              mass / 12 * (BOX[0]**2 + BOX[2]**2),
                                                              mass / 12 * (BOX[0]**2 + BOX[1]**2)]))


def payload_model(model, link, inertia):
    """A copy of ``model`` with ``inertia`` (in the link's frame) added to the joint that carries ``link``."""
    out = model.copy()
    frame = out.frames[out.getFrameId(link)]
    out.inertias[frame.parentJoint] = out.inertias[frame.parentJoint] + frame.placement.act(inertia)
    return out


def smootherstep(t, start, duration):
    x = np.clip((t - start) / duration, 0, 1)
    inside = ((t > start) & (t < start + duration)).astype(float)
    return x**3 * (10 + x * (-15 + 6 * x)), 30 * x * x * (1 - x) ** 2 * inside / duration


def simulate(urdf, samples=10000, rate=100.0, noise=0.05, seed=0, joints=None, payload=None, pickup=None,
             still=(), friction=None):
    """(t, q, qd, qdd, tau, joint names): ``payload`` (link, mass, com); ``pickup`` (T, ramp) or None; ``friction``
    (viscous, Coulomb) coefficients per joint, each (n,), added as viscous qd + Coulomb sign(qd)."""
    model, names = reduced_model(urdf, joints)
    t = np.arange(samples) / rate
    still_idx = [names.index(s) for s in still]
    q, qd, qdd = trajectory(t, model.nq, seed, still=still_idx)
    data = model.createData()
    tau = np.array([pin.rnea(model, data, q[s], qd[s], qdd[s]) for s in range(samples)])
    if payload is not None:
        link, mass, com = payload
        only = model.copy()
        for i in range(1, only.njoints):
            only.inertias[i] = pin.Inertia.Zero()
        only.gravity = model.gravity
        only = payload_model(only, link, box_inertia(mass, com))
        d = only.createData()
        extra = np.array([pin.rnea(only, d, q[s], qd[s], qdd[s]) for s in range(samples)])
        if pickup is None:
            tau += extra
        else:
            s_val, s_rate = smootherstep(t, *pickup)
            rate_term = np.array([pin.crba(only, d, q[s]) @ qd[s] if s_rate[s] else np.zeros(model.nv)
                                  for s in range(samples)])
            tau += s_val[:, None] * extra + s_rate[:, None] * rate_term
    if friction is not None:
        tau += np.asarray(friction[0]) * qd + np.asarray(friction[1]) * np.sign(qd)
    tau += np.random.default_rng(seed + 1).normal(0.0, noise, tau.shape)
    return t, q, qd, qdd, tau, names


def write_csv(path, t, q, qd, qdd, tau, names, rates=True, numbered=False):
    keys = [str(k + 1) for k in range(len(names))] if numbered else names
    kinds = ("q", "qd", "qdd", "tau") if rates else ("q", "tau")
    arrays = {"q": q, "qd": qd, "qdd": qdd, "tau": tau}
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t"] + [f"{kind}_{k}" for kind in kinds for k in keys])
        for s in range(len(t)):
            w.writerow([repr(float(t[s]))] + [repr(float(arrays[kind][s, j])) for kind in kinds
                                              for j in range(len(keys))])


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("urdf")
    p.add_argument("out")
    p.add_argument("--samples", type=int, default=10000)
    p.add_argument("--rate", type=float, default=100.0)
    p.add_argument("--noise", type=float, default=0.05)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--joints")
    p.add_argument("--payload")
    p.add_argument("--payload-mass", type=float, default=1.5)
    p.add_argument("--payload-com", type=float, nargs=3, default=(0.0, 0.0, 0.05))
    p.add_argument("--pickup", type=float)
    p.add_argument("--ramp", type=float, default=1.0)
    p.add_argument("--still", action="append", default=[])
    p.add_argument("--no-rates", action="store_true")
    p.add_argument("--numbered", action="store_true")
    a = p.parse_args(argv)
    payload = None if a.payload is None else (a.payload, a.payload_mass, a.payload_com)
    pickup = None if a.pickup is None else (a.pickup, a.ramp)
    joints = a.joints.split(",") if a.joints else None
    t, q, qd, qdd, tau, names = simulate(a.urdf, a.samples, a.rate, a.noise, a.seed, joints, payload, pickup, a.still)
    write_csv(a.out, t, q, qd, qdd, tau, names, rates=not a.no_rates, numbered=a.numbered)
    print(f"{a.out}: {a.samples} samples of {len(names)} joints ({', '.join(names)})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
