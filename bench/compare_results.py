"""Compare two results.json files of ``inertiaproof run`` apart from timings: every other difference is printed.

Ignored: fields that are wall-clock times (``runtime_s``, ``seconds``, ``elapsed``, keys ending in ``_s``, the
convergence traces' first column, i.e. whole ``convergence`` lists), the versions block, and certificate hashes and
paths (``sha256``, ``hash``, ``digest``, ``path``, ``file``, values naming OUT/certificates); with
``--no-certificates`` also the certificate channel itself (``certificates`` lists and ``certificate`` entries: their
status and citations), to compare the verdicts, brackets and numbers alone while that channel changes shape. Each
difference is printed as ``path: before -> after``; the exit status is 1 when there is one.

    python bench/compare_results.py [--no-certificates] BEFORE/results.json AFTER/results.json
"""

from __future__ import annotations

import json
import re
import sys

TIMING = re.compile(r"(^|_)(runtime|seconds|elapsed|time|times|wall|duration)(_s)?$|_s$|^convergence$")
HASHES = re.compile(r"(sha256|hash|digest|path|file|certificate_file)s?$")
IGNORED = {"versions", "time_per_n"}  # time_per_n: GRE's seconds per n
CERTIFICATE_VALUE = re.compile(r"(certificates/|[0-9a-f]{64})")


def differences(before, after, path="", ignored=frozenset(IGNORED)):
    """(path, before, after) for every difference of two JSON values outside the ignored fields."""
    if isinstance(before, dict) and isinstance(after, dict):
        for key in sorted(set(before) | set(after)):
            if key in ignored or TIMING.search(key) or HASHES.search(key):
                continue
            if key not in before or key not in after:
                yield f"{path}/{key}", before.get(key, "<missing>"), after.get(key, "<missing>")
                continue
            yield from differences(before[key], after[key], f"{path}/{key}", ignored)
    elif isinstance(before, list) and isinstance(after, list):
        if len(before) != len(after):
            yield f"{path}[len]", len(before), len(after)
        for i, (b, a) in enumerate(zip(before, after)):
            yield from differences(b, a, f"{path}[{_name(b, i)}]", ignored)
    elif isinstance(before, str) and isinstance(after, str):
        if before != after and CERTIFICATE_VALUE.sub("", before) != CERTIFICATE_VALUE.sub("", after):
            if _strip_times(before) != _strip_times(after):
                yield path, before, after
    elif before != after:
        yield path, before, after


def _strip_times(text):
    """A text with its wall-clock mentions ("in 1.2 s", "(3.4 s)") left out."""
    return re.sub(r"\d+(\.\d+)?(e[-+]?\d+)? ?(s|ms|seconds)\b", "<t>", text)


def _name(item, index):
    return item.get("id", index) if isinstance(item, dict) else index


def main(argv):
    ignored = set(IGNORED)
    if argv[:1] == ["--no-certificates"]:
        argv, ignored = argv[1:], ignored | {"certificates", "certificate"}
    if len(argv) != 2:
        raise SystemExit(__doc__)
    with open(argv[0]) as f:
        before = json.load(f)
    with open(argv[1]) as f:
        after = json.load(f)
    found = list(differences(before, after, ignored=frozenset(ignored)))
    for path, b, a in found:
        print(f"{path}: {json.dumps(b)[:300]} -> {json.dumps(a)[:300]}")
    print(f"{len(found)} differences")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
