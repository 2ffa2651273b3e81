"""Beyond the paper: the payload envelope (``APP-payload-envelope``), Theorems 2-4 over a set of payloads.

:func:`envelope_result` certifies alpha1, alpha2 and chi over every consistent payload of a set (a ball or an
ellipsoid) at a body (:mod:`inertiaproof.bounds.payload`) and attacks them: Hypothesis draws payloads of the set
(point masses, spheres and boxes inside it: :mod:`inertiaproof.counterexamples.payloads`) and configurations, and
none may go beyond a certified constant; a payload beyond the set (heavier) is shown to go beyond alpha2, so the set
matters. VIOLATED where a payload of the set goes beyond a certified constant or a bracket's attained side beyond
its certified one. Without ``--scene``, in deep the built-in Panda and UR5 carry 0..5 kg within 0.1 m of the
flange (the last body's frame origin; in ci the planar 2R 0..2 kg), taken up in 1 s (smootherstep); with one, the
ball of 0.1 m around its heaviest payload's centre of mass (or 5 kg at the last body's origin).
"""

from __future__ import annotations

import functools
from fractions import Fraction

import numpy as np
from hypothesis import HealthCheck, Phase, given, seed, settings, target
from hypothesis import strategies as st
from hypothesis.errors import HypothesisException

from inertiaproof.bounds.domain import search_box
from inertiaproof.bounds.payload import PayloadSet, envelope, with_payload
from inertiaproof.bounds.pivot_search import DEEP_ROUNDS
from inertiaproof.counterexamples.payloads import payloads
from inertiaproof.dynamics import composite
from inertiaproof.dynamics.trajectory import Payload, Profile
from inertiaproof.model.inertia import point_mass, pseudo_inertia
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.scene import robots
from inertiaproof.dynamics.chain import Chain
from inertiaproof.suite.execution import Executor
from inertiaproof.suite.hunt import shard_seed, shard_sizes
from inertiaproof.suite.registry import check, replayer

__all__ = ["attack", "BUILT_IN", "envelope_result", "payload_envelope", "prove", "ramp_rate", "replay_payload",
           "TOLERANCE"]

ID = "APP-payload-envelope"
BUILT_IN = {  # (scene, kg, m): deep runs the report's section; ci the planar 2R (Panda's envelope and the checker's
    # re-proof would be most of a ci run: bench/results/machine_timings.md; UR5's sups are certified by Fourier entry
    # bounds, whose certificates carry no partition, beyond the checker's ci work: inertiaproof envelope spends that
    # budget)
    "ci": (("planar_2r", 2, Fraction(1, 10)),),
    "deep": (("panda", 5, Fraction(1, 10)), ("ur5", 5, Fraction(1, 10))),
}
RAMP_S = 1.0  # the built-in payloads are taken up in this many seconds
TOLERANCE = 1e-9  # relative: what eigvalsh's rounding (8 n eps |lambda|) cannot reach
ATTACK_SHARD = 2500  # payloads per task of the attack (deep's 100,000 per robot: 40 tasks)
HEAVIER = (1.5, 2.0, 4.0, 8.0)  # masses (times the set's) tried for a payload beyond the set at the worst point


def ramp_rate(seconds, shape="smootherstep"):
    """sup |s'| of a payload taken up over ``seconds`` with the scenes' ``shape`` (1/s), as a Fraction of the float."""
    return Fraction(Profile(shape, 0.0, seconds).rate_bound())


def _margins(chain, theta, pset, bounds, rate, phi, q):
    """Relative margins (K,) of payload ``phi`` at configurations q (K, n) against the certified constants (bounds:
    alpha1, alpha2, chi, zeta); > 0 inside."""
    loaded = with_payload(theta, pset, phi)
    eig = np.linalg.eigvalsh(composite.mass_matrix(chain, q, loaded))
    alone = np.linalg.eigvalsh(composite.mass_matrix(chain, q, with_payload(np.zeros_like(theta), pset, phi)))[:, -1]
    zeta = np.linalg.eigvalsh(pseudo_inertia(loaded))[:, -1].max()
    a1, a2, chi, z = bounds
    return np.minimum.reduce([(eig[:, 0] - a1) / abs(a1), (a2 - eig[:, -1]) / a2, (chi - float(rate) * alone) / chi,
                              np.full(len(q), (z - zeta) / z)])


def attack(chain, theta, pset, bounds, rate, *, examples, seed_value, witnesses, executor=None, label="attack"):
    """Hypothesis draws ``examples`` payloads of the set and a configuration each (tested with the
    ``witnesses`` (K, n) too): {examples, smallest_margin, worst, violation}; the first margin below -TOLERANCE
    stops the hunt and is the violation (payload Phi, q). The payloads are drawn in shards of ATTACK_SHARD, each
    with its own seed (:func:`~inertiaproof.suite.hunt.shard_seed`; one shard keeps ``seed_value``), as tasks of
    ``executor`` (default: this process), merged in shard order up to the first violating one: the answer does not
    depend on the workers."""
    sizes = shard_sizes(examples, ATTACK_SHARD)
    seeds = [seed_value] if len(sizes) == 1 else [shard_seed(seed_value, label, i, len(sizes))
                                                  for i in range(len(sizes))]
    task = functools.partial(_attack_shard, chain, theta, pset, bounds, rate, witnesses)
    shards = (executor or Executor()).map(task, list(zip(sizes, seeds)), kind="hunt", label=label,
                                          stop=lambda i, shard: shard["violation"] is not None)
    seen = {"examples": 0, "smallest": np.inf, "worst": None, "violation": None}
    for shard in shards:
        seen["examples"] += shard["examples"]
        if shard["smallest"] < seen["smallest"]:
            seen.update(smallest=shard["smallest"], worst=shard["worst"])
        if shard["violation"] is not None:
            seen["violation"] = shard["violation"]
            break
    return seen


def _attack_shard(chain, theta, pset, bounds, rate, witnesses, shard):
    """One shard of :func:`attack`: (examples, seed) -> its {examples, smallest, worst, violation}."""
    examples, seed_value = shard
    lo, hi = search_box(chain)
    m, c, axes = pset.floats
    seen = {"examples": 0, "smallest": np.inf, "worst": None, "violation": None}

    @seed(seed_value)
    @settings(max_examples=examples, deadline=None, database=None, derandomize=False,
              phases=[Phase.generate, Phase.target], suppress_health_check=list(HealthCheck))
    @given(payloads(m, c, axes), st.lists(st.floats(0, 1, allow_nan=False), min_size=chain.n, max_size=chain.n))
    def hunt(phi, u):
        q = np.vstack([witnesses, lo + (hi - lo) * np.asarray(u)])
        margins = _margins(chain, theta, pset, bounds, rate, phi, q)
        k = int(np.argmin(margins))
        seen["examples"] += 1
        if margins[k] < seen["smallest"]:
            seen.update(smallest=float(margins[k]), worst={"phi": phi.tolist(), "q": q[k].tolist()})
        target(-float(margins[k]))
        if margins[k] < -TOLERANCE:
            seen["violation"] = {"phi": phi.tolist(), "q": q[k].tolist(), "margin": float(margins[k])}
            raise AssertionError("beyond a certified constant")

    try:
        hunt()
    except (AssertionError, HypothesisException):
        pass
    return seen


def _beyond(chain, theta, pset, alpha2, point, q):
    """The lightest of HEAVIER x the set's mass, at the worst point, whose lambda_max at q (a value) goes beyond
    alpha2 (the certified constant)."""
    for factor in HEAVIER:
        mass = factor * float(pset.mass)
        loaded = with_payload(theta, pset, point_mass(mass, point))
        value = np.linalg.eigvalsh(composite.mass_matrix(chain, q, loaded))[-1]
        if value > alpha2:
            return {"mass": mass, "com": list(point), "lambda_max": float(value), "alpha2": alpha2}
    return None


def prove(chain, theta, pset, *, ramp_s, profile, points, goal, speed=None, seed_value=0, progress=None):
    """The certified side of one envelope (:func:`inertiaproof.bounds.payload.envelope`): the constants, the
    brackets and the curve against the mass (``points`` masses below the set's); ``goal`` the sup brackets' (None:
    the ladder's default; alpha2's ladder may test ``profile.envelope_boxes`` boxes); ``speed``: the payload's
    particles move inside the set at most this fast (m/s; Theorem 5). Its own random stream (``seed_value``): one
    envelope's answer does not depend on another's."""
    masses = [pset.mass * Fraction(i, points + 1) for i in range(1, points + 1)]
    return envelope(chain, theta, pset, rate=ramp_rate(ramp_s), speed=speed, masses=masses, goal=goal,
                    boxes=profile.envelope_boxes or None, samples=profile.samples, rounds=profile.rounds,
                    rng=np.random.default_rng(seed_value), progress=progress)


def envelope_result(name, chain, theta, pset, *, ramp_s, profile, examples, points, goal, speed=None, seed_value=0,
                    progress=None, executor=None, found=None):
    """The Result of one envelope: :func:`prove`'s constants, brackets and curve (``found``, when already proved)
    and the attack (``examples`` Hypothesis payloads, its shards tasks of ``executor``)."""
    rate = ramp_rate(ramp_s)
    if found is None:
        found = prove(chain, theta, pset, ramp_s=ramp_s, profile=profile, points=points, goal=goal, speed=speed,
                      seed_value=seed_value, progress=progress)
    low, high, chi = found["lower"], found["upper"], found["chi"]
    bounds = (low["certified"]["value"], high["certified"]["value"], chi["certified"]["value"],
              found["ingredients"]["zeta"][1])
    witnesses = np.array([low["observed"]["witness"], high["observed"]["witness"], chi["observed"]["witness"]])
    seen = attack(chain, theta, pset, bounds, rate, examples=examples, seed_value=seed_value,
                  witnesses=witnesses, executor=executor, label=f"{name} payload attack")
    worst = found["worst_payload"]
    beyond = _beyond(chain, theta, pset, bounds[1], worst["com"], np.asarray(worst["q"]))
    inverted = [k for k, b in (("inf lambda_min(M)", low["observed"]), ("sup lambda_max(M)", high["observed"]),
                               ("sup sigma_max(M(q, Thetadot))", chi["observed"])) if not b["lower"] <= b["upper"]]
    label = f"{name}: {pset.describe()}"
    if seen["violation"] is not None:
        verdict = Verdict.VIOLATED
        summary = (f"{label}: a payload of the set goes beyond a certified constant (relative margin "
                   f"{seen['violation']['margin']:.3g})")
    elif inverted:
        verdict, summary = Verdict.VIOLATED, f"{label}: attained beyond the certified side: {', '.join(inverted)}"
    elif not all(np.isfinite(bounds)):
        verdict, summary = Verdict.INCONCLUSIVE, f"{label}: a constant is not certified (infinite)"
    else:
        verdict = Verdict.HOLDS
        summary = (f"{label}: alpha1 {bounds[0]:.4g}, alpha2 {bounds[1]:.4g} (sup lambda_max in "
                   f"[{high['observed']['lower']:.4g}, {high['observed']['upper']:.4g}]), chi {bounds[2]:.4g}; "
                   f"{seen['examples']} Hypothesis payloads, none beyond")
    evidence = {
        "payload_set": found["payload"], "ramp_s": quantity(ramp_s, "exact", "the ramp's duration (s)"),
        "rate": quantity(float(rate), "exact", "sup |s'| (1/s)"),
        "constants": _constants(found),
        "brackets": found["brackets"],
        "worst_payload": worst,
        "attack": {"examples": quantity(seen["examples"], "count", "Hypothesis payloads drawn from the set"),
                   "smallest_margin": quantity(seen["smallest"], "sampled", "smallest relative margin to a certified "
                                                                            "constant over the examples"),
                   "worst": seen["worst"], "violation": seen["violation"]},
        "beyond_the_set": _labelled(beyond) if beyond else "no heavier payload at the worst point goes beyond alpha2",
        "curve": _curve(found, pset),
        "curve_certified": [{"mass": row["mass"],
                             "alpha2": quantity(row["alpha2"]["certified"], "upper_bound", "sup lambda_max(M) over the "
                                                "payloads of this mass", certificate=row["alpha2"]["certificate"]),
                             "chi": quantity(row["chi"]["certified"]["value"], "certified_constant",
                                             row["chi"]["certified"]["how"],
                                             certificate=row["chi"]["certified"].get("certificate"))}
                            for row in found["curve"]],
        "figures": {f"{name}: constants against the payload's mass": {"series": _series(found, pset)}},
        **({"theorem5": _theorem5(found["theorem5"], speed)} if speed is not None else {}),
    }
    counterexample, violation = None, seen["violation"]
    if violation is None and inverted:  # the worst point mass itself goes beyond
        phi = point_mass(float(pset.mass), worst["com"])
        q = np.asarray([worst["q"]])
        violation = {"phi": phi.tolist(), "q": worst["q"],
                     "margin": float(_margins(chain, theta, pset, bounds, rate, phi, q)[0])}
    if violation is not None:
        counterexample = {"kind": "payload-envelope", "data": {
            "name": name, "chain": chain.to_data(), "theta": np.asarray(theta).tolist(), "payload_set": pset.to_json(),
            "rate": str(rate), "bounds": list(bounds), **violation}}
    return Result(ID, verdict, summary, evidence, counterexample)


def _labelled(beyond):
    """:func:`_beyond`'s payload, its numbers saying what they are."""
    return {"mass": quantity(beyond["mass"], "exact", "a point mass heavier than the set's (kg), at the worst point"),
            "com": beyond["com"],
            "lambda_max": quantity(beyond["lambda_max"], "value", "lambda_max(M) it reaches at the worst q"),
            "alpha2": quantity(beyond["alpha2"], "value", "the set's certified alpha2 it goes beyond (its certificate: "
                                                          "constants.alpha2.certified)")}


def _constants(found):
    low, high, chi = found["lower"], found["upper"], found["chi"]
    sides = {"alpha1": found["brackets"]["inf lambda_min(M)"]["lower"],  # the true extremes' certified sides
             "alpha2": found["brackets"]["sup lambda_max(M)"]["upper"], "chi": chi["certified"]}
    out = {}
    for name, c, sense in (("alpha1", low, "lower"), ("alpha2", high, "upper"), ("chi", chi, "upper")):
        certified = c["certified"]
        paper = c["paper"]
        side = sides[name].get("certificate")
        out[name] = {
            "certified": quantity(certified["value"], "certified_constant", certified["how"],
                                  certificate=certified.get("certificate")),
            "paper": quantity(paper.get(sense, paper["value"]), "lower_bound" if sense == "lower" else "upper_bound",
                              "the paper's constant from certified ingredients", certificate=paper.get("certificate")),
            "true_extreme": {
                "lower": quantity(c["observed"]["lower"], "lower_bound" if sense == "lower" else "sampled",
                                  "certified side" if sense == "lower" else "attained at the witness",
                                  certificate=side if sense == "lower" else None),
                "upper": quantity(c["observed"]["upper"], "sampled" if sense == "lower" else "upper_bound",
                                  "attained at the witness" if sense == "lower" else "certified side",
                                  certificate=side if sense == "upper" else None)},
        }
    return out


def _theorem5(t5, speed):
    how = ("the prover's certified sides (Bernstein bounds), not re-proved: no certificate kind covers sup "
           "sigma_max(Y_p)")
    return {"speed": quantity(float(speed), "exact", "the particles' speed inside the set (m/s)"),
            "psi_star": quantity(t5["psi_star"], "upper_bound", "m V (1 + (|c| + a_max)^2)^(1/2), rounded up"),
            "paper": quantity(t5["paper"], "upper_bound", "sqrt(6N) Psi* max_p sup_q sigma_max(Y_p): " + how),
            "sharp": quantity(t5["sharp"], "upper_bound", "Psi* sup_q (sum_p sigma_max(Y_p)^2)^(1/2): " + how),
            "brackets": t5["brackets"]}


def _curve(found, pset):
    """Rows (mass, alpha1, alpha2 attained and certified, chi certified) from no payload to the set's full one."""
    alpha1 = found["lower"]["certified"]["value"]
    high = found["upper"]
    full = {"mass": float(pset.mass), "chi": found["chi"],
            "alpha2": {"attained": high["observed"]["lower"], "certified": high["certified"]["value"]}}
    empty = {"mass": 0.0, "alpha1": alpha1, "alpha2_attained": None, "alpha2_certified": None, "chi_certified": 0.0}
    return [empty] + [
        {"mass": row["mass"], "alpha1": alpha1, "alpha2_attained": row["alpha2"]["attained"],
         "alpha2_certified": row["alpha2"]["certified"], "chi_certified": row["chi"]["certified"]["value"]}
        for row in found["curve"] + [full]]


def _series(found, pset):
    rows = _curve(found, pset)[1:]
    line = lambda key: [[r["mass"], r[key]] for r in rows if r[key] is not None]  # noqa: E731
    return {"title": "certified constants against the payload's mass", "x_label": "payload mass (kg)",
            "y_label": "constant", "y_log": True,
            "lines": {"alpha2 certified": line("alpha2_certified"), "sup lambda_max attained": line("alpha2_attained"),
                      "chi certified": line("chi_certified"), "alpha1 certified": line("alpha1")}}


def _cases(ctx, deep):
    if ctx.scene is None:
        for name, mass, radius in BUILT_IN["deep" if deep else "ci"]:
            scene = getattr(robots, name)()
            yield name, scene.chain, scene.trajectory.base, PayloadSet.ball(scene.chain.n - 1, mass, (0, 0, 0), radius)
        return
    scene = ctx.scene
    loads = sorted((load for load in scene.trajectory.loads if isinstance(load, Payload)), key=lambda p: -p.phi[0])
    if loads:
        body, mass, centre = loads[0].body, Fraction(float(loads[0].phi[0])), loads[0].phi[1:4] / loads[0].phi[0]
    else:
        body, mass, centre = scene.chain.n - 1, Fraction(5), np.zeros(3)
    yield scene.name, scene.chain, scene.trajectory.base, PayloadSet.ball(body, mass, tuple(map(float, centre)),
                                                                          Fraction(1, 10))


def _prove_case(settings, progress, case):
    name, chain, theta, pset = case
    return prove(chain, theta, pset, progress=progress, **settings)


@check(ID)
def payload_envelope(ctx):
    """In a run: in ci the profile's Hypothesis examples per hunt, the ladder's default goal and no curve points;
    in deep the envelope's budget (Profile.envelope_*: 100,000 payloads per robot), as ``inertiaproof envelope``."""
    deep = ctx.profile.rounds >= DEEP_ROUNDS
    cases = list(_cases(ctx, deep))
    settings = dict(ramp_s=RAMP_S, profile=ctx.profile, points=ctx.profile.envelope_points if deep else 0,
                    goal=ctx.profile.envelope_goal if deep else None, seed_value=ctx.seed)
    task = functools.partial(_prove_case, settings, ctx.progress)
    executor = ctx.executor if ctx.executor.portable(task) else Executor()
    found = executor.map(task, cases, kind="boxes", label="payload envelope provers")  # the robots side by side
    results = [envelope_result(name, chain, theta, pset, examples=ctx.profile.envelope_examples if deep else
                               ctx.profile.examples, progress=ctx.progress, executor=ctx.executor, found=proved,
                               **settings) for (name, chain, theta, pset), proved in zip(cases, found)]
    verdict = combine(r.verdict for r in results)
    first = next((r for r in results if r.verdict == verdict), results[0])
    return Result(ID, verdict, "; ".join(r.summary for r in results),
                  {"cases": {r.summary.split(":")[0]: r.evidence for r in results}}, first.counterexample)


@replayer("payload-envelope")
def replay_payload(data, ctx):
    """The saved payload at its configuration against the saved certified constants: still beyond one is VIOLATED."""
    pset = PayloadSet.from_json(data["payload_set"])
    margin = float(_margins(Chain.from_data(data["chain"]), np.asarray(data["theta"], float), pset, data["bounds"],
                            Fraction(data["rate"]), np.asarray(data["phi"], float), np.asarray([data["q"]], float))[0])
    verdict = Verdict.VIOLATED if margin < -TOLERANCE else Verdict.HOLDS
    return Result(ID, verdict, f"{data['name']}: the saved payload's relative margin to the certified constants is "
                  f"{margin:.3g}", {"margin": quantity(margin, "value", "relative margin at the saved q")})
