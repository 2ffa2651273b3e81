"""``inertiaproof audit ROBOT.urdf|DIR ...``: physical consistency and mass-matrix bounds of real robots.

Per link: the verdict of ``physical_consistency`` on the ``<inertial>`` as
written (mass, and the inertia about the CoM; Theorem 1), the signs of
common authoring mistakes (:mod:`inertiaproof.audit.mistakes`) and, where it is not
consistent, the nearest consistent inertia (:mod:`inertiaproof.audit.repair`).
Per movable joint: the body the mass matrix sees (its child link and the
links fixed to it). Per chain (:mod:`inertiaproof.audit.kinematic_tree`): the
eigenvalue extremes of M(q) over the file's joint limits
(:func:`chain_bounds`) and whether M(q) can become singular
(:mod:`inertiaproof.bounds.singular`).

Exit status: 0 every moving link and every body is consistent; 1 some is not;
2 some input could not be read (the others are still audited). A link moves
when a movable joint moves it; a massless frame (no mass, no inertia) is not
a body and is not judged, but a body made only of massless frames is.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from inertiaproof.bounds.constants import mass_matrix_bounds
from inertiaproof.bounds.singular import singularity
from inertiaproof.errors import InputError
from inertiaproof.model.consistency import CONSISTENT, LABELS, physical_consistency
from inertiaproof.result import quantity
from inertiaproof.suite.profiles import PROFILES

from .kinematic_tree import kinematic_tree
from .mistakes import diagnose, entries
from .repair import DEFAULT_SLACK, nearest_consistent_inertia
from .urdf import read_urdf

__all__ = [
    "audit_paths", "audit_robot", "audit_urdf", "BOUNDS_MODES", "chain_bounds", "document", "exit_status", "is_serial_arm",
    "SCHEMA",
]

SCHEMA = "inertiaproof.audit/1"
BOUNDS_MODES = ("arms", "all", "none")
def chain_bounds(chain, theta, *, samples, refine_s, seed=0):
    """Theorems 2 and 3 on one chain over its joint limits, from :func:`inertiaproof.bounds.mass_matrix_bounds`.

    ``lambda_min`` is the side that decides whether M(q) can become singular:
    the certified lower bound of inf_q lambda_min(M(q)) when it is positive,
    else the smallest sampled value (an upper estimate of the infimum).
    ``lambda_max`` is the largest sampled value (a lower estimate of the
    supremum); the certified sides, alpha1 and alpha2 (the paper's constant and
    the sharpest certified one) come as further quantities.
    ``samples`` and ``refine_s`` are the per-chain budget (a profile's ``audit_samples``, ``audit_refine_s``).
    """
    found = mass_matrix_bounds(chain, theta, samples=samples, refine_s=refine_s,
                               rng=np.random.default_rng(seed))
    low, high = found["lower"], found["upper"]
    m_low, m_high = low["observed"], high["observed"]
    sampled_min = quantity(m_low["upper"], "sampled", "smallest sampled lambda_min(M(q)): an upper estimate of the inf")
    certified_min = quantity(m_low["lower"], "lower_bound", "certified lower bound of inf_q lambda_min(M(q))")
    return {
        "lambda_min": certified_min if m_low["lower"] > 0 else sampled_min,
        "lambda_min_q": m_low["witness"],
        "lambda_max": quantity(m_high["lower"], "sampled", "largest sampled lambda_max(M(q)): a lower estimate of the sup"),
        "lambda_max_q": m_high["witness"],
        "inf_lambda_min_certified": certified_min,
        "inf_lambda_min_sampled": sampled_min,
        "sup_lambda_max_certified": quantity(m_high["upper"], "upper_bound",
                                             "certified upper bound of sup_q lambda_max(M(q))"),
        "alpha1_paper_lower": quantity(low["paper"]["lower"], "lower_bound",
                                       "the paper's alpha1 (LowerBoundedness) from certified ingredients"),
        "alpha1_paper_upper": quantity(low["paper"]["upper"], "estimate",
                                       "the paper's alpha1 from observed ingredients: an upper estimate"),
        "alpha1_certified": quantity(low["certified"]["value"], "certified_constant", low["certified"]["how"]),
        "alpha2_paper_lower": quantity(high["paper"]["lower"], "estimate",
                                       "the paper's alpha2 (UpperBoundedness) from observed ingredients: a lower estimate"),
        "alpha2_paper_upper": quantity(high["paper"]["upper"], "upper_bound",
                                       "the paper's alpha2 from certified ingredients"),
        "alpha2_certified": quantity(high["certified"]["value"], "certified_constant", high["certified"]["how"]),
        "resolution": quantity(8 * chain.n * np.finfo(float).eps * abs(m_high["lower"]), "tolerance",
                               "rounding of eigvalsh: 8 n eps lambda_max"),
    }


def is_serial_arm(chains):
    """A serial arm, possibly with a parallel gripper: its chains differ at most in their last joint."""
    prefixes = {tuple(j.name for j in c.chain.joints[:-1]) for c in chains}
    return len(chains) > 0 and len(prefixes) == 1


# -- one file ------------------------------------------------------------------

def audit_robot(robot, *, samples, refine_s, bounds="arms", floating_base=False, slack=DEFAULT_SLACK, seed=0):
    """The audit of one parsed robot as a JSON-ready dict (see README, ``inertiaproof audit``)."""
    tree = kinematic_tree(robot)
    links = robot.links
    written = [link.inertial for link in links]
    mass = np.array([0.0 if w is None else w.mass for w in written])
    inertia = np.array([np.zeros((3, 3)) if w is None else w.inertia for w in written])
    offset = np.array([np.zeros(3) if w is None else w.rotation.T @ w.com for w in written])
    phi = np.array([np.zeros(10) if w is None else w.phi_at_com for w in written])
    verdicts = physical_consistency(phi, written=[(None,) * 10 if w is None or w.written is None
                                                  else w.phi_at_com_written for w in written])
    rows = list(verdicts.rows())
    signs, tested = diagnose(mass, inertia, offset, verdicts.verdict)
    massless = ~phi.any(axis=1)

    link_out, judged = {}, []
    for k, link in enumerate(links):
        role, anchor = tree.role(link.name)
        moving = role != "base" or floating_base
        entry = {"role": role, "group": anchor, "moving": moving, "massless_frame": bool(massless[k])}
        entry.update(rows[k])
        entry["inertial"] = None if written[k] is None else {
            "mass": written[k].mass, "com": written[k].com.tolist(), "inertia": entries(written[k].inertia)}
        entry["signs"] = signs[k]
        entry["hypotheses_tested"] = tested[k]
        entry["repair"] = _repair(mass[k], inertia[k], slack) if rows[k]["verdict"] != "consistent" and not massless[k] else None
        if moving and not massless[k]:
            judged.append((link.name, rows[k]["verdict"]))
        link_out[link.name] = entry

    body_out = _bodies(tree, links, verdicts, massless, floating_base)
    judged += [(f"body {name}", b["verdict"]) for name, b in body_out.items() if b["judged"]]
    chains_out, arm = {}, is_serial_arm(tree.chains)
    for sc in tree.chains:
        names = [b.anchor for b in sc.bodies]
        codes = [LABELS.index(body_out[name]["verdict"]) for name in names]
        want = bounds == "all" or (bounds == "arms" and arm)
        found = chain_bounds(sc.chain, sc.theta, samples=samples, refine_s=refine_s, seed=seed) if want else None
        chains_out[sc.bodies[-1].anchor] = {
            "name": sc.name,
            "joints": [j.name for j in sc.chain.joints],
            "kinds": sc.chain.kinds,
            "limits": [list(j.limits) if j.limits is not None else None for j in sc.chain.joints],
            "bodies": names,
            "bodies_consistent": all(c == CONSISTENT for c in codes),
            "bounds": found,
            "singular": singularity(sc.chain, sc.theta, codes, names, found),
        }
    not_consistent = [name for name, v in judged if v != "consistent"]
    return {
        "status": "ok",
        "robot": robot.name,
        "warnings": list(robot.warnings),
        "serial_arm": arm,
        "consistent": not not_consistent,
        "not_consistent": not_consistent,
        "left_out_joints": [{"joint": name, "type": kind, "reason": f"{kind} joints are reported and left out; "
                             "their child is treated as a fixed base"} for name, kind in tree.left_out],
        "mimic_joints": [{"joint": j.name, "mimics": j.mimic} for j in robot.joints if j.mimic is not None],
        "counts": {label: int(np.sum(verdicts.verdict == code)) for code, label in enumerate(LABELS)},
        "links": link_out,
        "bodies": body_out,
        "chains": chains_out,
    }


def _repair(mass, inertia, slack):
    r = nearest_consistent_inertia(mass, inertia, slack)
    out = {"note": r.note, "inertia": None if r.inertia is None else entries(r.inertia)}
    if r.inertia is not None:
        out.update(
            change_frobenius_rel=quantity(r.change_frobenius_rel, "value", "||I - W||_F / ||W||_F"),
            change_spectral=quantity(r.change_spectral, "value", "||I - W||_2: bound on the change of 1/2 w^T I w per |w|^2/2",
                                     unit="kg m^2"),
            triangle_slack_rel=quantity(r.triangle_slack, "margin", "of the suggestion, relative to tr(I_CoM)"),
            principal_moments_before=quantity(np.linalg.eigvalsh(inertia), "value", "as written", unit="kg m^2"),
            principal_moments_after=quantity(np.linalg.eigvalsh(r.inertia), "value", "suggested", unit="kg m^2"),
        )
    return out


def _bodies(tree, links, verdicts, massless, floating_base):
    """The verdict of every group the mass matrix sees: exact as written when one link carries all the mass."""
    index = {link.name: k for k, link in enumerate(links)}
    groups = [g for g in tree.groups.values() if g.is_body or floating_base]
    summed = physical_consistency(np.array([g.phi for g in groups])) if groups else None
    out = {}
    for i, g in enumerate(groups):
        massive = [index[name] for name in g.links if not massless[index[name]]]
        if len(massive) == 1:
            k = massive[0]
            verdict, reason = LABELS[verdicts.verdict.flat[k]], verdicts.reason(k)
        else:
            verdict, reason = LABELS[summed.verdict[i]], summed.reason(i)
        out[g.anchor] = {"joint": g.joint, "links": list(g.links), "massless": not massive,
                         "verdict": verdict, "reason": reason if massive else "no link of the body carries mass",
                         "mass": quantity(g.phi[0], "value", unit="kg"), "judged": g.is_body or floating_base}
    return out


def audit_paths(paths, **options):
    """Every URDF under ``paths`` (files, or folders searched for *.urdf): {path: entry}."""
    files = {}
    for path in map(Path, paths):
        if path.is_dir():
            found = sorted(path.rglob("*.urdf"))
            if not found:
                files[str(path)] = {"status": "error", "error": f"{path}: no *.urdf files in this folder"}
            for f in found:
                files[str(f)] = _audit_one(f, options)
        else:
            files[str(path)] = _audit_one(path, options)
    return files


def audit_urdf(path, *, profile="ci", bounds="arms", floating_base=False, slack=DEFAULT_SLACK, seed=0):
    """The audit of one URDF file as a JSON-ready dict (README, ``inertiaproof audit``); its chains get the
    per-chain budget of ``profile`` (``audit_samples``, ``audit_refine_s``). Raises InputError on a bad file."""
    budget = PROFILES[profile]
    with np.errstate(all="ignore"):
        return audit_robot(read_urdf(path), samples=budget.audit_samples, refine_s=budget.audit_refine_s,
                           bounds=bounds, floating_base=floating_base, slack=slack, seed=seed)


def _audit_one(path, options):
    try:
        return audit_robot(read_urdf(path), **options)
    except InputError as exc:
        return {"status": "error", "error": str(exc)}
    except MemoryError:
        return {"status": "error", "error": f"{path}: out of memory: the audit needs more than its memory budget"}


def exit_status(files):
    if any(f["status"] == "error" for f in files.values()):
        return 2
    return 0 if all(f["consistent"] for f in files.values()) else 1


def document(files, *, profile, seed, bounds, floating_base, slack, runtime_s, versions):

    ok = [f for f in files.values() if f["status"] == "ok"]
    signs = {}
    for f in ok:
        for link in f["links"].values():
            for s in link["signs"]:
                signs[s["sign"]] = signs.get(s["sign"], 0) + 1
    return {
        "schema": SCHEMA,
        "profile": profile, "seed": seed, "bounds": bounds, "floating_base": floating_base, "repair_slack": slack,
        "runtime_s": runtime_s,
        "versions": versions,
        "summary": {
            "files": len(files),
            "unreadable": len(files) - len(ok),
            "files_consistent": sum(f["consistent"] for f in ok),
            "files_not_consistent": sum(not f["consistent"] for f in ok),
            "links": {label: sum(f["counts"][label] for f in ok) for label in LABELS},
            "moving_not_consistent": sum(len(f["not_consistent"]) for f in ok),
            "signs": signs,
            "exit_status": exit_status(files),
        },
        "files": files,
    }
