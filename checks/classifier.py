"""The classifier attacked at its boundary: physical_consistency against an exact decision (Def1, Thm1, Thm1-boundary).

``physical_consistency`` gives users their verdicts (``inertiaproof inertia``,
the audit, scenes). Here its public API is fed rows on both sides of the
boundary of Theorem 1 and on it (:mod:`inertiaproof.counterexamples.classifier`:
relatively inconsistent or consistent by 1e-15 .. 1e-3, exactly degenerate
point, line and planar masses and their ulp moves, non-positive masses, at
magnitudes 1e-150 .. 1e150), and every verdict is compared with this module's
own decision in rational arithmetic on the row's float values (a float is a
dyadic rational, so its exact value is the row as written):

    f(Phi) > 0                      consistent (Theorem 1)
    m > 0, f(Phi) >= 0 singular     degenerate, Sigma_CoM of rank rank(f) - 1 (Thm1-boundary)
    otherwise                       inconsistent

decided by LDL^T with symmetric pivoting in rational arithmetic
(:func:`~inertiaproof.model.positive_map.exact_psd`); nothing of
physical_consistency, its Schur complement or its exact fallback is used. Any disagreement, in
the label or in the rank of a degenerate row, is VIOLATED with the row as a
replayable counterexample. Wrong classifiers (one that accepts rows
inconsistent by 1e-6 relative, one that takes the boundary as consistent, one
that signs lambda_min(f) by eigvalsh alone) must disagree somewhere, else the
check is INCONCLUSIVE.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from inertiaproof.counterexamples.classifier import DELTAS, MAGNITUDE_BITS, boundary_rows, sweep

from inertiaproof.model.consistency import CONSISTENT, DEGENERATE, INCONSISTENT, LABELS, physical_consistency
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.model.positive_map import exact_psd
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "CLASSIFIER_CONTROLS", "classifier_result", "disagreements", "exact_classification", "exact_classifications",
    "replay_classifier_row", "verdicts_only",
]


def exact_classification(row):
    """(verdict code, rank of Sigma_CoM where degenerate else -1) of a finite float row, exactly."""
    m, h1, h2, h3, i11, i22, i33, i12, i23, i13 = (Fraction(float(x)) for x in row)
    if m <= 0:
        return INCONSISTENT, -1
    inertia = [[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]]
    half_trace = (i11 + i22 + i33) / 2
    h = (h1, h2, h3)
    f = [[(half_trace if i == j else 0) - inertia[i][j] for j in range(3)] + [h[i]] for i in range(3)] + [[*h, m]]
    psd, rank, _ = exact_psd(f)
    if not psd:
        return INCONSISTENT, -1
    return (CONSISTENT, -1) if rank == 4 else (DEGENERATE, rank - 1)


def verdicts_only(rows):
    """physical_consistency without the margins: the verdicts and ranks are the same, and a wrong verdict does not
    send every row through the exact margin (rational arithmetic, the costly part) before it is caught."""
    return physical_consistency(rows, margins=False)


def _classifier_answers(classify, rows):
    c = classify(rows)
    rank = np.where(c.verdict == DEGENERATE, c.degenerate_rank, -1)
    return np.asarray(c.verdict, int), np.asarray(rank, int)


def exact_classifications(rows):
    """(K, 2): :func:`exact_classification` of every row."""
    return np.array([exact_classification(r) for r in rows], dtype=int).reshape(-1, 2)


def disagreements(rows, classify=verdicts_only, exact=None):
    """(indices where ``classify`` and the exact decision differ, the exact (verdict, rank) per row, the
    classifier's verdicts and ranks); ``exact`` as :func:`exact_classifications` gives it (computed when None)."""
    exact = exact_classifications(rows) if exact is None else exact
    verdict, rank = _classifier_answers(classify, rows)
    bad = np.flatnonzero((verdict != exact[:, 0]) | (rank != exact[:, 1]))
    return bad, exact, (verdict, rank)


# -- wrong classifiers (negative controls), built on the public API -------------------------------------------

class _Verdicts:
    def __init__(self, verdict, rank):
        self.verdict, self.degenerate_rank = verdict, rank


def _loosened(rows):
    """Accepts rows inconsistent by up to 1e-6 of tr(Sigma_CoM) as consistent."""
    c = verdicts_only(rows)
    verdict = np.where((c.verdict == INCONSISTENT) & (c.mass > 0) & (c.triangle_slack > -1e-6), CONSISTENT, c.verdict)
    return _Verdicts(verdict, c.degenerate_rank)


def _boundary_consistent(rows):
    """Takes f >= 0 singular for consistent."""
    c = verdicts_only(rows)
    return _Verdicts(np.where(c.verdict == DEGENERATE, CONSISTENT, c.verdict), c.degenerate_rank)


def _eigvalsh_only(rows):
    """Signs lambda_min(f) by LAPACK's eigvalsh, no exact fallback; zero exactly is the boundary."""
    low = np.linalg.eigvalsh(pseudo_inertia(rows))[:, 0]
    verdict = np.where(low > 0, CONSISTENT, np.where(low == 0, DEGENERATE, INCONSISTENT))
    return _Verdicts(np.where(rows[:, 0] > 0, verdict, INCONSISTENT), verdicts_only(rows).degenerate_rank)


CLASSIFIER_CONTROLS = {
    "accepts rows inconsistent by 1e-6 relative": _loosened,
    "takes the boundary (f >= 0 singular) as consistent": _boundary_consistent,
    "signs lambda_min(f) by eigvalsh alone": _eigvalsh_only,
}


def _row_counterexample(row, exact, answer, about):
    return {"kind": "classifier-row", "data": {
        "phi": [float(x) for x in row], "about": about,
        "exact": {"verdict": LABELS[exact[0]], "rank": int(exact[1])},
        "classifier": {"verdict": LABELS[answer[0]], "rank": int(answer[1])}}}


def _counts(about, exact):
    out = {}
    for a, e in zip(about, exact):
        key = f"{a['family']} -> {LABELS[e[0]]}"
        out[key] = out.get(key, 0) + 1
    return {k: quantity(v, "count") for k, v in sorted(out.items())}


def classifier_result(ctx, classify=verdicts_only):
    """The sweep and the hunt against the exact decision; the controls on the sweep."""
    rows, about = sweep(ctx.rng("Thm1-boundary:classifier"), repeats=max(2, ctx.profile.examples // 30))
    exact = exact_classifications(rows)
    bad, _, answers = disagreements(rows, classify, exact)
    decided_exactly = int(np.sum(verdicts_only(rows).decided_exactly))
    counterexample = None
    if bad.size:
        i = bad[0]
        counterexample = _row_counterexample(rows[i], exact[i], (answers[0][i], answers[1][i]), about[i])

    def margin(example):
        row, _ = example
        b, e, _ = disagreements(row[None], classify)
        return -1.0 if b.size else 1.0

    found = hunt(boundary_rows(), margin, ctx, label="Thm1-boundary classifier")
    if found.violation is not None and counterexample is None:
        row, description = found.violation
        b, e, a = disagreements(row[None], classify)
        counterexample = _row_counterexample(row, e[0], (a[0][0], a[1][0]), description)
    controls = {label: bool(disagreements(rows, wrong, exact)[0].size) for label, wrong in CLASSIFIER_CONTROLS.items()}
    missed = [label for label, caught in controls.items() if not caught]
    evidence = {
        "method": "physical_consistency (public API, float64 rows) against an exact decision of f(Phi) >= 0 and its "
                  "rank by LDL^T with symmetric pivoting in rational arithmetic on the floats' exact values",
        "sweep": {"rows": quantity(len(rows), "count", "every decade of delta 1e-15..1e-3 on both sides, every "
                                   "degenerate kind and its ulp moves, non-positive masses, at 2^k, |k| <= "
                                   f"{MAGNITUDE_BITS} (1e-150..1e150)"),
                  "by_family_and_exact_verdict": _counts(about, exact),
                  "disagreements": quantity(int(bad.size), "count", "rows where the label or rank differs"),
                  "decided_exactly_by_the_classifier": quantity(decided_exactly, "count",
                                                                "rows below its float resolution")},
        "hunt": {**found.summary(), "margins": found.margins[:500],
                 "margin": "+1 where the classifier agrees with the exact decision, -1 where not"},
        "deltas": [DELTAS[0], DELTAS[-1]],
        "negative_controls": controls,
    }
    if counterexample is not None:
        data = counterexample["data"]
        return Result("Thm1-boundary", Verdict.VIOLATED,
                      f"physical_consistency says {data['classifier']['verdict']} (rank {data['classifier']['rank']}) "
                      f"where the exact decision says {data['exact']['verdict']} (rank {data['exact']['rank']}) at "
                      f"Phi = {data['phi']} ({data['about']['family']})", evidence, counterexample=counterexample)
    summary = (f"physical_consistency agrees with the exact decision on {len(rows)} swept rows and {found.examples} "
               f"hunted ones across the boundary (delta 1e-15..1e-3, degenerate, ulp moves, 1e-150..1e150); "
               f"{len(controls) - len(missed)}/{len(controls)} wrong classifiers caught")
    if missed:
        return Result("Thm1-boundary", Verdict.INCONCLUSIVE, f"{summary}; not caught: {'; '.join(missed)}", evidence)
    return Result("Thm1-boundary", Verdict.HOLDS, summary, evidence)


@check("Thm1-boundary", variant="classifier")
def classifier_at_the_boundary(ctx):
    return classifier_result(ctx)


@replayer("classifier-row")
def replay_classifier_row(data, ctx):
    row = np.array(data["phi"], float)
    bad, exact, (verdict, rank) = disagreements(row[None])
    summary = (f"physical_consistency: {LABELS[verdict[0]]} (rank {rank[0]}); exact: {LABELS[exact[0, 0]]} "
               f"(rank {exact[0, 1]})")
    return Result("Thm1-boundary", Verdict.VIOLATED if bad.size else Verdict.HOLDS, summary,
                  {"phi": data["phi"]}, counterexample={"kind": "classifier-row", "data": data} if bad.size else None)
