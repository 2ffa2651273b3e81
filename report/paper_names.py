"""The paper's LaTeX labels as the paper prints them: ``LowerBoundedness`` -> "Eq. (28)", ``theorem:...`` ->
"Theorem 2", ``section:...`` -> "Section 4.1".

:func:`printed_names` numbers a LaTeX source the way LaTeX's article class does for this paper: one counter per
theorem-like environment (theorem, lemma, assumption, corollary, definition, remark: none shares a counter),
sections and subsections (starred ones unnumbered), items of enumerate lists, and one equation number per row of
an ``align`` (rows split at top-level ``\\\\``; ``\\nonumber`` or ``\\notag`` leaves a row unnumbered; starred
environments number nothing) or per ``equation``. ``PRINTED`` holds its answer for the paper
(``python -m inertiaproof.report.paper_names PAPER.tex`` prints it again); :func:`printed` looks a label up and
passes anything else (a name such as "Theorem 1 (second part)") through.
"""

from __future__ import annotations

import re
import sys

__all__ = ["printed", "PRINTED", "printed_names"]

THEOREMS = {"theorem": "Theorem", "lemma": "Lemma", "assumption": "Assumption", "corollary": "Corollary",
            "definition": "Definition", "remark": "Remark"}
MATH = ("align", "equation", "gather", "multline")
_TOKEN = re.compile(r"\\begin\{(?P<begin>[^}]*)\}|\\end\{(?P<end>[^}]*)\}|\\label\{(?P<label>[^}]*)\}|"
                    r"\\(?P<sec>section|subsection)(?P<star>\*?)\s*\{|(?P<row>\\\\)|\\(?P<nonum>nonumber|notag)\b|"
                    r"\\item\b(?P<item>)|(?P<open>\{)|(?P<close>\})|(?P<comment>(?<!\\)%[^\n]*)")


def printed_names(tex):
    """{label: printed name} of a LaTeX source (see the module's docstring for what is numbered)."""
    counters = {name: 0 for name in THEOREMS}
    section = subsection = equation = 0
    names = {}
    stack = []  # open environments: [name, brace depth at begin]
    depth = 0
    math = None  # {"numbered": bool, "nonum": bool, "labels": [...], "depth_env": int, "star": bool, "kind": str}
    items = []  # counters of open enumerate lists
    last = None  # what a \label outside math refers to

    def close_row():
        nonlocal equation
        if math is None:
            return
        if not math["star"] and not math["nonum"]:
            equation += 1
            for label in math["labels"]:
                names[label] = f"Eq. ({equation})"
        math["labels"], math["nonum"] = [], False

    for m in _TOKEN.finditer(tex):
        if m.group("comment") is not None:
            continue
        if m.group("open") is not None:
            depth += 1
        elif m.group("close") is not None:
            depth -= 1
        elif m.group("begin") is not None:
            env = m.group("begin")
            base = env.rstrip("*")
            stack.append(env)
            if base in MATH and math is None:
                math = {"star": env.endswith("*"), "nonum": False, "labels": [], "level": len(stack), "kind": base,
                        "depth": depth}
            elif base in THEOREMS and math is None:
                counters[base] += 1
                last = f"{THEOREMS[base]} {counters[base]}"
            elif base == "enumerate":
                items.append(0)
        elif m.group("end") is not None:
            env = m.group("end")
            if math is not None and len(stack) == math["level"]:
                close_row()
                math = None
            if env.rstrip("*") == "enumerate" and items:
                items.pop()
            if stack:
                stack.pop()
        elif m.group("row") is not None:
            if math is not None and math["kind"] != "equation" and len(stack) == math["level"] and depth == math["depth"]:
                close_row()
        elif m.group("nonum") is not None:
            if math is not None:
                math["nonum"] = True
        elif m.group("item") is not None:
            if items:
                items[-1] += 1
                last = f"item {items[-1]}" + (f" of Section {section}" if section else "")
        elif m.group("sec") is not None:
            if m.group("star"):
                last = None
            elif m.group("sec") == "section":
                section, subsection = section + 1, 0
                last = f"Section {section}"
            else:
                subsection += 1
                last = f"Section {section}.{subsection}"
            depth += 1  # the title's opening brace
        elif m.group("label") is not None:
            label = m.group("label")
            if math is not None:
                math["labels"].append(label)
            elif last is not None:
                names[label] = last
    return names


_CAMEL = re.compile(r"[A-Za-z][A-Za-z0-9_:]*")


def _is_label_like(token):
    """A LaTeX label, not an English word: it has an underscore or a colon, or capitals inside (CamelCase)."""
    return "_" in token or ":" in token or sum(c.isupper() for c in token[1:]) >= 1


def printed(label):
    """How the paper prints ``label`` (its theorem, equation or section number); in a longer name such as
    "Theorem 2 (LowerBoundedness)" each label-like word is replaced ("Theorem 2, Eq. (60)"); anything else is
    returned as it is."""
    if label in PRINTED:
        return PRINTED[label]
    text = _CAMEL.sub(lambda m: PRINTED[m.group(0)] if m.group(0) in PRINTED and _is_label_like(m.group(0))
                      else m.group(0), label)
    return re.sub(r" \(((?:Eq\. \(\d+\)(?:, )?)+)\)", r", \1", text)


# printed_names() of shared/paper/time_dependent_inertial_parameters.tex (tests/test_report_engineer.py re-derives it)
PRINTED = {
    'ClassicalRoboticEquation': 'Eq. (1)',
    'SimpleGeneralizationOfTheRoboticEquation': 'Eq. (2)',
    'section:Notation': 'Section 1.2',
    'section:PhysicalConsistency': 'Section 2',
    'eq:h': 'Eq. (5)',
    'eq:I': 'Eq. (6)',
    'eq:Phi': 'Eq. (7)',
    'MassDistributionToInertialParam': 'Eq. (8)',
    'DefTrafoInertialParameters': 'Eq. (9)',
    'fPosDef_IFF_PosMassPosDefSigmaCoM': 'Eq. (10)',
    'I_Sigma_IsTranslationInvariant': 'Eq. (14)',
    'SigmaCoMPosDef_IFF_StricTriangleCoM': 'Eq. (18)',
    'definition:PhysicalConsistency': 'Definition 1',
    'theorem:PhysicalConsistency': 'Theorem 1',
    'section:Modeling': 'Section 3',
    'Defml': 'Eq. (20)',
    'DefIl': 'Eq. (22)',
    'Layout': 'Eq. (24)',
    'Assumption:IndependentJacobian': 'Assumption 1',
    'Kinematics': 'Eq. (26)',
    'VelocityRigidMass': 'Eq. (29)',
    'VelocitySquishyMass': 'Eq. (31)',
    'RespectiveKineticEnergy_Intermediate': 'Eq. (35)',
    'IntermediateKineticEnergy': 'Eq. (36)',
    'DefMatrixZ': 'Eq. (37)',
    'RespectiveKineticEnergy': 'Eq. (40)',
    'RespectivePotenitalEnergy': 'Eq. (43)',
    'KineticEnergy': 'Eq. (44)',
    'MassMatrix': 'Eq. (45)',
    'DefBlockmatrixZ': 'Eq. (46)',
    'DefBlockmatrixQ': 'Eq. (47)',
    'PotentialEnergy': 'Eq. (50)',
    'Lagrangian': 'Eq. (51)',
    'LagrangeFormalism': 'Eq. (52)',
    'RoboticEquation': 'Eq. (53)',
    'Cristoffel': 'Eq. (54)',
    'DefCoriolis': 'Eq. (55)',
    'DefGravitation': 'Eq. (56)',
    'DefH': 'Eq. (57)',
    'section:StructuralProperties': 'Section 4',
    'Prop1': 'item 1 of Section 4',
    'Prop2': 'item 2 of Section 4',
    'RoboticRegressor': 'Eq. (58)',
    'RoboticRegressorVel': 'Eq. (59)',
    'section:BoundedMassMatrix': 'Section 4.1',
    'definition:NormalJacobian': 'Definition 2',
    'definition:PropertiesInertialParameters': 'Definition 3',
    'theorem:LowerBoundedMassMatrix': 'Theorem 2',
    'LowerBoundedness': 'Eq. (60)',
    'lemma:NormalJacobian': 'Lemma 1',
    'Assumption:UniformUpperBound': 'Assumption 2',
    'theorem:UpperBoundedMassMatrix': 'Theorem 3',
    'UpperBoundedness': 'Eq. (61)',
    'lemma:UpperBoundedJacobian': 'Lemma 2',
    'corollary:UniformBounds': 'Corollary 1',
    'corollary:UniformBoundsForConstantParameters': 'Corollary 2',
    'section:OtherComponents': 'Section 4.2',
    'theorem:BoundedRateOfChange': 'Theorem 4',
    'BoundedEffectofVaryingParam': 'Eq. (62)',
    'LumpedAccelerationBounding': 'Eq. (63)',
    'DefK': 'Eq. (64)',
    'assumption:BoundedPartialDerivatives': 'Assumption 3',
    'BoundedEffectOfLumpedVel': 'Eq. (65)',
    'section:Conclusion': 'Section 5',
    'GoalForSufficiency': 'Eq. (66)',
    'Intermediate': 'Eq. (67)',
    'Tjaja': 'Eq. (68)',
    'LHS': 'Eq. (70)',
    'Intermediate1': 'Eq. (71)',
    'Intermediate2': 'Eq. (74)',
    'Intermediate0': 'Eq. (75)',
    'StrictSchwartz': 'Eq. (78)',
    'Intermediate3': 'Eq. (80)',
    'Intermediate5': 'Eq. (82)',
    'Intermediate4': 'Eq. (86)',
    'SetRepresentation': 'Eq. (88)',
    'remark:StrictTriangleIneqsUnderPhysicalConsistency': 'Remark 2',
    'ExplicitLagrange': 'Eq. (94)',
    'skalarRoboticEquation': 'Eq. (96)',
    'IntermediateRoboticEquation': 'Eq. (99)',
    'DefF': 'Eq. (100)',
    'MassMatrixRegressors': 'Eq. (101)',
}

if __name__ == "__main__":  # pragma: no cover
    import json

    with open(sys.argv[1], encoding="utf-8") as handle:
        print(json.dumps(printed_names(handle.read()), indent=1))
