"""Verdict and evidence of a Section 4 bound on scenes, from brackets of both of its sides.

A bound "extreme of the left-hand side <= constant" (>= for Theorem 2) is
judged from a Bracket of the true extreme (inertiaproof.bounds.extremes) and the
range the constant can take given its bracketed ingredients, and from the
proof's pointwise inequality at sampled (q, t) (checks.pointwise):

- VIOLATED, whatever else holds: the certified side of the extreme lies
  beyond a value attained at its witness (an inverted bracket: the
  certificate is refuted); or a value attained at a witness lies beyond every
  value the constant can have; or a sampled point breaks the pointwise
  inequality, or a reported constant fails against a sampled left-hand side,
  by more than the resolution;
- HOLDS: the certified side of the extreme lies within every value the
  constant can have; or the proof covers the constant (its key step is
  certified for all Phi) and no sampled point breaks the pointwise inequality;
- INCONCLUSIVE otherwise.

Brackets are shared by the checks of a run (:func:`cached`) under the scene's name and a digest of its chain
and trajectory: two scenes that share a name (hunted scenes are named by their sample seed) never share a
bracket. A "bound-bracket" counterexample carries the certified side with the witness and the parameter sets,
and the case replays it before it reports it (:func:`replay_bound_bracket`): a VIOLATED the saved file cannot
show is not reported as one.

The ``constants`` evidence (the report plots it) says what each number is:
``paper`` is the paper's constant evaluated with certified ingredients (an
upper bound of it when its ingredients are suprema, a lower bound when they
are infima), ``paper_observed`` the same formula with the observed
ingredients (an estimate from the other side), ``certified`` the sharpest
constant the suite certifies, ``observed`` the worst case attained over the
samples (a one-sided estimate of the true extreme).
"""

from __future__ import annotations

import hashlib
import json

import numpy as np
from inertiaproof.checks.pointwise import (
    CONSTANTS,
    RESOLUTION,
    SENSE,
    named_margins,
    point_counterexample,
    state_at,
)

from inertiaproof.bounds.domain import free_coordinates, search_box
from inertiaproof.bounds.certificate import key_step_certificate as key_step_claim
from inertiaproof.bounds.extremes import Bracket, local_search
from inertiaproof.bounds.spectral import spectral
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.citation import cite
from inertiaproof.dynamics import composite
from inertiaproof.dynamics.chain import Chain
from inertiaproof.dynamics.trajectory_data import trajectory_to_data
from inertiaproof.dynamics.terms import lumped_acceleration_force, lumped_velocity_matrix
from inertiaproof.model.positive_map import key_step_proof
from inertiaproof.presentation import bracket_evidence
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.suite.registry import replayer

__all__ = [
    "bracket_refutation", "cached", "case_result", "constants_evidence", "inverted_bracket", "inverted_extreme",
    "judge", "key_step_evidence", "kw", "parameter_stack", "pointwise_on_scene", "replay_bound_bracket",
    "REPORTED_KINDS", "replay_bracket", "run_scenes", "sampled_bracket", "scene_digest", "scene_samples", "shown",
    "time_and_configuration_bracket", "time_quantities",
]

def cached(ctx, scene, what, fn):
    """fn() once per run, scene and quantity: corollaries reuse the theorems' brackets. The key holds a digest of
    the scene's chain and trajectory (:func:`scene_digest`), not only its name: hunted scenes are named by their
    sample seed, which Hypothesis draws again and again (0 above all) with other chains and trajectories."""
    return ctx.shared(("bracket", scene.name, scene.description, scene_digest(scene), what), fn)


def scene_digest(scene):
    """SHA-256 of what a scene's brackets are computed from: its chain and its parameter trajectory."""
    text = json.dumps([scene.chain.to_data(), trajectory_to_data(scene.trajectory)], sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def kw(ctx, scene, what, share=1.0):
    """The bracket settings of the run's profile, with a random stream per scene and quantity."""
    return dict(samples=ctx.profile.samples, rounds=ctx.profile.rounds * share,
                rng=ctx.rng(f"{scene.name}:{what}"), progress=ctx.progress)


def scene_samples(ctx, scene, salt, count=None):
    """Random configurations in the chain's box paired with times over the trajectory's span."""
    rng = ctx.rng(f"{scene.name}:{salt}:pairs")
    count = count or ctx.profile.samples
    lo, hi = search_box(scene.chain)
    q = lo + (hi - lo) * rng.random((count, scene.chain.n))
    t = rng.choice(scene.trajectory.times(max(count // 4, 2)), count)
    return q, t


def pointwise_on_scene(check_id, ctx, scene, k, reported=None):
    """The proof's pointwise inequality at sampled (q, t) of a scene, for every constant of the check as the code
    computes it (times k), and the sampled left-hand sides against the constants the check reports for the scene
    (``reported``: {name: value}, e.g. the paper's constant with certified ingredients and the sharpest certified
    one): evidence and the point closest to failing. A reported constant beyond a sampled value is a
    "bound-constant" counterexample, which the replay re-computes (the scene's constants with the current code)."""
    q, t = scene_samples(ctx, scene, check_id)
    state = state_at(scene.trajectory, t)
    margin, resolution, lhs, rhs, names = named_margins(check_id, scene.chain, q, state, k)
    compared = ~np.isnan(margin)
    if not compared.any():
        return {"violated": False, "counterexample": None,
                "evidence": {"samples": quantity(len(q), "count", "random (q, t) pairs; both sides vanish at all"),
                             **({"reported": _reported_evidence(reported)} if reported else {})}}
    i = int(np.nanargmin(margin + resolution))
    point = (i, float(margin[i]), float(resolution[i]), float(lhs[i]), float(rhs[i]), str(names[i]))
    evidence = {"constants_tested": sorted(set(CONSTANTS[check_id])),
                "smallest_margin": quantity(float(np.nanmin(margin)), "margin",
                                            "relative margin of the proof's pointwise inequality (closest constant)"),
                "resolution": quantity(float(resolution[i]), "tolerance", "resolution at the point closest to failing"),
                "unresolved": quantity(int(np.sum(np.abs(margin[compared]) <= resolution[compared])), "count",
                                       "points whose margin is within their resolution"),
                "samples": quantity(int(compared.sum()), "count",
                                    "random (q, t) pairs compared (both sides vanish at the others)")}
    violated = bool(margin[i] < -resolution[i])
    counterexample = point_counterexample(check_id, scene.chain, q, state, k, point)
    against = {}
    upper = SENSE[check_id] == "upper"
    for name, value in (reported or {}).items():
        value = float(value)
        if not np.isfinite(value):
            continue
        scale = np.abs(lhs) + abs(value)
        with np.errstate(invalid="ignore", divide="ignore"):
            m = (value - lhs) / scale if upper else (lhs - value) / scale
            res = RESOLUTION + (resolution - RESOLUTION) * (np.abs(lhs) + np.abs(rhs)) / scale
        j = int(np.nanargmin(np.where(compared, m + res, np.nan))) if compared.any() else 0
        against[name] = quantity(float(m[j]), "margin", f"relative margin of every sampled left-hand side against the "
                                 f"reported {name} constant {value:.6g}")
        if m[j] < -res[j] and not violated:
            violated = True
            counterexample = {"kind": "bound-constant", "data": {
                "id": check_id, "scene": scene.name, "description": scene.description, "constant": name,
                "factor": float(k), "value": value, "lhs": float(lhs[j]), "margin": float(m[j]),
                "resolution": float(res[j]), "chain": scene.chain.to_data(),
                "trajectory": trajectory_to_data(scene.trajectory), "q": np.asarray(q[j]).tolist(), "t": float(t[j]),
                "samples": ctx.profile.samples, "rounds": ctx.profile.rounds, "seed": ctx.seed}}
    if against:
        evidence["against_reported"] = against
    if reported:
        evidence["reported"] = _reported_evidence(reported)
    return {"violated": violated, "counterexample": counterexample, "evidence": evidence}


REPORTED_KINDS = {"paper": "paper_constant", "certified": "certified_constant"}


def _reported_evidence(reported):
    return {name: quantity(float(v), REPORTED_KINDS.get(name, "value"), "constant the check reports for the scene "
                           "(times the factor for the paper's)") for name, v in reported.items()}


def inverted_bracket(lhs):
    """Whether the certified side of a Bracket lies beyond the value attained at its witness by more than the
    resolution (a certified sup below, or a certified inf above, a value attained at the witness): the certificate
    is refuted by its own witness."""
    with np.errstate(invalid="ignore"):
        return bool(lhs.upper < lhs.lower - RESOLUTION * (abs(lhs.lower) + abs(lhs.upper)))


def inverted_extreme(found):
    """Whether the certified side of a time extreme (inertiaproof.bounds.time.time_extreme: observed, certified,
    sense) lies beyond the value it attains on its time grid by more than the resolution: an inverted bracket."""
    certified, observed = float(found["certified"]), float(found["observed"])
    if not (np.isfinite(certified) and np.isfinite(observed)):
        return False
    tol = RESOLUTION * (abs(certified) + abs(observed))
    return bool(certified > observed + tol if found["sense"] == "min" else certified < observed - tol)


def bracket_refutation(sense, lhs, constant_lower, constant_upper):
    """Why the bracket of the extreme alone refutes 'extreme <= (upper) / >= (lower) the constant' (an inverted
    bracket, or a value attained at the witness beyond every value the constant can have), or None."""
    if inverted_bracket(lhs):
        side = "upper" if lhs.sense == "max" else "lower"
        return (f"the certified {side} side of the extreme ({float(lhs.certified):.6g}) lies beyond a value attained "
                f"at the witness ({float(lhs.observed):.6g}): the certificate is refuted")
    bound = constant_upper if np.isfinite(constant_upper) else constant_lower
    tol = RESOLUTION * (abs(lhs.observed) + abs(bound))
    if sense == "upper" and lhs.observed > constant_upper + tol:
        return "a value attained at the witness exceeds the largest value the constant can have"
    if sense != "upper" and lhs.observed < constant_lower - tol:
        return "a value attained at the witness is below the smallest value the constant can have"
    return None


def judge(sense, lhs, constant_lower, constant_upper, *, proof_covers, pointwise_violated):
    """(verdict, why) of 'extreme of the left-hand side <= (upper) / >= (lower) the constant'.

    ``lhs`` is a Bracket of the true extreme; the constant lies in [constant_lower, constant_upper].
    ``pointwise_violated``: a sampled (q, t) breaks the proof's pointwise inequality, or a reported constant fails
    against a sampled left-hand side (:func:`pointwise_on_scene`). Refutations come first, whatever else holds: an
    inverted bracket, a value attained beyond the constant, a pointwise violation; then the certified side.
    """
    why = bracket_refutation(sense, lhs, constant_lower, constant_upper)
    if why is not None:
        return Verdict.VIOLATED, why
    if pointwise_violated:
        return Verdict.VIOLATED, ("the proof's pointwise inequality, or a constant the check reports, fails at a "
                                  "sampled (q, t) beyond its resolution")
    bound = constant_upper if np.isfinite(constant_upper) else constant_lower
    tol = RESOLUTION * (abs(lhs.observed) + abs(bound))
    if sense == "upper":
        if lhs.upper < constant_lower - tol:
            return Verdict.HOLDS, "the certified upper side of the extreme is below the constant"
    else:
        if lhs.lower > constant_upper + tol:
            return Verdict.HOLDS, "the certified lower side of the extreme is above the constant"
    if proof_covers:
        return Verdict.HOLDS, ("the certified proof covers this constant (key step certified for all Phi) and its "
                               "pointwise inequality held at every sample")
    return Verdict.INCONCLUSIVE, "the brackets of the extreme and of the constant overlap"


def constants_evidence(sense, formula, paper, paper_observed, certified, certified_how, observed, observed_note,
                       paper_certificate=None, certified_certificate=None):
    """The ``constants`` evidence: what each number is, in its kind and note; ``paper_certificate`` (kind
    ``product``, the paper's constant from its ingredients' certificates) goes into the paper quantity,
    ``certified_certificate`` into the certified one."""
    upper = sense == "upper"
    return {
        "paper": quantity(paper, "upper_bound" if upper else "lower_bound",
                          f"the paper's {formula} with certified ingredients: "
                          f"{'an upper' if upper else 'a lower'} bound of the paper's constant",
                          certificate=paper_certificate),
        "paper_observed": quantity(paper_observed, "sampled",
                                   f"the paper's {formula} with the observed ingredients: "
                                   f"{'a lower' if upper else 'an upper'} estimate of the paper's constant"),
        "certified": quantity(certified, "certified_constant", certified_how, certificate=certified_certificate),
        "observed": quantity(observed, "sampled", observed_note),
    }


def _cite(q, source):
    """``q`` (a quantity, being made) cites the certificate ``source`` (a constants entry) cites when it repeats the
    same number."""
    if source and float(source["value"]) == float(q["value"]) and source.get("certificate"):
        q["certificate"] = cite(source["certificate"], q["value"])
    return q


def _constant_range(sense, lo, hi, constants):
    """The range [lo, hi] of the (scaled) constant: its certified end (the paper's constant with certified
    ingredients) and its attained end (with the observed ingredients: a value the constant reaches)."""
    upper = sense == "upper"
    certified = _cite(quantity(hi if upper else lo, "upper_bound" if upper else "lower_bound",
                               f"{'largest' if upper else 'smallest'} value the (scaled) constant can have"),
                      constants.get("paper"))
    attained = quantity(lo if upper else hi, "sampled", "the (scaled) constant with the observed ingredients: it is "
                        f"at {'least' if upper else 'most'} this")
    return {"lower": attained, "upper": certified} if upper else {"lower": certified, "upper": attained}


def case_result(check_id, scene, sense, lhs, constant_range, k, proof_factor, pointwise, constants, extra,
                replay=None):
    """(verdict, why, evidence, counterexample) of one bound on one scene; ``constant_range`` is the range of
    the constant (times k) given its bracketed ingredients."""
    lo, hi = constant_range
    covers = bool(key_step_proof()["ok"]) and (k >= proof_factor if sense == "upper" else k <= proof_factor)
    verdict, why = judge(sense, lhs, lo, hi, proof_covers=covers, pointwise_violated=pointwise["violated"])
    evidence = {
        "scene": scene.name,
        "factor": quantity(k, "value", "multiplier of the paper's constant (1 = the paper's statement)"),
        "constants": constants,
        "constant_range": _constant_range(sense, lo, hi, constants),
        "bracket": bracket_evidence(lhs),
        "pointwise": pointwise["evidence"],
        "why": why,
        **extra,
    }
    for name, q in evidence["pointwise"].get("reported", {}).items():
        _cite(q, constants.get(name))
    counterexample = None
    if verdict == Verdict.VIOLATED and bracket_refutation(sense, lhs, lo, hi) is None:  # the samples refute it
        counterexample = pointwise["counterexample"]
        if counterexample is not None and counterexample["kind"] == "bound-constant":
            why = (f"the reported {counterexample['data']['constant']} constant fails against a sampled left-hand "
                   f"side beyond the resolution")
        else:
            why = "the proof's pointwise inequality fails at a sampled (q, t) beyond its resolution"
        evidence["why"] = why
    elif verdict == Verdict.VIOLATED:  # the bracket refutes it: its witness and parameter sets show it
        certified = None if lhs.certified is None or not np.isfinite(lhs.certified) else float(lhs.certified)
        counterexample = {"kind": "bound-bracket", "data": {
            "id": check_id, "scene": scene.name, "description": scene.description, "factor": k, "sense": sense,
            "chain": scene.chain.to_data(), "trajectory": trajectory_to_data(scene.trajectory),
            "witness": np.asarray(lhs.witness).tolist(), "observed": lhs.observed, "certified": certified,
            "bracket_sense": lhs.sense, "constant_upper": hi, "constant_lower": lo,
            **{key: np.asarray(v).tolist() for key, v in (replay or {}).items()}}}
        if replay:  # the file must show what the check saw: replay it before reporting it
            replayed = replay_bound_bracket(counterexample["data"], None)
            if replayed.verdict != Verdict.VIOLATED:
                why = (f"{why}; but on the parameter sets the check saves, the left-hand side at the witness is "
                       f"{replayed.evidence['value']['value']:.6g} and refutes nothing: the bracket's attained value "
                       f"was not computed on the scene's parameters")
                verdict, counterexample = Verdict.INCONCLUSIVE, None
                if pointwise["violated"]:
                    verdict, counterexample = Verdict.VIOLATED, pointwise["counterexample"]
                    why += "; the samples refute the bound"
                evidence["why"] = why
    return verdict, why, evidence, counterexample


def run_scenes(check_id, ctx, case, scenes, k=1.0):
    """One bound on several scenes: the first VIOLATED scene (else the first) leads the evidence."""
    verdicts, rows, first = [], {}, None
    for scene in scenes:
        ctx.progress(scene.name)
        verdict, why, evidence, cx = case(ctx, scene, k)
        verdicts.append(verdict)
        rows[scene.name] = evidence
        if first is None or (verdict == Verdict.VIOLATED and first[0] != Verdict.VIOLATED):
            first = (verdict, why, evidence, cx)
    verdict = combine(verdicts)
    c = first[2]["constants"]
    bound_word = "at most" if c["paper"]["kind"] == "upper_bound" else "at least"
    g = {key: shown(c[key]["value"]) for key in ("paper", "paper_observed", "certified", "observed")}
    summary = (f"on {', '.join(rows)}: paper's constant {bound_word} {g['paper']} (certified "
               f"ingredients; {g['paper_observed']} with observed ones), sharpest certified "
               f"{g['certified']}, worst observed {g['observed']}; {first[1]}")
    evidence = {**first[2], "scenes": rows, "key_step": key_step_evidence()}
    return Result(check_id, verdict, summary, evidence, counterexample=first[3] if verdict == Verdict.VIOLATED else None)


def shown(value):
    """A quantity's value in a summary: a number to 4 digits; "inf" and "nan" (JSON-ready) as themselves."""
    return value if isinstance(value, str) else f"{value:.4g}"


def key_step_evidence():
    """The key step's SDP certificate in evidence; it cites its ``key-step`` certificate (the Choi matrix) where
    the SDP found one."""
    found = key_step_proof()
    cited = {"certificate": cite(key_step_claim(found["choi"], found["lower"], found["upper"]))} if found["ok"] else {}
    return {**{k: v for k, v in found.items() if k != "choi"}, **cited}


def time_quantities(d, what):
    """Evidence of an ingredient over time (inertiaproof.bounds.time_extreme)."""
    inf = d["sense"] == "min"
    return {"quantity": what,
            "observed": quantity(d["observed"], "sampled", f"on a time grid, at t = {d['witness_time']:.4g}, body "
                                                           f"{d['body'] + 1}"),
            "certified": quantity(d["certified"], "lower_bound" if inf else "upper_bound", d["how"],
                                  certificate=d.get("certificate"))}


def sampled_bracket(value, chain, name, sense, ctx, scene, note):
    """A one-sided bracket from samples plus local search (no certified side)."""
    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    rng = ctx.rng(f"{scene.name}:{name}")
    q = lo + (hi - lo) * rng.random((ctx.profile.samples, chain.n))
    vals = value(q)
    sign = 1.0 if sense == "min" else -1.0
    top = np.argsort(sign * vals)[:8]
    qs, vs = local_search(value, q[top], lo, hi, free, sign=sign)
    j = int(np.argmin(sign * vs))
    return Bracket(name, sense, float(vs[j]), None, qs[j], [[0.0, None, None]], 0, note)


def time_and_configuration_bracket(value, ctx, scene, name, note, certified, certificate=None):
    """sup over (q, t) of value(q, t): samples of pairs, then a local search over q at the worst time; the certified
    side ``certified`` cites ``certificate``."""
    q, t = scene_samples(ctx, scene, name)
    vals = value(q, t)
    i = int(np.argmax(vals))
    chain = scene.chain
    lo, hi = search_box(chain)
    qs, vs = local_search(lambda qq: value(qq, np.full(len(qq), t[i])), q[i:i + 1], lo, hi,
                          free_coordinates(chain), sign=-1.0)
    best, witness = (float(vs[0]), qs[0]) if vs[0] > vals[i] else (float(vals[i]), q[i])
    cite = lambda side, *_: certificate if side == certified else None  # noqa: E731
    return Bracket(name, "max", best, certified, witness, [[0.0, best, float(certified)]], 0, note, cite), float(t[i])


def parameter_stack(trajectory, rate, count=64):
    """The parameter sets an extreme over time is taken over: the segment ends (payloads, scalings: exact), or
    ``count`` sampled times (moving masses)."""
    verts = parameter_vertices(trajectory)
    if verts is not None:
        return verts[1] if rate else verts[0]
    theta, theta_dot = trajectory.theta(trajectory.times(count))
    return theta_dot if rate else theta


def replay_bracket(data):
    """(value at the witness, the constant's bound it was compared with) recomputed from a saved file."""
    chain = Chain.from_data(data["chain"])
    q = np.asarray(data["witness"], float)[None]
    if "thetas" in data:
        m = composite.mass_matrix(chain, q[:, None], np.asarray(data["thetas"], float)[None])
        vals = spectral(m, data["spectral"])[0]
        value = vals.min() if data["spectral"] == "lmin" else vals.max()
    elif "psi_dot" in data:
        value = np.linalg.norm(lumped_acceleration_force(chain.body_jacobian(q), np.asarray(data["psi_dot"])[None]))
    else:
        h = lumped_velocity_matrix(chain.body_jacobian_derivative(q), np.asarray(data["psi"])[None])
        value = np.linalg.svd(h, compute_uv=False)[0, 0]
    bound = data["constant_upper"] if data["sense"] == "upper" else data["constant_lower"]
    return float(value), float(bound)


@replayer("bound-bracket")
def replay_bound_bracket(data, ctx):
    """Recompute the left-hand side at the saved witness on the saved parameter sets and compare it with the
    constant's bound and, where the file saves it, with the certified side of the bracket (an inverted bracket)."""
    value, bound = replay_bracket(data)
    upper = data["sense"] == "upper"

    def past(a, b, above):  # a beyond b (above or below) by more than the resolution
        return (a > b if above else a < b) and abs(a - b) > RESOLUTION * (abs(a) + abs(b))

    beyond = past(value, bound, upper)
    summary = (f"at the witness the left-hand side is {value:.6g}; the constant (factor {data['factor']:g}) is at "
               f"{'most' if upper else 'least'} {bound:.6g}")
    evidence = {"value": quantity(value, "value"), "bound": quantity(bound, "upper_bound" if upper else "lower_bound")}
    certified = data.get("certified")
    refuted = False
    if certified is not None and np.isfinite(float(certified)):
        certified = float(certified)
        above = data.get("bracket_sense", "max" if upper else "min") == "max"
        refuted = past(value, certified, above)
        summary += (f"; the certified {'upper' if above else 'lower'} side of the extreme is {certified:.6g}"
                    + (", beyond the value at the witness: the certificate is refuted" if refuted else ""))
        evidence["certified"] = quantity(certified, "upper_bound" if above else "lower_bound")
    verdict = Verdict.VIOLATED if beyond or refuted else Verdict.HOLDS
    return Result(data["id"], verdict, summary, evidence)
