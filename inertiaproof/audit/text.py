"""The audit document (:mod:`inertiaproof.audit`) as readable text tables."""

from __future__ import annotations

__all__ = [
    "engine_actions", "format_audit", "format_baseline", "format_file", "headline", "line_of", "NOT_JUDGED_WORDS",
    "reason", "remarks", "role", "totals", "verdict",
]


def _number(q):
    """A quantity as 'value [kind]'."""
    value = q["value"]
    text = f"{value:.6g}" if isinstance(value, float) else str(value)
    return f"{text}{' ' + q['unit'] if q.get('unit') else ''} [{q['kind']}]"


def _count(items, one, many=None):
    return f"{len(items)} {one if len(items) == 1 else many or one + 's'}"


ENGINE_NAMES = {"mujoco": "MuJoCo", "drake": "Drake", "pybullet": "PyBullet", "gazebo": "Gazebo"}
ENGINE_HEADER = "MuJoCo/Drake/PyBullet/Gazebo"
ENGINE_WIDTH = 34


def engine_actions(link):
    """What the four engines do with a link's inertia, in one word each ("loads/replaces/zeroes/rejects")."""
    if not link.get("engines"):
        return "-"
    unknown = ("not_documented", "not_verified")
    return "/".join("?" if e["action"] in unknown else e["action"] for e in link["engines"].values())


def role(link):
    """A link's role as a reader says it: base, body or merged into its body's anchor, and whether it moves."""
    if link["role"] == "joint_frame":
        return f"joint frame of {link['group'].split('/')[0]}"
    if link["role"] == "merged":
        return f"merged into {link['group']}"
    return link["role"] + ("" if link["moving"] else " (fixed)")


def headline(f):
    """One readable file's robot, sizes and state, e.g. "robot 'panda', 13 links (8 judged), 7 bodies, ...:
    consistent"; bodies are the judged ones (not MuJoCo joint frames nor massless bases)."""
    state = "consistent" if f["consistent"] else f"NOT CONSISTENT: {', '.join(f['not_consistent'])}"
    if f.get("problems"):
        state += f"; {_count(f['problems'], 'problem')} in inertials"
    if f.get("geometry_errors"):
        state += f"; {_count(f['geometry_errors'], 'hard finding')} on the bodies inside the geometry"
    if (f.get("total_mass") or {}).get("matches") is False:
        state += "; total mass not the expected"
    twins = f.get("mirror_twins") or {}
    if twins.get("mismatches"):
        state += f"; {twins['mismatches']} of {_count(twins['pairs'], 'mirror pair')} not mirrored"
    links = _count(f["links"], "link")
    bodies = [b for b in f["bodies"].values() if b.get("judged", True)]
    if "counts" in f:
        links += f" ({len(f['links']) - f['counts'].get('not_judged', 0)} judged)"
    return (f"robot '{f['robot']}', {links}, {_count(bodies, 'body', 'bodies')}, "
            f"{_count(f['chains'], 'chain')}{', serial arm' if f['serial_arm'] else ''}: {state}")


def verdict(link):
    """The verdict a reader sees: a massless frame or a joint frame has none."""
    return "not judged" if link["massless_frame"] or link["role"] == "joint_frame" else link["verdict"]


def reason(link):
    """Why the link has its verdict, or why it is not judged."""
    if link["role"] == "joint_frame":
        return "a frame between two joints of one MuJoCo body -- a massless frame, not a body: not judged"
    if link["massless_frame"]:
        return "no mass, no inertia -- a massless frame, not a body: not judged"
    return link["reason"]


def remarks(f):
    """What the audit left out or simplified in one readable file, one line each."""
    out = [f"left out: joint {j['joint']} ({j['type']}): {j['reason']}" for j in f["left_out_joints"]]
    if f["mimic_joints"]:
        out.append(f"mimic joints, treated as independent coordinates (as Pinocchio's URDF reader does by default): "
                   f"{', '.join(m['joint'] + ' (' + m['mimics'] + ')' for m in f['mimic_joints'])}")
    return out


def line_of(location):
    """'line 12' or 'line 12, column 5' of a location, with the text it is a line of when that is not the file."""
    if not location:
        return "no line"
    where = f"line {location['startLine']}" + (f", column {location['startColumn']}" if "startColumn" in location
                                                 else "")
    return where + (f" of the text {location['expanded']} expands the file to" if location.get("expanded") else "")


def format_file(path, f):
    if f["status"] == "error":
        return f"== {path}\n  UNREADABLE: {f['error']}"
    links = f["links"]
    out = [f"== {path}: {headline(f)}"] + [f"  {line}" for line in remarks(f)]
    out += [f"  problem {p['link']} ({line_of(p['location'])}): {p['message']}" for p in f.get("problems", ())]
    mass = f.get("total_mass") or {}
    if mass.get("expected") is not None:
        out.append(f"  mass    {mass['message']}" if mass["matches"] is False else
                   f"  mass    total {mass['total']['value']:.6g} kg, as expected ({mass['expected']['value']:.6g} kg "
                   f"within {mass['tolerance_rel']:.3g} relative)")
    width = max(len(name) for name in links)
    roles = {name: role(link) for name, link in links.items()}
    role_width = max(len(r) for r in roles.values())
    engines = {name: engine_actions(link) for name, link in links.items()}
    out.append(f"  {'link':<{width}}  {'role':<{role_width}}  {'verdict':<12}  {ENGINE_HEADER:<{ENGINE_WIDTH}}  reason")
    for name, link in links.items():
        out.append(f"  {name:<{width}}  {roles[name]:<{role_width}}  {verdict(link):<12}  "
                   f"{engines[name]:<{ENGINE_WIDTH}}  {reason(link)}")
    if f.get("format") == "mjcf":
        out.append(f"  (MJCF: source {', '.join(sorted({str(link['source']) for link in links.values()}))}; "
                   "'geoms': the inertia MuJoCo computed from the body's geoms)")
    for name, link in links.items():
        for s in link["signs"]:
            out.append(f"  sign    {name}: {s['text']}")
    for name, link in links.items():
        inside = link.get("bodies_inside") or {}
        for found in inside.get("findings", ()):
            out.append(f"  {'finding' if found['hard'] else 'soft'} {found['rule']}: {found['message']}")
        if inside.get("findings") and (inside.get("uniform") or {}).get("text"):
            out.append(f"  uniform {name}: {inside['uniform']['text']} (its geometry at uniform density)")
    for name, link in links.items():
        if link["engines"] and any(e["action"] != "loads" for e in link["engines"].values()):
            out.append(f"  engines {name}: " + "; ".join(f"{ENGINE_NAMES[k]} {e['text']}" for k, e in link["engines"].items()))
    for name, link in links.items():
        r = link["repair"]
        if r is None:
            continue
        if r["inertia"] is None:
            out.append(f"  repair  {name}: {r['note']}")
            continue
        moments = ", ".join(f"{x:.4g}" for x in r["principal_moments_before"]["value"])
        fixed = ", ".join(f"{x:.4g}" for x in r["principal_moments_after"]["value"])
        six = " ".join(f'{k}="{v}"' for k, v in (r["written"] or {}).items())
        out.append(f"  repair  {name}: nearest consistent I_CoM changes it by {r['change_frobenius_rel']['value']:.3g} "
                   f"(relative Frobenius), {r['change_spectral']['value']:.3g} kg m^2 (spectral); principal moments "
                   f"({moments}) -> ({fixed}); <inertia {six}/> ({r['note']})")
    for pair in (f.get("mirror_twins") or {}).get("pairs", ()):
        if not pair["matches"]:
            out.append(f"  mirror  {pair['message']}")
    for name, body in f["bodies"].items():
        if body["verdict"] != "consistent" and body.get("judged", True):  # not MuJoCo joint frames, massless bases
            out.append(f"  body    {name} (joint {body['joint']}; links {', '.join(body['links'])}): "
                       f"{body['verdict']}: {body['reason']}")
    for leaf, c in f["chains"].items():
        budget = f", bounds with {c['bounds_rounds']:g} rounds per bracket" if "bounds_rounds" in c else ""
        out.append(f"  chain   {c['name']}: {len(c['joints'])} joints {c['kinds']}, bodies "
                   f"{'all consistent' if c['bodies_consistent'] else 'not all consistent'}{budget}")
        out.append(f"          M(q) singular: {c['singular']['verdict']}: {c['singular']['argument']}")
        for key, q in (c["bounds"] or {}).items():
            if isinstance(q, dict) and "kind" in q:
                note = f" ({q['note']})" if q.get("note") else ""
                out.append(f"          {key} = {_number(q)}{note}")
    return "\n".join(out)


NOT_JUDGED_WORDS = {"joint_frames": ("joint frame", "joint frames"),
                    "massless_frames": ("massless frame or base", "massless frames or bases"),
                    "fixed_base": ("link of a fixed base", "links of a fixed base")}


def totals(summary):
    """The audit's counts (its ``summary``) after the number of files, e.g. "43 consistent, ...; judged links: ...;
    judged bodies: ...; signs: ...". Joint frames, massless frames and bases and the links of a fixed base are
    counted apart from the judged links, whatever their verdict as written."""
    links = ", ".join(f"{n} {label}" for label, n in summary["links"].items() if label != "not_judged")
    apart = summary.get("links_not_judged")
    why = ", ".join(f"{n} {NOT_JUDGED_WORDS[k][n != 1]}" for k, n in apart.items() if n and k in NOT_JUDGED_WORDS) \
        if apart is not None else "fixed base, massless or joint frames"
    links += f"; {summary['links'].get('not_judged', 0)} not judged" + (f" ({why})" if why else "")
    bodies = summary.get("bodies")
    judged_bodies = "" if bodies is None else "judged bodies: " + ", ".join(
        f"{n} {label}" for label, n in bodies.items() if label != "not_judged") + "; "
    signs = ", ".join(f"{k} {v}" for k, v in sorted(summary["signs"].items())) or "none"
    problems = f"; problems in inertials: {summary['problems']}" if summary.get("problems") else ""
    if summary.get("mass_mismatches"):
        problems += f"; total mass not the expected: {summary['mass_mismatches']}"
    twins = summary.get("mirror_twins")
    if twins and twins["pairs"]:
        problems += f"; mirror pairs: {twins['pairs']}, not mirrored: {twins['mismatches']}"
    inside = summary.get("bodies_inside")
    if inside:
        problems += "; bodies inside the geometry: " + ", ".join(f"{k} {v}" for k, v in sorted(inside.items()))
    return (f"{summary['files_consistent']} consistent, {summary['files_not_consistent']} not consistent, "
            f"{summary['unreadable']} unreadable; judged links: {links}; {judged_bodies}moving links or bodies not "
            f"consistent: {summary['moving_not_consistent']}; signs: {signs}{problems}")


def format_baseline(doc):
    """The findings against the baseline (``--baseline``): counts per state, then each new, updated or absent
    one."""
    compared = doc.get("baseline")
    if not compared:
        return None
    counts = ", ".join(f"{n} {state}" for state, n in compared["counts"].items())
    errors = "error" if compared["counted"] == 1 else "errors"
    out = [f"baseline {compared['path']}: {counts}; the exit status counts the {compared['counted']} new or updated "
           + errors]
    for found in doc.get("findings", ()):
        if found.get("baseline_state") in ("new", "updated"):
            out.append(f"  {found['baseline_state']:<8} {found['level']:<7} {found['rule']} {found['file']} "
                       f"{found['subject']}: {found['message']}")
    out += [f"  absent   {found['rule']} {found['file']} {found['subject']}: {found['message']}"
            for found in compared["absent"]]
    return "\n".join(out)


def format_audit(doc):
    parts = [format_file(path, f) for path, f in doc["files"].items()]
    if doc.get("baseline"):
        parts.append(format_baseline(doc))
    parts.append(f"audited {doc['summary']['files']} files in {doc['runtime_s']:.2f} s: {totals(doc['summary'])}")
    return "\n\n".join(parts)
