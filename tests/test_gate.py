"""The derivation gate: passes on a clean copy, fails on a changed meaning, warns on a changed form, any hash seed."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from inertiaproof.checks.derivation_gate import gate_result
from inertiaproof.symbolic import gate

from inertiaproof.result import Verdict

REPO = Path(__file__).resolve().parents[1]
# run the copy's package in place of the installed (possibly editable) one
BOOTSTRAP = """
import sys
sys.meta_path[:] = [f for f in sys.meta_path if not getattr(f, "__module__", "").startswith("__editable__")]
sys.path.insert(0, sys.argv[1])
from inertiaproof.cli import main
sys.exit(main(sys.argv[2:]))
"""


def package_copy(tmp_path):
    """The package laid out as installed (inertiaproof/, inertiaproof/symbolic, ...), from this checkout."""
    root = tmp_path / "pkg"
    shutil.copytree(REPO / "inertiaproof", root / "inertiaproof", ignore=shutil.ignore_patterns("__pycache__"))
    for sub in ("symbolic", "checks", "counterexamples", "report"):
        shutil.copytree(REPO / sub, root / "inertiaproof" / sub, ignore=shutil.ignore_patterns("__pycache__"))
    return root


def edit(root, module, old, new):
    path = root / "inertiaproof" / "symbolic" / module
    text = path.read_text()
    assert old in text, f"{old!r} not in {module}"
    path.write_text(text.replace(old, new, 1))


def run_copy(root, tmp_path, *args, seed="0"):
    env = dict(os.environ, PYTHONHASHSEED=seed, INERTIAPROOF_CACHE=str(tmp_path / "cache"))
    lock = tmp_path / "derivations.lock.json"
    if not lock.exists():
        shutil.copy(REPO / "symbolic" / "derivations.lock.json", lock)
    return subprocess.run([sys.executable, "-c", BOOTSTRAP, str(root), "gate", "--lockfile", str(lock), "--quiet",
                           *args], capture_output=True, text=True, env=env, timeout=300)


@pytest.mark.slow
def test_clean_copy_passes_under_any_hash_seed(tmp_path):
    root = package_copy(tmp_path)
    first = run_copy(root, tmp_path, "--json", seed="0")
    second = run_copy(root, tmp_path, "--json", seed="12345")
    assert first.returncode == 0, first.stdout + first.stderr
    assert second.returncode == 0, second.stdout + second.stderr
    a, b = json.loads(first.stdout), json.loads(second.stdout)
    for report in (a, b):
        report.pop("seconds")
    assert a == b and not a["failures"] and not a["warnings"]


@pytest.mark.parametrize("module, old, new, affected", [
    ("robotics_equation.py", "a[k][j] - a[j][k]", "a[j][k] - a[k][j]", "GRE"),  # a sign in (DefH)
    pytest.param("lagrangian.py", "kinetic += quadratic_form(velocity, spatial_inertia(phi), velocity) / 2",
                 "kinetic += quadratic_form(velocity, spatial_inertia(phi), velocity)", "GRE",
                 marks=pytest.mark.slow),  # a factor 1/2 in T
])
def test_edited_derivation_fails_with_old_and_new_values(tmp_path, module, old, new, affected):
    root = package_copy(tmp_path)
    edit(root, module, old, new)
    out = run_copy(root, tmp_path)
    assert out.returncode == 1, out.stdout + out.stderr
    assert f"[{affected}]: meaning" in out.stdout
    assert " old " in out.stdout and " new " in out.stdout and "gate FAILED" in out.stdout


@pytest.mark.slow
def test_renamed_symbols_change_the_form_only(tmp_path):
    root = package_copy(tmp_path)
    edit(root, "jets.py", 'Generator("cos", (k,), f"c{k}")', 'Generator("cos", (k,), f"cos_q{k}")')
    out = run_copy(root, tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "warning:" in out.stdout and "form changed" in out.stdout and "gate passed" in out.stdout


def test_gate_checker_reports_violated_on_a_changed_meaning():
    report = {"failures": [{"object": "3R/C", "id": "GRE", "change": "meaning", "what": "C",
                            "differences": [{"point": 0, "entry": 1, "old": "1/2", "new": "1"}]}],
              "warnings": [], "unchanged": 3, "skipped": 0, "systems": ["3R"], "objects": 4, "seconds": 0.1,
              "profile": "ci", "lockfile": "x"}
    result = gate_result(report)
    assert result.verdict == Verdict.VIOLATED and "GRE" in result.summary
    assert result.counterexample["kind"] == "gate"


def test_compare_classifies_changes():
    fp = {"id": "GRE", "what": "M", "form": "aaa", "meaning": [["1", "2"]]}
    locked = {"2R/M": fp, "2R/C": fp, "6R/M": fp}
    found = {"2R/M": dict(fp, form="bbb"), "2R/G": fp}
    report = gate.compare(locked, found, ["2R"])
    changes = {f["object"]: f["change"] for f in report["failures"]}
    assert changes == {"2R/G": "not in the lockfile", "2R/C": "no longer derived"}
    assert [w["object"] for w in report["warnings"]] == ["2R/M"] and report["skipped"] == 1
    report = gate.compare(locked, {"2R/M": dict(fp, meaning=[["1", "3"]]), "2R/C": fp}, ["2R"])
    assert report["failures"][0]["differences"] == [{"point": 0, "entry": 1, "old": "2", "new": "3"}]


def test_bad_lockfile_is_a_one_line_error(tmp_path):
    from inertiaproof.errors import InputError

    bad = tmp_path / "lock.json"
    bad.write_text("{not json")
    with pytest.raises(InputError, match="not JSON"):
        gate.read_lock(bad)
