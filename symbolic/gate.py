"""``inertiaproof gate``: compare the fingerprints of every derived object with the committed lockfile.

A changed meaning (an exact value at a fixed rational point) fails with exit 1
and shows the old and new values and the catalog ID affected; a changed form
with the same meaning passes with a warning; an object the lockfile does not
know, or one that disappeared, fails. ``--update`` rewrites the lockfile's
entries for the systems of the profile, deliberately.

SymPy's printed forms may depend on PYTHONHASHSEED, so the gate always runs
under PYTHONHASHSEED=0: started with any other value it re-executes itself.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

from inertiaproof.errors import InputError
from inertiaproof.suite.environment import command
from inertiaproof.suite.profiles import PROFILES

__all__ = [
    "compare", "configure", "current", "evaluate", "format_report", "hash_seed_is_fixed", "LOCKFILE", "main",
    "read_lock", "run_gate", "SCHEMA", "SHOWN", "update",
]

LOCKFILE = Path(__file__).with_name("derivations.lock.json")
SCHEMA = "inertiaproof.derivations-lock/1"
SHOWN = 6  # changed entries shown per object


def hash_seed_is_fixed():
    return os.environ.get("PYTHONHASHSEED") == "0"


def current(profile, progress=None):
    """Fingerprints of the profile's systems: ({object: fingerprint}, [system labels], seconds)."""
    from inertiaproof.symbolic.derivations import derivation
    from inertiaproof.symbolic.fingerprints import fingerprints
    from inertiaproof.symbolic.systems import profile_systems

    start = time.perf_counter()
    out, labels = {}, []
    for key in profile_systems(profile):
        d = derivation(key, progress=progress)
        labels.append(key.label)
        out.update(fingerprints(d))
    return out, labels, time.perf_counter() - start


def read_lock(path):
    path = Path(path)
    if not path.exists():
        return {"schema": SCHEMA, "objects": {}}
    try:
        lock = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not JSON: {exc}") from None
    if lock.get("schema") != SCHEMA or not isinstance(lock.get("objects"), dict):
        raise InputError(f"{path}: not a derivation lockfile (schema {SCHEMA})")
    return lock


def compare(locked, found, labels):
    """The gate's findings: failures (meaning changed, unlocked, removed), warnings (form only), unchanged."""
    failures, warnings, unchanged = [], [], []
    for name, new in sorted(found.items()):
        old = locked.get(name)
        if old is None:
            failures.append({"object": name, "id": new["id"], "change": "not in the lockfile",
                             "hint": "a new derived object: inertiaproof gate --update"})
        elif old["meaning"] != new["meaning"]:
            failures.append({"object": name, "id": new["id"], "change": "meaning", "what": new["what"],
                             "differences": _differences(old["meaning"], new["meaning"])})
        elif old["form"] != new["form"]:
            warnings.append({"object": name, "id": new["id"], "change": "form", "old_form": old["form"][:16],
                             "new_form": new["form"][:16]})
        else:
            unchanged.append(name)
    for name in sorted(set(locked) - set(found)):
        if name.split("/")[0] in labels:
            failures.append({"object": name, "id": locked[name]["id"], "change": "no longer derived",
                             "hint": "inertiaproof gate --update if deliberate"})
    skipped = sorted(n for n in locked if n.split("/")[0] not in labels)
    return {"failures": failures, "warnings": warnings, "unchanged": len(unchanged), "skipped": len(skipped),
            "systems": labels}


def _differences(old, new):
    out = []
    if len(old) != len(new) or any(len(a) != len(b) for a, b in zip(old, new)):
        return [{"note": f"shape changed: {[len(a) for a in old]} values -> {[len(b) for b in new]}"}]
    for point, (a, b) in enumerate(zip(old, new)):
        for entry, (x, y) in enumerate(zip(a, b)):
            if x != y:
                out.append({"point": point, "entry": entry, "old": x, "new": y})
    return out[:SHOWN] + ([{"note": f"... {len(out) - SHOWN} more"}] if len(out) > SHOWN else [])


def evaluate(profile, lockfile=LOCKFILE, progress=None):
    """The gate's report for a profile, computed in this process (which must run under PYTHONHASHSEED=0)."""
    if not hash_seed_is_fixed():
        raise RuntimeError("the gate's forms are defined under PYTHONHASHSEED=0; use run_gate()")
    lock = read_lock(lockfile)
    found, labels, seconds = current(profile, progress)
    report = compare(lock["objects"], found, labels)
    report.update(profile=profile.name, lockfile=str(lockfile), seconds=seconds, objects=len(found))
    return report, found


def run_gate(profile_name, lockfile=LOCKFILE, progress=None):
    """The gate's report whatever this process's hash seed: in process under seed 0, else in a child with seed 0."""
    if hash_seed_is_fixed():
        return evaluate(PROFILES[profile_name], lockfile, progress)[0]
    env = dict(os.environ, PYTHONHASHSEED="0")
    child = subprocess.run(command("gate", "--profile", profile_name, "--lockfile", str(lockfile), "--json"),
                           capture_output=True, text=True, env=env)
    try:
        return json.loads(child.stdout)
    except json.JSONDecodeError:
        raise RuntimeError(f"the gate under PYTHONHASHSEED=0 failed: {child.stderr.strip()[-500:]}") from None


def update(lockfile, found, labels):
    """Rewrite the lockfile's entries for these systems, keeping the others."""
    lock = read_lock(lockfile)
    objects = {k: v for k, v in lock["objects"].items() if k.split("/")[0] not in labels}
    objects.update(found)
    lock = {"schema": SCHEMA,
            "about": "fingerprints of derived objects, written by 'inertiaproof gate --update'; form = sha256 of "
                     "the canonical form under PYTHONHASHSEED=0, meaning = exact values at fixed rational points",
            "objects": dict(sorted(objects.items()))}
    Path(lockfile).write_text(json.dumps(lock, indent=1, sort_keys=True) + "\n")
    return len(found)


def format_report(report):
    lines = []
    for f in report["failures"]:
        lines.append(f"FAIL {f['object']} [{f['id']}]: {f['change']}" + (f" of {f['what']}" if "what" in f else "")
                     + (f" ({f['hint']})" if "hint" in f else ""))
        for d in f.get("differences", []):
            if "note" in d:
                lines.append(f"       {d['note']}")
            else:
                lines.append(f"       entry {d['entry']} at point {d['point']}: old {d['old']}  new {d['new']}")
    for w in report["warnings"]:
        lines.append(f"warning: {w['object']} [{w['id']}]: form changed ({w['old_form']}.. -> {w['new_form']}..), "
                     "meaning unchanged")
    verdict = "FAILED" if report["failures"] else "passed"
    lines.append(f"gate {verdict}: {report['objects']} objects of {', '.join(report['systems'])} "
                 f"({report['profile']} profile); {len(report['failures'])} failing, {len(report['warnings'])} "
                 f"form-only warnings, {report['unchanged']} unchanged, {report['skipped']} locked objects of other "
                 f"profiles not checked; {report['seconds']:.1f} s")
    return "\n".join(lines)


def configure(parser):
    parser.add_argument("--profile", choices=sorted(PROFILES), default="ci")
    parser.add_argument("--update", action="store_true", help="rewrite the lockfile's entries deliberately")
    parser.add_argument("--lockfile", default=str(LOCKFILE), metavar="FILE",
                        help="the lockfile (default: the package's derivations.lock.json)")
    parser.add_argument("--json", action="store_true", help="print the report as JSON")
    parser.add_argument("--quiet", action="store_true", help="no progress lines on stderr")


def _argv(args):
    out = ["--profile", args.profile, "--lockfile", args.lockfile]
    return out + [flag for flag, on in (("--update", args.update), ("--json", args.json),
                                        ("--quiet", args.quiet)) if on]


def main(args):
    if not hash_seed_is_fixed():
        if not args.quiet:
            print("gate: re-running under PYTHONHASHSEED=0 (SymPy's printed forms depend on the hash seed)",
                  file=sys.stderr)
        env = dict(os.environ, PYTHONHASHSEED="0")
        return subprocess.run(command("gate", *_argv(args)), env=env).returncode
    say = (lambda m: None) if args.quiet or args.json else (lambda m: print(f"gate: {m}", file=sys.stderr, flush=True))
    report, found = evaluate(PROFILES[args.profile], args.lockfile, say)
    if args.update:
        written = update(args.lockfile, found, report["systems"])
        print(f"gate: wrote {written} fingerprints of {', '.join(report['systems'])} to {args.lockfile}")
        return 0
    print(json.dumps(report, indent=1) if args.json else format_report(report))
    return 1 if report["failures"] else 0
