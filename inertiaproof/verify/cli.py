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

from .claims import prove, side, statement
from .exact import BadCertificate, need, read_json
from .outcome import REFUTED, REPROVED, UNPROVED, Outcome
from .product import UNIT

BAD = "bad certificate"
SIZE = 64 * 2**20  # the largest certificate file read (bytes)
CERTIFIED = "certified_constant"  # the kind of number in results.json that must cite a certificate
DEFINITIONS = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)  # what may have a docstring


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
        out = prove(cert)
        claim = statement(cert)
    except BadCertificate as exc:
        out = Outcome(BAD, str(exc))
    except Exception as exc:  # noqa: BLE001 - whatever goes wrong inside the checker proves nothing
        out = Outcome(UNPROVED, f"{type(exc).__name__}: {exc}")
    return {"claim": claim, **out._asdict(), "seconds": round(time.perf_counter() - start, 4)}


def verify_file(path):
    """:func:`check` of a certificate file, with its name. A file named by 16 hex digits (as a run writes them) must
    hold what they are the SHA-256 of, so a number altered in it is a bad certificate, not another claim."""
    path = Path(path)
    try:
        need(path.stat().st_size <= SIZE, f"larger than {SIZE} bytes")
        text = path.read_text()
        cert, name = read_json(text), hashlib.sha256(text.encode()).hexdigest()[:16]
        need(not re.fullmatch(r"[0-9a-f]{16}", path.stem) or path.stem == name,
             f"its content is not what its name says (SHA-256 {name}...): altered")
    except (OSError, UnicodeDecodeError, BadCertificate, RecursionError) as exc:
        why = str(exc) if isinstance(exc, BadCertificate) else f"cannot be read: {exc}"
        return {"file": str(path), "claim": "", **Outcome(BAD, why)._asdict(), "seconds": 0.0}
    return {"file": str(path), **check(cert)}


def _problem(out, rows, number, entry):
    """Why a citation in results.json of the run folder ``out`` does not hold, or None: its certificate (``entry``)
    is among ``rows``, re-proved, with the claim it says; the number citing it (if any: ``number``) is implied by
    that claim, a lower side at most its bound, an upper one at least it (``as`` "root": its square, an upper side of
    a claim on (QJ)^T QJ)."""
    file = entry.get("file") if isinstance(entry, dict) else None
    row = rows.get(file) if isinstance(file, str) else None
    if entry is None:
        return "a certified number that cites no certificate"
    if row is None:
        return f"cites {file if isinstance(entry, dict) else entry!r}, which is not among the certificates"
    if row["status"] != REPROVED:
        return f"cites {file}, {row['status']}"
    if entry.get("claim") != row["claim"]:
        return f"says the claim is {entry.get('claim')!r}; the certificate claims {row['claim']!r}"
    if number is None:
        return None
    value, cert = number.get("value"), read_json((out / file).read_text())
    if type(value) not in (int, float) or value != value or abs(value) == float("inf"):
        return f"the number {value!r} is not finite"
    claim = cert["claim"]
    relation, bound = side(claim), Fraction(claim["upper" if claim["kind"] == "key-step" else "bound"])
    if {"lower_bound": ">=", "upper_bound": "<="}.get(number.get("kind"), relation) != relation:
        return f"a {number.get('kind')} cites a {relation} claim"
    value = Fraction(value)
    if entry.get("as") == "root":
        qj = claim["kind"] == "mass-matrix-spectrum" and cert["parameters"] == [[UNIT] * len(cert["chain"]["joints"])]
        if relation != "<=" or value < 0 or not qj:
            return "only an upper side of sigma_max(QJ) is the root of a claim on (QJ)^T QJ"
        value *= value
    if value > bound if relation == ">=" else value < bound:
        return f"the number {number['value']!r} is not implied by the claim ({relation} {float(bound)!r})"
    return None


def _citations(node, path):
    """(path, the quantity or None, the certificate entry) of every citation in results.json's evidence, and
    (path, quantity, None) of every certified number that cites none."""
    if isinstance(node, dict):
        if node.get("certificate") is not None or node.get("kind") == CERTIFIED and "value" in node:
            yield path, (node if "value" in node else None), node.get("certificate")
        for k, v in node.items():
            yield from _citations(v, f"{path}/{k}")
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _citations(v, f"{path}[{i}]")


def results_problems(out, rows):
    """Every way results.json of the run folder ``out`` does not hold together with its certificates (``rows``: the
    checker's answers by file name), and the count of numbers citing one."""
    try:
        checks = read_json((out / "results.json").read_text(), floats=True)["checks"]
        need(isinstance(checks, list) and all(isinstance(c, dict) for c in checks), "checks: a list of objects")
    except (OSError, BadCertificate, KeyError, TypeError, RecursionError) as exc:
        return [f"cannot be read as a run's results ({exc})"], 0
    cited = [found for c in checks for found in _citations(c.get("evidence"), str(c.get("id")))]
    problems = [f"{path}: {why}" for path, number, entry in cited if (why := _problem(out, rows, number, entry))]
    return problems, sum(number is not None for _, number, _ in cited)


def code_lines(source):
    """The lines of ``source`` that hold code: not blank, not only a comment, not in a docstring."""
    docs = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, DEFINITIONS) and ast.get_docstring(node, clean=False) is not None:
            docs.update(range(node.body[0].lineno, node.body[0].end_lineno + 1))
    lines = [line.strip() for i, line in enumerate(source.splitlines(), 1) if i not in docs]
    return sum(1 for line in lines if line and not line.startswith("#"))


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
        line = f"{row['status']:>15}  {path.name}: {row['why']} ({row['seconds']:.2f} s)"
        print(json.dumps(row) if args.json else line)
    counts = {s: sum(r["status"] == s for r in rows.values()) for s in (REPROVED, REFUTED, UNPROVED, BAD)}
    print(", ".join(f"{n} {s}" for s, n in counts.items()), file=sys.stderr)
    problems = 0
    for out in dict.fromkeys(p for p in args.paths if (p / "results.json").is_file()):
        found, numbers = results_problems(out, {f"certificates/{p.name}": r for p, r in rows.items()
                                                if p.parent == out / "certificates"})
        problems += len(found)
        print(f"{out}/results.json: {numbers} certified number(s), {len(found)} problem(s)",
              *(f"{out}/results.json: {problem}" for problem in found), sep="\n", file=sys.stderr)
    return 1 if counts[REFUTED] else 2 if counts[BAD] or problems else 3 if counts[UNPROVED] else 0


def command(argv):
    """``inertiaproof verify`` on its own: the checker's process imports nothing but this package, flint and the
    standard library."""
    parser = argparse.ArgumentParser(prog="inertiaproof verify", description="re-prove certificates with the "
                                     "independent checker", epilog=__doc__.split("\n\n")[1])
    configure(parser)
    return main(parser.parse_args(argv))
