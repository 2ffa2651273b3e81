"""The paper's results, in the paper's order, with the IDs of shared/CATALOG.md."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["APPLICATIONS", "BY_ID", "ENTRIES", "Entry", "EXTRAS", "IDS", "order", "SECTIONS"]


@dataclass(frozen=True)
class Entry:
    id: str
    section: str
    label: str  # the paper's LaTeX label or name
    statement: str


SECTIONS = {
    "2": "Physical consistency",
    "3": "The generalized robotics equation",
    "4": "Structural properties",
}

ENTRIES = (
    Entry("EQ-moments", "2", "MassDistributionToInertialParam",
          "m, h and I are the zeroth, first and second moments of the density rho."),
    Entry("EQ-geom", "2", "Tjaja", "S(x)^T S(x) = tr(x x^T) I3 - x x^T for all x in R^3."),
    Entry("EQ-inverse", "2", "Theorem 1 (second part)",
          "I = tr(Sigma) I3 - Sigma inverts Sigma = tr(I)/2 I3 - I; f is a linear bijection R^10 -> sym(4)."),
    Entry("EQ-schur", "2", "fPosDef_IFF_PosMassPosDefSigmaCoM", "f(Phi) > 0 iff m > 0 and Sigma_CoM = Sigma - h h^T / m > 0."),
    Entry("EQ-translation", "2", "I_Sigma_IsTranslationInvariant",
          "Sigma_CoM = tr(I_CoM)/2 I3 - I_CoM with I_CoM = I - S(h)^T S(h) / m."),
    Entry("EQ-triangle", "2", "SigmaCoMPosDef_IFF_StricTriangleCoM",
          "Sigma_CoM > 0 iff I_CoM satisfies the strict triangle inequalities; these imply I_CoM > 0."),
    Entry("Def1/Thm1-suff", "2", "Definition 1, Theorem 1 (sufficiency)",
          "A nonnegative Lebesgue density with m > 0 gives f(Phi) > 0."),
    Entry("Thm1-nec", "2", "Theorem 1 (necessity)", "Every Phi with f(Phi) > 0 is realised by a nonnegative density."),
    Entry("Thm1-boundary", "2", "Theorem 1, Definition 1 (boundary)",
          "Point, line and planar masses give f >= 0 singular: why Definition 1 asks for Lebesgue densities."),
    Entry("Rem2", "2", "Remark 2", "Physical consistency implies the strict triangle inequalities of I_CoM."),
    Entry("GRE", "3", "RoboticEquation",
          "Lagrange's equations give M qdd + (C + M(q, Thetadot) + H) qd + G = tau + w - J^T Q^T Psidot."),
    Entry("GRE-F", "3", "DefF", "F(q, Theta, Thetadot) = M(q, Thetadot)."),
    Entry("GRE-physics", "3", "Model (Section 3)", "The equation describes real moving and added mass."),
    Entry("Prop1", "4", "Property 1", "Mdot - 2C - M(q, Thetadot) and H(q, Psi) are skew-symmetric."),
    Entry("Prop2", "4", "Property 2 (RoboticRegressor, RoboticRegressorVel)",
          "M a + C v + G = sum_l R_l Phi_l and M(q, Thetadot) v = sum_l R_M,l Phidot_l."),
    Entry("Def2", "4", "Definition 2", "QJ is normal: inf_q lambda_min((QJ)^T QJ) > 0."),
    Entry("CX-normal", "4", "First counterexample",
          "Phi_l = (1, 0, I3) gives M = (QJ)^T QJ: a non-normal QJ gives inf lambda_min(M) = 0."),
    Entry("CX-sphere", "4", "Second counterexample",
          "A translating sphere with m(t) -> 0 or infinity is consistent at all times, yet M has no uniform bounds."),
    Entry("Def3", "4", "Definition 3", "Uniformly physically consistent and upper bounded inertial parameters."),
    Entry("Thm2", "4", "Theorem 2 (LowerBoundedness)",
          "QJ normal and uniform consistency give M >= alpha1 I with alpha1 < min_l inf_t lambda_min(f(Phi_l)) inf_q lambda_min((QJ)^T QJ)."),
    Entry("Lem1", "4", "Lemma 1", "QJ is normal iff M has a positive lower bound for all constant consistent Phi."),
    Entry("Asm2/Lem2", "4", "Assumption 2, Lemma 2",
          "sup_q lambda_max(M) is finite for constant consistent Phi iff sup_q sigma_max(QJ) is finite."),
    Entry("Thm3", "4", "Theorem 3 (UpperBoundedness)",
          "M <= alpha2 I with alpha2 <= 2 max_l sup_t lambda_max(f(Phi_l)) sup_q sigma_max(QJ)^2."),
    Entry("Cor1", "4", "Corollary 1", "Normal bounded QJ with uniformly consistent, upper bounded Phi gives alpha1 I <= M <= alpha2 I."),
    Entry("Cor2", "4", "Corollary 2", "For constant consistent Phi: uniform bounds of M iff QJ is normal and bounded."),
    Entry("Thm4", "4", "Theorem 4 (BoundedEffectofVaryingParam)",
          "sigma_max(M(q, Thetadot)) <= sqrt(69 N) max_l sup_t sigma_max(f(Phidot_l)) sup_q sigma_max(QJ)^2."),
    Entry("EQ-acc", "4", "LumpedAccelerationBounding", "||J^T Q^T Psidot|| <= dPsi* sup_q sigma_max(QJ)."),
    Entry("Asm3/Thm5", "4", "Assumption 3, Theorem 5 (BoundedEffectOfLumpedVel)",
          "sigma_max(H(q, Psi)) <= sqrt(6N) Psi* max_p sup_q sigma_max(dK_p/dq - dK_p/dq^T)."),
)

# What the paper says its results are for (abstract, introduction), checked with adaptive laws.
APPLICATIONS = (
    Entry("APP-estimate-bounds", "A", "Abstract; Theorems 2, 3 for Theta_hat",
          "If Theta_hat(t) is uniformly physically consistent (f(Phi_hat_l) >= xi_hat I4) and upper bounded "
          "(f <= zeta_hat I4) along a run, M(q, Theta_hat(t)) obeys the bounds of Theorems 2 and 3 with xi_hat, "
          "zeta_hat."),
    Entry("APP-euclidean-escape", "A", "Introduction (natural adaptation, Lee, Kwon and Park 2018)",
          "Euclidean-gradient adaptation (Slotine-Li) may leave the consistent set, so that M(q, Theta_hat) loses "
          "its positive lower bound; natural (log-det Bregman) adaptation cannot."),
    Entry("APP-robustness", "A", "Introduction, contribution (a testbed for robustness)",
          "Adaptive tracking with Thetadot != 0 on the generalized equation against Eq. (1) and Pagilla's Eq. (2): "
          "tracking and parameter error against the rate of change, every run closing its Lyapunov balance."),
    Entry("APP-payload-envelope", "A", "Theorems 2-4 over a set of payloads (the payload envelope)",
          "For every consistent payload of mass at most m within radius R of a point of the flange, taken up at a "
          "bounded rate: alpha1 I <= M(q, Theta) <= alpha2 I and sigma_max(M(q, Thetadot)) <= chi with certified "
          "constants; no payload of the set goes beyond them."),
)

# Results the suite reports that are not statements of the paper.
EXTRAS = (
    Entry("gate", "CI", "derivation fingerprints",
          "The derived objects mean what the committed lockfile says they mean."),
    Entry("stability", "Numerics", "simulation of (RoboticEquation) with solve_ivp",
          "Simulating the equation conserves the power balance of Prop1 as the tolerance tightens; "
          "error against run time and the failures of each method on stiff and extreme scenes."),
)

BY_ID = {e.id: e for e in ENTRIES + APPLICATIONS + EXTRAS}
IDS = tuple(e.id for e in ENTRIES)


def order(entry_id):
    """Position in the paper; unknown IDs (e.g. the gate) sort last."""
    return IDS.index(entry_id) if entry_id in IDS else len(IDS)
