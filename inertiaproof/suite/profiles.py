"""Profiles: how hard a run looks. Checks and audits scale their work by these numbers."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["PROFILES", "Profile"]


@dataclass(frozen=True)
class Profile:
    name: str
    examples: int  # Hypothesis examples per hunt
    samples: int  # configurations / times sampled per extreme
    rounds: float  # rounds of branch and bound a bracket may refine (2 batches of boxes each; the pivot ladders' boxes
    # and the local search's rounds are counted from it: inertiaproof.bounds.pivot_search.ladder_budget)
    symbolic_max_n: int  # largest n for the abstract symbolic derivation
    derandomize: bool  # Hypothesis: same examples every run, no database
    concrete_chains: tuple = ("2R", "3R")  # concrete chains derived symbolically
    symbolic_parameters: int = 2  # generic M^h, U^h of the abstract derivation (linearity covers any 10N)
    symbolic_rows: int = 2  # generic rows of QJ of the abstract derivation (linearity covers any 6N)
    moment_samples: int = 2**18  # Monte Carlo points per density (EQ-moments)
    bernstein_degree: int = 3  # highest Bernstein degree checked symbolically (EQ-moments)
    audit_samples: int = 512  # configurations per chain in an audit (a sweep audits dozens of chains)
    audit_rounds: float = 2  # an audit's bracket budget per chain (rounds, as ``rounds``) with the default --bounds
    # arms: below PIVOT_MIN_ROUNDS, so no pivot ladders: M(q) certified nonsingular, the lower side loose
    audit_full_rounds: float = 20  # the same with --bounds all: the pivot ladders run (lower sides within 2x)
    audit_full_chains: int = 12  # chains of one file --bounds all bounds with audit_full_rounds, in the tree's order;
    # the others get audit_rounds (a tree of 99 chains: 12 full, 87 quick; every chain of a serial arm fits)
    check_s: float = 180.0  # seconds one check may run (inertiaproof.budget): then it ends INCONCLUSIVE with what it
    # has (the safety net behind the counted budgets; bench/cpu_hog.py measures a run beside two CPU hogs)
    run_s: float = 300.0  # seconds a whole run may take: a check started late gets only what is left
    memory_mb: int = 4096  # memory one check may add to the process (its address space)
    shard_examples: int = 100  # a hunt splits into shards of at most this many examples (tasks for the workers)
    def audit_budget(self, bounds):
        """(samples, rounds) per chain of an audit with ``--bounds`` ``bounds``."""
        return self.audit_samples, self.audit_full_rounds if bounds == "all" else self.audit_rounds

    def audit_chains(self, bounds):
        """{full_chains, quick_rounds} of :func:`inertiaproof.audit.document.audit_robot` for ``--bounds``
        ``bounds``: with all, at most ``audit_full_chains`` chains of a file get the full budget; else no cap."""
        return {"full_chains": self.audit_full_chains, "quick_rounds": self.audit_rounds} if bounds == "all" else {}

    envelope_goal: float = 1.2  # the payload envelope's sup brackets: the pivot ladder goes on to this ratio
    envelope_boxes: int = 0  # boxes the ladder of alpha2's sup over the payload set may test (0: the bracket budget's)
    envelope_examples: int = 1000  # Hypothesis payloads drawn from the set per envelope
    envelope_points: int = 2  # masses of the curve against the payload's mass, besides the full one
    tree_boxes: int = 2_000  # boxes the prover may test beyond a certificate's tree to complete it for the checker,
    # which walks the tree once (inertiaproof.bounds.completion)


PROFILES = {
    "ci": Profile("ci", examples=60, samples=2000, rounds=20, symbolic_max_n=3, derandomize=True,
                  shard_examples=60),
    "deep": Profile("deep", examples=2000, samples=50000, rounds=800, symbolic_max_n=5, derandomize=False,
                    concrete_chains=("2R", "3R", "6R"), symbolic_parameters=10, symbolic_rows=6,
                    moment_samples=2**22, bernstein_degree=8, audit_samples=20000, audit_rounds=200, audit_full_rounds=200,
                    check_s=1800.0, run_s=14400.0, memory_mb=6144, tree_boxes=100_000,
                    envelope_goal=1.04, envelope_boxes=800_000, envelope_examples=100_000, envelope_points=2),
}
