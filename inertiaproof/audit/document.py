"""``inertiaproof audit ROBOT.urdf|MODEL.xml|DIR ...``: physical consistency and mass-matrix bounds of real robots.

Per link (URDF :mod:`.urdf`, MJCF :mod:`.mjcf`): the verdict of
``physical_consistency`` on the inertial as written (mass, and the inertia
about the CoM; Theorem 1), where its element stands in the file
(:mod:`.locate`), what MuJoCo, Drake, PyBullet and Gazebo do with it
(:mod:`.engines`), the signs of common authoring mistakes
(:mod:`inertiaproof.audit.mistakes`) and, where it is not consistent, the
nearest consistent inertia (:mod:`inertiaproof.audit.repair`) with the
element's replacement text (:mod:`.rewrite`).
Per movable joint: the body the mass matrix sees (its child link and the
links fixed to it). Per chain (:mod:`inertiaproof.audit.kinematic_tree`): the
eigenvalue extremes of M(q) over the file's joint limits
(:func:`chain_bounds`) and whether M(q) can become singular
(:mod:`inertiaproof.bounds.singular`).

Exit status: 0 every moving link and every body is consistent; 1 some is not,
or some URDF ``<inertial>`` has a problem that urdfdom reads past (``problems``,
each with its line: :class:`inertiaproof.audit.urdf.Problem`); 2 some input
could not be read (the others are still audited; its ``location`` is the line
of the error, where the reader has one). A file whose total mass is not the expected (``--expect-mass``,
:mod:`.total_mass`) is 1 too; with a baseline (``--baseline``, :mod:`.baseline`) 1 counts only the new and
updated errors (``findings`` lists every finding with its ``baseline_state``). A link moves
when a movable joint moves it; a massless frame (no mass, no inertia) is not
a body and is not judged, but a body made only of massless frames is. The
counts (``counts``, ``not_judged``, ``body_counts`` per file; ``summary``)
keep the judged links and bodies apart from the rest: MuJoCo joint frames,
massless frames and bases, links of a fixed base.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

import numpy as np

from inertiaproof.bounds.constants import mass_matrix_bounds
from inertiaproof.bounds.singular import singularity
from inertiaproof.errors import InputError
from inertiaproof.model.consistency import CONSISTENT, LABELS, physical_consistency
from inertiaproof.result import quantity

from .annotations import keyed_findings
from .baseline import COUNTED, STATES, compare
from .bodies_inside import DENSEST
from .engines import MJ_MINVAL, engine_column, unread_column
from .kinematic_tree import LEFT_OUT, kinematic_tree
from .mesh_bodies import link_findings
from .mistakes import diagnose, entries
from .mirror_twins import mirror_twins
from .mjcf import is_mjcf, read_mjcf
from .mjcf_geometry import with_mujoco
from .repair import DEFAULT_SLACK, nearest_consistent_inertia, written_inertia
from .sdf import is_sdf, read_sdf, sdf_inertial_text
from .rewrite import replacement
from .total_mass import check_total_mass
from .urdf import read_urdf
from .xacro_files import is_xacro, read_xacro

__all__ = [
    "audit_paths", "audit_robot", "BOUNDS_MODES", "chain_bounds", "document", "exit_status",
    "is_serial_arm", "listed_findings", "NOT_JUDGED_LINKS", "read_robot", "SCHEMA",
]

SCHEMA = "inertiaproof.audit/1"
BOUNDS_MODES = ("arms", "all", "none")
NOT_JUDGED_LINKS = ("joint_frames", "massless_frames", "fixed_base")  # why a link is not judged, in that order

def chain_bounds(chain, theta, *, samples, rounds, seed=0):
    """Theorems 2 and 3 on one chain over its joint limits, from :func:`inertiaproof.bounds.mass_matrix_bounds`.

    ``lambda_min`` is the side that decides whether M(q) can become singular:
    the certified lower bound of inf_q lambda_min(M(q)) when it is positive,
    else the smallest sampled value (an upper estimate of the infimum).
    ``lambda_max`` is the largest sampled value (a lower estimate of the
    supremum); the certified sides, alpha1 and alpha2 (the paper's constant and
    the sharpest certified one) come as further quantities.
    ``samples`` and ``rounds`` are the per-chain budget (a profile's ``audit_samples``, ``audit_rounds``).
    """
    found = mass_matrix_bounds(chain, theta, samples=samples, rounds=rounds,
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

def audit_robot(robot, *, samples, rounds, bounds="arms", floating_base=False, slack=DEFAULT_SLACK, seed=0,
                max_density=DENSEST, packages=None, full_chains=None, quick_rounds=None):
    """The audit of one parsed robot as a JSON-ready dict (see README, ``inertiaproof audit``); with ``full_chains``
    (a count) only that many chains, in the tree's order, get the budget of ``rounds``, the others that of
    ``quick_rounds`` (each chain's ``bounds_rounds`` and a warning say which); ``max_density``
    (kg/m^3) is the premise of the theorems on the bodies inside each link's geometry (:mod:`.bodies_inside`: URDF
    and SDFormat shapes, MJCF geoms by :mod:`.mjcf_geometry`, which also holds a declared MJCF inertial against
    MuJoCo's own inertia from the geoms)."""
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
    engine_moving = {j.child for j in robot.joints if j.type in LEFT_OUT}
    unread = {}  # link -> whether an element or attribute of its <inertial> is missing
    for problem in robot.problems:
        unread[problem.link] = unread.get(problem.link, False) or problem.missing
    for k, link in enumerate(links):
        role, anchor = tree.role(link.name)
        source = robot.sources.get(link.name)
        joint_frame = source is not None and source.kind == "joint_frame"
        moving = role != "base" or floating_base
        entry = {"role": "joint_frame" if joint_frame else role, "group": anchor, "moving": moving,
                 "massless_frame": bool(massless[k]), "source": None if source is None else source.kind,
                 "location": _location(source)}
        entry.update(rows[k])
        entry["inertial"] = None if written[k] is None else {
            "mass": written[k].mass, "com": written[k].com.tolist(), "inertia": entries(written[k].inertia)}
        entry["signs"] = signs[k]
        entry["hypotheses_tested"] = tested[k]
        entry["engines"] = unread_column(unread[link.name], fmt=robot.format) if link.name in unread else \
            None if written[k] is None or joint_frame else engine_column(
            mass[k], inertia[k], fmt=robot.format, moving=role == "body" or link.name in engine_moving,
            rescued=_rescued(tree.groups[anchor], link.name, links), lumped=role == "merged",
            full=source is None or source.kind in ("urdf", "fullinertia"), compiler=robot.compiler,
            from_geoms=source is not None and source.kind == "geoms")
        entry["repair"] = _repair(mass[k], inertia[k], slack, source) \
            if rows[k]["verdict"] != "consistent" and not massless[k] else None
        entry["bodies_inside"] = link_findings(link.name, written[k], robot.geometry.get(link.name),
                                               max_density=max_density, packages=packages) \
            if robot.format in ("urdf", "sdf", "mjcf") else None  # packages: --package NAME=DIR, for mesh URIs
        if robot.format == "sdf" and (entry["bodies_inside"] or {}).get("uniform"):  # the proposal as SDFormat
            uniform = entry["bodies_inside"]["uniform"]
            uniform["text"] = sdf_inertial_text(uniform["text"])
        if robot.format == "mjcf":  # against MuJoCo's own inertia from the geoms (:mod:`.mjcf_geometry`)
            entry["bodies_inside"] = with_mujoco(link.name, written[k], robot.geometry.get(link.name),
                                                 entry["bodies_inside"])
        if moving and not massless[k]:
            judged.append((link.name, rows[k]["verdict"]))
        link_out[link.name] = entry

    frames = {name for name, src in robot.sources.items() if src.kind == "joint_frame"}
    body_out = _bodies(tree, links, verdicts, massless, floating_base, frames)
    judged += [(f"body {name}", b["verdict"]) for name, b in body_out.items() if b["judged"]]
    chains_out, arm = {}, is_serial_arm(tree.chains)
    capped = (full_chains is not None and quick_rounds is not None and quick_rounds < rounds
              and len(tree.chains) > full_chains)
    cap = {"full_chains": full_chains, "chains": len(tree.chains), "full_rounds": rounds, "quick_rounds": quick_rounds,
           "note": f"--bounds {bounds}: {full_chains} of the {len(tree.chains)} chains (the first in the tree's order) "
                   f"bounded with the full budget ({rounds:g} rounds per bracket), the other "
                   f"{len(tree.chains) - full_chains} with the quick one ({quick_rounds:g} rounds: no pivot ladders, "
                   "certified sides looser); the profile's audit_full_chains"} if capped else None
    for index, sc in enumerate(tree.chains):
        names = [b.anchor for b in sc.bodies]
        codes = [LABELS.index(body_out[name]["verdict"]) for name in names]
        want = bounds == "all" or (bounds == "arms" and arm)
        chain_rounds = quick_rounds if capped and index >= full_chains else rounds
        found = chain_bounds(sc.chain, sc.theta, samples=samples, rounds=chain_rounds, seed=seed) if want else None
        chains_out[sc.bodies[-1].anchor] = {
            "name": sc.name,
            "joints": [j.name for j in sc.chain.joints],
            "kinds": sc.chain.kinds,
            "limits": [list(j.limits) if j.limits is not None else None for j in sc.chain.joints],
            "bodies": names,
            "bodies_consistent": all(c == CONSISTENT for c in codes),
            "bounds": found,
            **({"bounds_rounds": chain_rounds} if capped and want else {}),
            "singular": _singularity(sc, codes, names, found, frames),
        }
    not_consistent = [name for name, v in judged if v != "consistent"]
    judged_links = {name for name, _ in judged if name in link_out}
    apart = {kind: 0 for kind in NOT_JUDGED_LINKS}
    for name, entry in link_out.items():
        if name not in judged_links:
            apart["joint_frames" if entry["role"] == "joint_frame" else
                  "massless_frames" if entry["massless_frame"] else "fixed_base"] += 1
    judged_bodies = [b["verdict"] for b in body_out.values() if b["judged"]]
    return {
        "status": "ok",
        "robot": robot.name,
        "format": robot.format,
        "warnings": list(robot.warnings) + ([cap["note"]] if capped else []),  # the CLI prints them on stderr
        **({"bounds_cap": cap} if capped else {}),  # chains beyond the profile's count of fully bounded ones
        "problems": [{"link": p.link, "kind": p.kind, "message": p.message, "reads": p.reads,
                      "location": _region(robot.path, p.span, p.expanded)} for p in robot.problems],
        "geometry_errors": [f"{name}: {found['rule']}" for name, entry in link_out.items() if entry["moving"]
                            for found in (entry["bodies_inside"] or {}).get("findings", ()) if found["hard"]],
        "serial_arm": arm,
        "consistent": not not_consistent,
        "not_consistent": not_consistent,
        "left_out_joints": [{"joint": name, "type": kind, "reason": f"{kind} joints are reported and left out; "
                             "their child is treated as a fixed base"} for name, kind in tree.left_out],
        "joint_frames": sorted(frames),
        "mimic_joints": [{"joint": j.name, "mimics": j.mimic} for j in robot.joints if j.mimic is not None],
        "counts": {label: sum(v == label for name, v in judged if name in link_out) for label in LABELS}
        | {"not_judged": len(link_out) - len(judged_links)},
        "not_judged": apart,  # the links not judged, by why: joint frames, massless frames, links of a fixed base
        "body_counts": {label: judged_bodies.count(label) for label in LABELS}
        | {"not_judged": len(body_out) - len(judged_bodies)},
        "links": link_out,
        "bodies": body_out,
        "chains": chains_out,
        "mirror_twins": mirror_twins(robot),  # left/right pairs placed mirrored (:mod:`.mirror_twins`; soft)
    }


def _singularity(sc, codes, names, bounds, frames):
    """Whether M(q) can become singular; a chain through joint frames by the MuJoCo bodies they belong to.

    QJ is block lower triangular in the MuJoCo bodies along the chain (the
    joints of body k move bodies k.. and none before), so with every body
    consistent (Z >= lambda_min(f) I, Theorem 2's key step) M(q) > 0 at every
    q when each body's own joint twists are independent at every q: a single
    hinge, or two with axes not parallel (a rotation about one axis keeps the
    angle to the other), and slides with independent axes and no hinge
    between them (their directions then keep their relative place). Anything
    else (three hinges can lock like gimbals) falls back to
    :func:`~inertiaproof.bounds.singular.singularity`.
    """
    if not frames.intersection(names):
        return singularity(sc.chain, sc.theta, codes, names, bounds)
    groups, run = [], []
    for k, name in enumerate(names):
        run.append(k)
        if name not in frames:
            groups.append(run)
            run = []
    bad = [names[g[-1]] for g in groups if codes[g[-1]] != CONSISTENT]
    locking = [names[g[-1]] for g in groups if not _independent([sc.chain.joints[k] for k in g])]
    if not bad and not locking:
        return {"verdict": "never",
                "argument": "every MuJoCo body has f(Phi) > 0 (Theorem 2, key step) and the joints of each body have "
                            "independent twists at every q (one hinge or two with axes not parallel; slides with "
                            "independent axes), so QJ(q) has full column rank: M(q) > 0 for all q"}
    answer = singularity(sc.chain, sc.theta, codes, names, bounds)
    if answer["verdict"] == "not_excluded":
        why = [f"bodies {', '.join(bad)} are not consistent"] if bad else []
        why += [f"the joints of {', '.join(locking)} can lose independent twists (three hinges can lock like a "
                "gimbal; slides split by a hinge turn with it)"] if locking else []
        answer.update(bodies_not_consistent=bad, argument="; ".join(why) + ": the structural argument does not apply")
    return answer


def _independent(joints):
    """The twists of one MuJoCo body's joints (axes in one frame: joint frames differ by translations) are
    independent at every q: see :func:`_singularity`."""
    hinges = [np.asarray(j.axis, float) for j in joints if j.revolute]
    slides = [np.asarray(j.axis, float) for j in joints if not j.revolute]
    if len(hinges) > 2 or not re.fullmatch("h*s*h*", "".join("h" if j.revolute else "s" for j in joints)):
        return False
    if len(hinges) == 2 and np.linalg.norm(np.cross(*hinges)) <= 1e-9 * np.linalg.norm(hinges[0]) * np.linalg.norm(hinges[1]):
        return False
    return not slides or np.linalg.matrix_rank(np.array(slides), tol=1e-9) == len(slides)


def _location(source):
    """Where the link's inertia element stands: file, line, and column and end where the markup was paired."""
    return None if source is None else _region(source.path, source.span, source.expanded)


def _region(path, span, expanded=None, line=None):
    """{"path", ["expanded",] "startLine", ...} of a span (or of a ``line`` alone) in a file, or None.

    ``expanded``: the lines are those of the text it names (e.g. what `xacro FILE` prints), not of the file."""
    if span is None and line is None:
        return None
    region = span.region() if span is not None else {"startLine": line}
    return {"path": str(path), **({"expanded": expanded} if expanded else {}), **region}


def _rescued(group, name, links):
    """MuJoCo: a link welded to ``name`` in its group carries mass and inertia above mjMINVAL."""
    for link in links:
        if link.name in group.links and link.name != name and link.inertial is not None:
            if link.inertial.mass >= MJ_MINVAL and np.linalg.eigvalsh(link.inertial.inertia)[0] >= MJ_MINVAL:
                return True
    return False


def _repair(mass, inertia, slack, source):
    """The nearest consistent inertia, its entries as written (consistent as printed) and the element's new text."""
    r = nearest_consistent_inertia(mass, inertia, slack)
    out = {"note": r.note, "inertia": None if r.inertia is None else entries(r.inertia), "written": None,
           "replacement": None}
    if r.inertia is not None:
        written = written_inertia(mass, r.inertia, slack)
        if written is not None:
            out["written"] = written[0]
            out["written_slack_rel"] = quantity(written[1], "margin", "triangle slack of the numbers as written, "
                                                "relative to tr(I_CoM)")
            if source is not None and source.span is not None and source.span.column is not None \
                    and source.kind in ("urdf", "sdf", "diaginertia", "fullinertia") and not source.expanded:
                out["replacement"] = {"path": source.path, **source.span.region(), "start": source.span.start,
                                      "end": source.span.end, "text": replacement(source, written[0])}
        out.update(
            change_frobenius_rel=quantity(r.change_frobenius_rel, "value", "||I - W||_F / ||W||_F"),
            change_spectral=quantity(r.change_spectral, "value", "||I - W||_2: bound on the change of 1/2 w^T I w per |w|^2/2",
                                     unit="kg m^2"),
            triangle_slack_rel=quantity(r.triangle_slack, "margin", "of the suggestion, relative to tr(I_CoM)"),
            principal_moments_before=quantity(np.linalg.eigvalsh(inertia), "value", "as written", unit="kg m^2"),
            principal_moments_after=quantity(np.linalg.eigvalsh(r.inertia), "value", "suggested", unit="kg m^2"),
        )
    return out


def _bodies(tree, links, verdicts, massless, floating_base, frames=()):
    """The verdict of every group the mass matrix sees: exact as written when one link carries all the mass.

    A joint frame (between two joints of one MJCF body) is not a body and is not judged; nor is a base without
    mass (a world frame, a floating base's massless root: the free coordinates move the whole robot, whose mass
    is elsewhere)."""
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
        if g.anchor in frames:
            reason = "a frame between two joints of one MuJoCo body, not a body"
        elif not massive and not g.is_body:
            reason = "no link of the base carries mass: a frame, not a body"
        elif not massive:
            reason = "no link of the body carries mass"
        out[g.anchor] = {"joint": g.joint, "links": list(g.links), "massless": not massive, "verdict": verdict,
                         "reason": reason, "mass": quantity(g.phi[0], "value", unit="kg"),
                         "judged": (g.is_body or (floating_base and bool(massive))) and g.anchor not in frames}
    return out


def read_robot(path, xacro_args=None):
    """A URDF or MJCF file (MJCF: a root element ``<mujoco>``), or a xacro file expanded into a URDF, read into
    links and joints."""
    if is_xacro(path):
        return read_xacro(path, xacro_args)
    if Path(path).suffix.lower() == ".sdf" or (Path(path).suffix.lower() != ".urdf" and is_sdf(path)):
        return read_sdf(path)
    return read_mjcf(path) if Path(path).suffix.lower() != ".urdf" and is_mjcf(path) else read_urdf(path)


def audit_paths(paths, executor=None, **options):
    """Every robot under ``paths`` (files, or folders searched for *.urdf and MJCF *.xml; a *.xacro file given by
    name is expanded with ``options["xacro_args"]``): {path: entry}.

    The files are audited as independent tasks of ``executor`` (:mod:`inertiaproof.suite.execution`; default: one
    after the other in this process), and listed in the order of ``paths`` whatever order they finish in."""
    files, todo = {}, []
    for path in map(Path, paths):
        if path.is_dir():
            found = sorted([*path.rglob("*.urdf"), *(p for p in path.rglob("*.xml") if is_mjcf(p)),
                            *path.rglob("*.sdf")])
            if not found:
                files[str(path)] = {"status": "error",
                                    "error": f"{path}: no *.urdf, MJCF *.xml or SDFormat *.sdf files in this folder"}
            for f in found:
                files[str(f)] = None
                todo.append(f)
        else:
            files[str(path)] = None
            todo.append(path)
    if executor is None:
        from inertiaproof.suite.execution import Executor

        executor = Executor()
    done = executor.map(functools.partial(_audit_task, options), todo, kind="audit", label="audit")
    for path, entry in zip(todo, done):
        files[str(path)] = entry
    return files


def _audit_task(options, path):
    """One file's audit: a task for any worker."""
    with np.errstate(all="ignore"):
        return _audit_one(path, options)


def _audit_one(path, options):
    options = dict(options)
    xacro_args = options.pop("xacro_args", None)
    try:
        return audit_robot(read_robot(path, xacro_args), **options)
    except InputError as exc:
        where = _region(path, None, getattr(exc, "expanded", None), getattr(exc, "line", None))
        return {"status": "error", "error": str(exc), **({"location": where} if where else {})}
    except MemoryError:
        return {"status": "error", "error": f"{path}: out of memory: the audit needs more than its memory budget"}


def exit_status(files, findings=None):
    """2 some file cannot be read; 1 some moving link or body is not consistent, some file has a problem that
    the engines read past (:class:`.urdf.Problem`), some moving link has a hard finding on the bodies inside
    its geometry (``geometry_errors``, :mod:`.bodies_inside`) or some file's total mass is not the expected
    (``total_mass``, :mod:`.total_mass`); else 0.

    With a baseline (``findings`` carrying a ``baseline_state``, :mod:`.baseline`), 1 counts only the findings of
    level ``error`` that are ``new`` or ``updated``: the known ones are left to be fixed."""
    if any(f["status"] == "error" for f in files.values()):
        return 2
    if findings is not None and any("baseline_state" in found for found in findings):
        return int(any(found["level"] == "error" and found["baseline_state"] in COUNTED for found in findings))
    return 0 if all(f["consistent"] and not f.get("problems") and not f.get("geometry_errors")
                    and (f.get("total_mass") or {}).get("matches") is not False
                    for f in files.values()) else 1


def listed_findings(files, baseline=None):
    """Every finding of the audit (:func:`.annotations.keyed_findings`) as ``{"rule", "level", "file",
    "subject", "message", "location"}``, with ``baseline_state`` against a ``baseline`` (:func:`.baseline.
    read_baseline`); and the baseline's summary (counts per state, the absent findings) or None."""
    out = [{"rule": rule, "level": level, "file": path, "subject": subject, "message": message, "location": where}
           for rule, level, path, where, message, _, subject in keyed_findings({"files": files})]
    if baseline is None:
        return out, None
    states, absent = compare(out, baseline["findings"])
    for found, state in zip(out, states):
        found["baseline_state"] = state
    counts = {state: states.count(state) for state in STATES[:3]} | {"absent": len(absent)}
    return out, {"path": baseline["path"], "format": baseline["format"], "counts": counts,
                 "counted": sum(f["level"] == "error" and f["baseline_state"] in COUNTED for f in out),
                 "absent": [{"rule": b["rule"], "level": b["level"], "file": b["file"], "subject": b["subject"],
                             "message": b["message"], "baseline_state": "absent",
                             **({"sarif": b["result"]} if b.get("result") else {})} for b in absent]}


def document(files, *, profile, seed, bounds, floating_base, slack, runtime_s, versions, expected_mass=None,
             baseline=None):
    """The audit of ``files`` as one JSON-ready document (schema :data:`SCHEMA`).

    ``expected_mass``: :func:`.total_mass.parse_expectations` (``--expect-mass``; each readable file gets its
    ``total_mass``); ``baseline``: :func:`.baseline.read_baseline` (``--baseline``): every entry of ``findings``
    gets its ``baseline_state``, ``baseline`` lists the absent ones, and the exit status counts only the new and
    updated errors."""
    check_total_mass(files, expected_mass)
    listed, compared = listed_findings(files, baseline)

    ok = [f for f in files.values() if f["status"] == "ok"]
    signs, inside = {}, {}
    for f in ok:
        for link in f["links"].values():
            for s in link["signs"]:
                signs[s["sign"]] = signs.get(s["sign"], 0) + 1
            for found in (link.get("bodies_inside") or {}).get("findings", ()):
                inside[found["rule"]] = inside.get(found["rule"], 0) + 1
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
            "links": {label: sum(f["counts"][label] for f in ok) for label in (*LABELS, "not_judged")},
            "links_not_judged": {kind: sum(f["not_judged"][kind] for f in ok) for kind in NOT_JUDGED_LINKS},
            "bodies": {label: sum(f["body_counts"][label] for f in ok) for label in (*LABELS, "not_judged")},
            "moving_not_consistent": sum(len(f["not_consistent"]) for f in ok),
            "problems": sum(len(f.get("problems", ())) for f in ok),
            "signs": signs,
            "bodies_inside": inside,  # links per finding of :mod:`.bodies_inside`, moving or not
            "geometry_errors": sum(len(f.get("geometry_errors", ())) for f in ok),
            "mass_mismatches": sum((f.get("total_mass") or {}).get("matches") is False for f in ok),
            "mirror_twins": {"pairs": sum(len((f.get("mirror_twins") or {}).get("pairs", ())) for f in ok),
                             "mismatches": sum((f.get("mirror_twins") or {}).get("mismatches", 0) for f in ok)},
            **({"baseline": {k: compared[k] for k in ("path", "counts", "counted")}} if compared else {}),
            "exit_status": exit_status(files, listed),
        },
        "expected_mass": expected_mass,
        "files": files,
        "findings": listed,  # every finding, as SARIF and the annotations give them (with baseline_state)
        **({"baseline": compared} if compared else {}),
    }
