"""The audit document as CI annotations: SARIF 2.1.0 and GitHub Actions workflow commands.

One rule per kind of finding: a link or body that is inconsistent or
degenerate, an ``<inertial>`` that urdfdom reads past (one result per error
in it, on the element at fault), each sign of an authoring mistake, a chain
whose M(q) can become singular, and a file that cannot be read (at the line
of the error where the reader has one), and each finding on the bodies inside a link's geometry
(:mod:`.bodies_inside`; its fix: the geometry's uniform-density inertia). A finding sits on the element of
the link's inertia (URDF ``<inertia>``, MJCF ``<inertial>``, or the
``<body>`` whose inertia MuJoCo computed from geoms) at the line and column
the reader found; a repair comes as a SARIF fix that replaces that element's
text. Levels: ``error`` for what the exit status counts (a moving link or a
body that is not consistent, a problem in an inertial, an unreadable file), ``warning`` for the same
on a link that does not move and for a chain whose M(q) can become singular,
``note`` for the signs and the soft findings on the geometry (a hard one is an ``error`` on a moving link, else
a ``warning``); a pair of mirror twins whose inertials are not reflections (:mod:`.mirror_twins`) is a ``warning``
on the right link's inertia, naming both links.
"""

from __future__ import annotations

from pathlib import Path

from .bodies_inside import HARD, SOFT
from .mirror_twins import RULE as RULE_MIRROR

__all__ = ["findings", "github_commands", "keyed_findings", "RULES", "sarif_log"]

SARIF_SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
RULES = {
    "inconsistent": "The link's inertial parameters are not physically consistent: no mass distribution has them "
                    "(f(Phi) is not positive semidefinite; the triangle inequality of I_CoM fails or the mass is not "
                    "positive).",
    "degenerate": "Only a point, line or planar mass has these parameters (f(Phi) >= 0 and singular): the triangle "
                  "inequality of I_CoM holds with equality.",
    "body-not-consistent": "A body (a link and the links fixed to it) as the mass matrix sees it is not consistent.",
    "singular-mass-matrix": "The chain's mass matrix M(q) can become singular or indefinite.",
    "unreadable": "The file cannot be read.",
    "missing-inertia": "An <inertial> has a <mass> and no <inertia>: urdfdom logs an error and Pinocchio loads the "
                       "link as a point mass.",
    "malformed-inertial": "An <inertial> urdfdom cannot parse (a missing element or attribute, a value that is not a "
                          "finite number): urdfdom logs an error and reads the link as far as it got.",
    "sdformat-default": "An SDFormat link lacks <inertial>, <mass>, <inertia> or a diagonal moment: sdformat and "
                        "Gazebo read the specification's default (mass 1 kg, ixx = iyy = izz = 1 kg m^2).",
    "mass-exceeds-densest": "The mass exceeds what the densest material (--max-density) fits in the volume of the "
                            "link's geometry: no body inside it has this mass.",
    "com-outside-geometry": "The centre of mass lies outside the convex hull of the link's geometry: no mass "
                            "distribution inside it has this centre.",
    "second-moment-below-densest-ball": "tr(I_CoM) is below 6/5 m R^2, the least of any body of this mass and "
                                        "density at most --max-density (a ball of radius R).",
    "outside-bounding-ellipsoid": "The inertia fails tr(Q f(Phi)) >= 0 for an ellipsoid holding the link's geometry "
                                  "(Wensing, Kim and Slotine): no mass distribution inside it has this inertia.",
    "total-mass-mismatch": "The model's total mass (the sum of its links' masses) is not the expected one "
                           "(--expect-mass) within --mass-tolerance (relative).",
    "mirror-twin-mismatch": "Soft: two links named and placed as left/right mirror twins have inertials that are not "
                            "reflections of each other (mass, centre of mass or an entry of the inertia, in the base "
                            "frame at q = 0).",
    "implausible-density": "Soft: the density implied by the mass and the geometry's volume is below that of solid "
                           "parts (100 kg/m^3).",
    "unlike-mujoco-inertia": "Soft: an MJCF body's declared <inertial> is far from MuJoCo's own inertia from its geoms "
                             "(inertiafromgeom, at the declared mass): a principal moment more than 10x off, or the "
                             "centre farther than MuJoCo's radius of gyration.",
    "inertia-unlike-geometry": "Soft: the principal moments are more than 10x off those of the link's geometry filled "
                               "uniformly at its mass.",
    "negative_mass": "Sign of an authoring mistake: negative mass.",
    "massless_with_inertia": "Sign of an authoring mistake: a massless link with an inertia.",
    "point_mass": "Sign of an authoring mistake: a positive mass with an all-zero inertia.",
    "negligible_inertia": "Sign of an authoring mistake: an inertia of rounding noise around a point mass.",
    "all_entries_equal": "Sign of an authoring mistake: all six entries equal (a placeholder).",
    "parallel_axis": "Sign of an authoring mistake: the inertia was shifted away from the centre of mass.",
    "power_of_ten": "Sign of an authoring mistake: one entry off by a power of ten.",
    "products_sign": "Sign of an authoring mistake: products of inertia in the opposite sign convention.",
}
SINGULAR = ("everywhere", "indefinite", "singular")


def _uri(path):
    p = Path(path)
    try:
        p = p.resolve().relative_to(Path.cwd().resolve())
    except ValueError:
        return p.resolve().as_uri()
    return p.as_posix()


def findings(doc):
    """(rule, level, file, location or None, message, link entry or None) for every finding, in file order.

    A location in an expanded text (a xacro file's) is not one in the file: the message names its line instead."""
    for rule, level, path, where, message, link, _ in keyed_findings(doc):
        yield rule, level, path, where, message, link


def keyed_findings(doc):
    """As :func:`findings`, each with its subject last: ``"link NAME"``, ``"body NAME"``, ``"chain NAME"``,
    ``"model"`` (the file's total mass) or ``"file"`` (an unreadable one); rule, file and subject identify a finding
    across versions of the file (:mod:`.baseline`), whatever lines it moved to."""
    for rule, level, path, where, message, link, subject in _findings(doc):
        if where is not None and where.get("expanded"):
            message += f" (line {where['startLine']} of the text {where['expanded']} expands the file to)"
            where = None
        yield rule, level, path, where, message, link, subject


def _findings(doc):
    for path, f in doc["files"].items():
        if f["status"] != "ok":
            yield "unreadable", "error", path, f.get("location"), f["error"], None, "file"
            continue
        for problem in f.get("problems", ()):
            yield (problem["kind"].replace("_", "-"), "error", path, problem["location"],
                   problem["message"], f["links"][problem["link"]], f"link {problem['link']}")
        mass = f.get("total_mass") or {}
        if mass.get("matches") is False:
            yield "total-mass-mismatch", "error", path, None, mass["message"], None, "model"
        for name, link in f["links"].items():
            where, subject = link["location"], f"link {name}"
            if link["verdict"] != "consistent" and not link["massless_frame"]:
                level = "error" if link["moving"] else "warning"
                moves = "" if link["moving"] else " (the link does not move: not counted in the exit status)"
                yield link["verdict"], level, path, where, f"link '{name}': {link['reason']}{moves}", link, subject
            for sign in link["signs"]:
                yield sign["sign"], "note", path, where, f"link '{name}': {sign['text']}", None, subject
            for found in (link.get("bodies_inside") or {}).get("findings", ()):
                level = ("error" if link["moving"] else "warning") if found["hard"] else "note"
                moves = "" if link["moving"] or not found["hard"] else \
                    " (the link does not move: not counted in the exit status)"
                yield found["rule"], level, path, where, found["message"] + moves, link, subject
        for pair in (f.get("mirror_twins") or {}).get("pairs", ()):
            if not pair["matches"]:
                yield (RULE_MIRROR, "warning", path, f["links"][pair["right"]]["location"], pair["message"], None,
                       f"links {pair['left']} {pair['right']}")
        for name, body in f["bodies"].items():
            # one link with mass has the body's verdict as its own; a body of massless frames has no link result
            if body["judged"] and body["verdict"] != "consistent" and (len(body["links"]) > 1 or body["massless"]):
                where = f["links"][name]["location"]
                yield ("body-not-consistent", "error", path, where,
                       f"body '{name}' (links {', '.join(body['links'])}): {body['verdict']}: {body['reason']}", None,
                       f"body {name}")
        for leaf, chain in f["chains"].items():
            if chain["singular"]["verdict"] in SINGULAR:
                where = f["links"][leaf]["location"]
                said = f"chain {chain['name']}: M(q) singular {chain['singular']['verdict']}: " \
                    f"{chain['singular']['argument']}"
                yield "singular-mass-matrix", "warning", path, where, said, None, f"chain {chain['name']}"


def _states(doc):
    """The baseline state of each finding of :func:`keyed_findings`, in its order (None without a baseline)."""
    listed = doc.get("findings") or ()
    return [found.get("baseline_state") for found in listed]


def sarif_log(doc, version="0"):
    """The audit as a SARIF 2.1.0 log (a dict ready for ``json.dumps``).

    Each result names its subject and audited file in ``properties`` (``subject``: ``link NAME``, ...; ``file``);
    against a baseline (``--baseline``) each has its ``baselineState``, and the baseline's findings this run does
    not have follow as results of level ``none`` and state ``absent``."""
    rule_ids = list(RULES)
    results = []
    states = _states(doc)
    for i, (rule, level, path, where, message, link, subject) in enumerate(keyed_findings(doc)):
        physical = {"artifactLocation": {"uri": _uri(where["path"] if where else path)}}
        if where is not None:
            physical["region"] = {k: v for k, v in where.items() if k != "path"}
        result = {"ruleId": rule, "ruleIndex": rule_ids.index(rule), "level": level, "message": {"text": message},
                  "locations": [{"physicalLocation": physical}], "properties": {"subject": subject, "file": _uri(path)}}
        if i < len(states) and states[i] is not None:
            result["baselineState"] = states[i]
        if link is not None:
            result["properties"].update(engines=link["engines"], triangle_slack_rel=link["triangle_slack_rel"])
            fix = _fix(link["repair"]) if rule == link["verdict"] else \
                _uniform_fix(link, where) if rule in HARD + SOFT else None  # the verdict's result carries the fix
            if fix is not None:
                result["fixes"] = [fix]
        results.append(result)
    results += [_absent(found, rule_ids) for found in (doc.get("baseline") or {}).get("absent", ())]
    run = {
        "tool": {"driver": {"name": "inertiaproof", "version": version,
                            "rules": [{"id": rule, "shortDescription": {"text": text.split(":")[0].split(".")[0]},
                                       "fullDescription": {"text": text}} for rule, text in RULES.items()]}},
        "columnKind": "unicodeCodePoints",
        "results": results,
    }
    if doc.get("baseline"):
        run["properties"] = {"baseline": doc["baseline"]["path"], "baseline_counts": doc["baseline"]["counts"]}
    return {"$schema": SARIF_SCHEMA, "version": "2.1.0", "runs": [run]}


def _absent(found, rule_ids):
    """A SARIF result for a finding of the baseline that this run does not have."""
    old = found.get("sarif") or {}
    locations = old.get("locations") or [{"physicalLocation": {"artifactLocation": {"uri": _uri(found["file"])}}}]
    result = {"ruleId": found["rule"], "level": "none",
              "message": {"text": f"in the baseline, not in this run: {found['message']}"}, "locations": locations,
              "baselineState": "absent",
              "properties": {"subject": found["subject"], "file": _uri(found["file"]),
                             "baseline_level": found["level"]}}
    if found["rule"] in rule_ids:
        result["ruleIndex"] = rule_ids.index(found["rule"])
    return result


def _fix(repair):
    """A SARIF fix replacing the inertia element by its repair, when the element's span is known."""
    if not repair or not repair.get("replacement"):
        return None
    r = repair["replacement"]
    region = {k: r[k] for k in ("startLine", "startColumn", "endLine", "endColumn")}
    return {"description": {"text": f"nearest consistent inertia ({repair['note']})"},
            "artifactChanges": [{"artifactLocation": {"uri": _uri(r["path"])},
                                 "replacements": [{"deletedRegion": region, "insertedContent": {"text": r["text"]}}]}]}


def _uniform_fix(link, where):
    """A SARIF fix replacing the link's ``<inertial>`` by its geometry filled uniformly at its mass, when that is
    defined (one primitive) and the element's columns are known."""
    uniform = (link.get("bodies_inside") or {}).get("uniform") or {}
    region = uniform.get("span")
    if not uniform.get("text") or where is None or not region or "startColumn" not in region:
        return None
    return {"description": {"text": "the inertia of the link's geometry at uniform density and the declared mass"},
            "artifactChanges": [{"artifactLocation": {"uri": _uri(where["path"])},
                                 "replacements": [{"deletedRegion": region,
                                                   "insertedContent": {"text": uniform["text"]}}]}]}


def _escape(text, property_value=False):
    text = text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    return text.replace(":", "%3A").replace(",", "%2C") if property_value else text


def github_commands(doc):
    """GitHub Actions workflow commands (``::error file=...,line=...::message``), one line per finding.

    Against a baseline, an error the baseline has unchanged is a ``warning`` (it does not fail the run) and its
    message says so; the baseline's findings this run does not have are not annotated."""
    out = []
    states = _states(doc)
    for i, (rule, level, path, where, message, _, _) in enumerate(keyed_findings(doc)):
        state = states[i] if i < len(states) else None
        if state == "unchanged":
            level = "warning" if level == "error" else level
            message += " [unchanged since the baseline]"
        elif state is not None:
            message += f" [{state} since the baseline]"
        command = {"error": "error", "warning": "warning", "note": "notice"}[level]
        props = [f"file={_escape(str(where['path'] if where else path), True)}"]
        if where is not None:
            props.append(f"line={where['startLine']}")
            if "startColumn" in where:
                props += [f"col={where['startColumn']}", f"endLine={where['endLine']}",
                          f"endColumn={where['endColumn']}"]
        props.append(f"title={_escape('inertiaproof ' + rule, True)}")
        out.append(f"::{command} {','.join(props)}::{_escape(message)}")
    return out
