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
a ``warning``).
"""

from __future__ import annotations

from pathlib import Path

from .bodies_inside import HARD, SOFT

__all__ = ["github_commands", "RULES", "sarif_log"]

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
    "mass-exceeds-densest": "The mass exceeds what the densest material (--max-density) fits in the volume of the "
                            "link's geometry: no body inside it has this mass.",
    "com-outside-geometry": "The centre of mass lies outside the convex hull of the link's geometry: no mass "
                            "distribution inside it has this centre.",
    "second-moment-below-densest-ball": "tr(I_CoM) is below 6/5 m R^2, the least of any body of this mass and "
                                        "density at most --max-density (a ball of radius R).",
    "outside-bounding-ellipsoid": "The inertia fails tr(Q f(Phi)) >= 0 for an ellipsoid holding the link's geometry "
                                  "(Wensing, Kim and Slotine): no mass distribution inside it has this inertia.",
    "implausible-density": "Soft: the density implied by the mass and the geometry's volume is below that of solid "
                           "parts (100 kg/m^3).",
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
    for rule, level, path, where, message, link in _findings(doc):
        if where is not None and where.get("expanded"):
            message += f" (line {where['startLine']} of the text {where['expanded']} expands the file to)"
            where = None
        yield rule, level, path, where, message, link


def _findings(doc):
    for path, f in doc["files"].items():
        if f["status"] != "ok":
            yield "unreadable", "error", path, f.get("location"), f["error"], None
            continue
        for problem in f.get("problems", ()):
            yield (problem["kind"].replace("_", "-"), "error", path, problem["location"],
                   problem["message"], f["links"][problem["link"]])
        for name, link in f["links"].items():
            where = link["location"]
            if link["verdict"] != "consistent" and not link["massless_frame"]:
                level = "error" if link["moving"] else "warning"
                moves = "" if link["moving"] else " (the link does not move: not counted in the exit status)"
                yield link["verdict"], level, path, where, f"link '{name}': {link['reason']}{moves}", link
            for sign in link["signs"]:
                yield sign["sign"], "note", path, where, f"link '{name}': {sign['text']}", None
            for found in (link.get("bodies_inside") or {}).get("findings", ()):
                level = ("error" if link["moving"] else "warning") if found["hard"] else "note"
                moves = "" if link["moving"] or not found["hard"] else \
                    " (the link does not move: not counted in the exit status)"
                yield found["rule"], level, path, where, found["message"] + moves, link
        for name, body in f["bodies"].items():
            if body["judged"] and body["verdict"] != "consistent" and len(body["links"]) > 1:
                where = f["links"][name]["location"]
                yield ("body-not-consistent", "error", path, where,
                       f"body '{name}' (links {', '.join(body['links'])}): {body['verdict']}: {body['reason']}", None)
        for leaf, chain in f["chains"].items():
            if chain["singular"]["verdict"] in SINGULAR:
                where = f["links"][leaf]["location"]
                yield ("singular-mass-matrix", "warning", path, where,
                       f"chain {chain['name']}: M(q) singular {chain['singular']['verdict']}: "
                       f"{chain['singular']['argument']}", None)


def sarif_log(doc, version="0"):
    """The audit as a SARIF 2.1.0 log (a dict ready for ``json.dumps``)."""
    rule_ids = list(RULES)
    results = []
    for rule, level, path, where, message, link in findings(doc):
        physical = {"artifactLocation": {"uri": _uri(where["path"] if where else path)}}
        if where is not None:
            physical["region"] = {k: v for k, v in where.items() if k != "path"}
        result = {"ruleId": rule, "ruleIndex": rule_ids.index(rule), "level": level, "message": {"text": message},
                  "locations": [{"physicalLocation": physical}]}
        if link is not None:
            result["properties"] = {"engines": link["engines"], "triangle_slack_rel": link["triangle_slack_rel"]}
            fix = _fix(link["repair"]) if rule == link["verdict"] else \
                _uniform_fix(link, where) if rule in HARD + SOFT else None  # the verdict's result carries the fix
            if fix is not None:
                result["fixes"] = [fix]
        results.append(result)
    return {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "inertiaproof", "version": version,
                                "rules": [{"id": rule, "shortDescription": {"text": text.split(":")[0].split(".")[0]},
                                           "fullDescription": {"text": text}} for rule, text in RULES.items()]}},
            "columnKind": "unicodeCodePoints",
            "results": results,
        }],
    }


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
    """GitHub Actions workflow commands (``::error file=...,line=...::message``), one line per finding."""
    out = []
    for rule, level, path, where, message, _ in findings(doc):
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
