"""``inertiaproof verify PATH ...``: re-prove certificates (files, folders, or a run's OUT folder, whose
results.json is read too: every number it calls certified cites a certificate there that is re-proved and implies
it).

Exit status: 0 every claim re-proved; 1 something refuted; 2 a bad certificate, a results.json that does not hold
together, or bad usage; 3 something not re-proved and nothing refuted or bad.
"""

import argparse
import ast
import hashlib
import json
import re
import sys
import time
from fractions import Fraction
from pathlib import Path

from .claims import prove, statement
from .exact import BadCertificate, read_json
from .outcome import REFUTED, REPROVED, UNPROVED
from .product import UNIT

BAD = "bad certificate"
STATUSES = (REPROVED, REFUTED, UNPROVED, BAD)
SIZE = 64 * 2**20  # the largest certificate file read (bytes)
CERTIFIED = "certified_constant"  # the kind of number in results.json that must cite a certificate


def configure(parser):
    parser.add_argument("paths", nargs="*", type=Path, help="certificate files, folders of them, or a run's OUT "
                        "folder (its certificates/ and results.json)")
    parser.add_argument("--json", action="store_true", help="one JSON object per certificate on stdout")
    parser.add_argument("--about", action="store_true", help="what the checker is and its size in lines")


def check(cert):
    """{claim, status, why, boxes, where, seconds} of one certificate (parsed JSON); status "bad certificate" when
    it is malformed (why names the field), "not re-proved" when a step fails in a way no field names."""
    start, claim = time.perf_counter(), ""
    try:
        out = prove(cert).to_json()
        claim = statement(cert)
    except BadCertificate as exc:
        out = {"status": BAD, "why": str(exc), "boxes": 0, "where": None}
    except Exception as exc:  # noqa: BLE001 - whatever goes wrong inside the checker proves nothing
        out = {"status": UNPROVED, "why": f"{type(exc).__name__}: {exc}", "boxes": 0, "where": None}
    return {"claim": claim, **out, "seconds": round(time.perf_counter() - start, 4)}


def verify_file(path):
    """:func:`check` of a certificate file, with its name. A file named by 16 hex digits (as a run writes them) must
    hold what they are the SHA-256 of, so a number altered in it is a bad certificate, not another claim."""
    path = Path(path)
    bad = {"file": str(path), "claim": "", "status": BAD, "boxes": 0, "where": None, "seconds": 0.0}
    try:
        if path.stat().st_size > SIZE:
            return {**bad, "why": f"larger than {SIZE} bytes"}
        text = path.read_text()
        cert = read_json(text)
    except (OSError, UnicodeDecodeError, BadCertificate, RecursionError) as exc:
        return {**bad, "why": f"cannot be read: {exc}"}
    name = hashlib.sha256(text.encode()).hexdigest()[:16]
    if re.fullmatch(r"[0-9a-f]{16}", path.stem) and path.stem != name:
        return {**bad, "why": f"its content is not what its name says (SHA-256 {name}...): altered"}
    return {"file": str(path), **check(cert)}


def _implied(number, cert, entry):
    """Why the results.json ``number`` (a quantity citing ``cert``) is not implied by the certificate's claim, or
    None: a lower side at most the claim's bound, an upper one at least it (or, ``as`` "root", the number's square
    at least a claim on (QJ)^T QJ)."""
    value, claim = number.get("value"), cert["claim"]
    if type(value) not in (int, float) or value != value or abs(value) == float("inf"):
        return f"the number {value!r} is not finite"
    side = "<=" if claim["kind"] == "key-step" else claim.get("relation") or (
        ">=" if claim["quantity"].startswith("lambda_min") or claim["kind"] == "residual-bound" else "<=")
    bound = Fraction(claim["upper"] if claim["kind"] == "key-step" else claim["bound"])
    if {"lower_bound": ">=", "upper_bound": "<="}.get(number.get("kind"), side) != side:
        return f"a {number.get('kind')} cites a {side} claim"
    value = Fraction(value)
    if entry.get("as") == "root":
        unit = claim["kind"] == "mass-matrix-spectrum" and cert.get("parameters") == [[UNIT] * len(
            cert["chain"]["joints"])]
        if side != "<=" or value < 0 or not unit:
            return "only an upper side of sigma_max(QJ) is the root of a claim on (QJ)^T QJ"
        value = value * value
    if value > bound if side == ">=" else value < bound:
        return f"the number {number['value']!r} is not implied by the claim ({side} {float(bound)!r})"
    return None


def _numbers(node, path):
    """(path, the quantity or None, the certificate entry) of every citation in results.json's evidence, and
    (path, quantity, None) of every certified number that cites none."""
    if isinstance(node, dict):
        entry = node.get("certificate")
        if entry is not None or node.get("kind") == CERTIFIED and "value" in node:
            yield path, (node if "value" in node else None), entry
        for k, v in node.items():
            yield from _numbers(v, f"{path}/{k}")
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _numbers(v, f"{path}[{i}]")


def results_problems(out, rows):
    """Every way results.json of the run folder ``out`` does not hold together with its certificates (``rows``: the
    checker's answers by file name), and the count of numbers citing one."""
    try:
        checks = read_json((out / "results.json").read_text(), floats=True)["checks"]
        assert isinstance(checks, list) and all(isinstance(c, dict) for c in checks)
    except (OSError, BadCertificate, KeyError, TypeError, AssertionError, RecursionError) as exc:
        return [f"cannot be read as a run's results ({exc})"], 0
    problems, numbers = [], 0
    for result in checks:
        for path, number, entry in _numbers(result.get("evidence"), str(result.get("id"))):
            numbers += number is not None
            row = rows.get(entry.get("file")) if isinstance(entry, dict) else None
            if entry is None:
                problems.append(f"{path}: a certified number that cites no certificate")
            elif row is None:
                cited = entry.get("file") if isinstance(entry, dict) else entry
                problems.append(f"{path}: cites {cited!r}, which is not among the certificates")
            elif row["status"] != REPROVED:
                problems.append(f"{path}: cites {entry['file']}, {row['status']}")
            elif entry.get("claim") != row["claim"]:
                problems.append(f"{path}: says the claim is {entry.get('claim')!r}; the certificate claims "
                                f"{row['claim']!r}")
            elif number is not None:
                why = _implied(number, read_json((out / entry["file"]).read_text()), entry)
                problems += [f"{path}: {why}"] if why else []
    return problems, numbers


def code_lines(source):
    """The lines of ``source`` that hold code: not blank, not only a comment, not in a docstring."""
    docs = set()
    for node in ast.walk(ast.parse(source)):
        first = getattr(node, "body", None)
        if isinstance(first, list) and first and isinstance(first[0], ast.Expr) \
                and isinstance(first[0].value, ast.Constant) and isinstance(first[0].value.value, str):
            docs.update(range(first[0].lineno, first[0].end_lineno + 1))
    return sum(1 for i, line in enumerate(source.splitlines(), 1)
               if i not in docs and line.strip() and not line.strip().startswith("#"))


def about():
    here = Path(__file__).parent
    sources = [p.read_text() for p in here.glob("*.py")]
    return (f"inertiaproof's independent checker ({here}): {sum(len(s.splitlines()) for s in sources)} lines of "
            f"Python ({sum(map(code_lines, sources))} of code, the rest docstrings and comments) in {len(sources)} "
            "modules, importing only python-flint and the standard library")


def main(args):
    if args.about:
        print(about())
        return 0
    files = [p for path in args.paths for p in (sorted((path / "certificates" if (path / "certificates").is_dir()
                                                        else path).glob("*.json")) if path.is_dir() else [path])]
    if not files:
        print("inertiaproof verify: no certificate found in " + ", ".join(map(str, args.paths)), file=sys.stderr)
        return 2
    rows = {}
    for path in files:
        rows[path] = row = verify_file(path)
        print(json.dumps(row) if args.json else
              f"{row['status']:>15}  {path.name}: {row['why']} ({row['seconds']:.2f} s)")
    counts = {s: sum(r["status"] == s for r in rows.values()) for s in STATUSES}
    print(", ".join(f"{n} {s}" for s, n in counts.items()), file=sys.stderr)
    problems = []
    for out in dict.fromkeys(p for p in args.paths if (p / "results.json").is_file()):
        found, numbers = results_problems(out, {f"certificates/{p.name}": r for p, r in rows.items()
                                                if p.parent == out / "certificates"})
        problems += [f"{out}/results.json: {p}" for p in found]
        print(f"{out}/results.json: {numbers} certified number(s), {len(found)} problem(s)", file=sys.stderr)
    for problem in problems:
        print(problem, file=sys.stderr)
    return 1 if counts[REFUTED] else 2 if counts[BAD] or problems else 3 if counts[UNPROVED] else 0


def command(argv):
    """``inertiaproof verify`` on its own: the checker's process imports nothing but this package, flint and the
    standard library."""
    parser = argparse.ArgumentParser(prog="inertiaproof verify", description="re-prove certificates with the "
                                     "independent checker", epilog=__doc__.split("\n\n")[1])
    configure(parser)
    return main(parser.parse_args(argv))
