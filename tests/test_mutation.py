"""bench/mutation.py: the project's mutants still match the code, the staging tree is the package, stale mutants
are reported, and the kill table goes into the report's appendix."""

import importlib.util
import os
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from inertiaproof.report import content, load
from inertiaproof.report.model import Section
from inertiaproof.suite.discovery import load_checks

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def mutation():
    spec = importlib.util.spec_from_file_location("bench_mutation", ROOT / "bench" / "mutation.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_at_least_40_mutants_spread_over_the_core(mutation):
    mutants = mutation.MUTANTS
    assert len(mutants) >= 40
    assert len({m.id for m in mutants}) == len(mutants)
    areas = Counter(m.area for m in mutants)
    assert set(areas) == {"model", "dynamics", "bounds", "symbolic", "classifier"} and min(areas.values()) >= 5


def test_every_pattern_matches_its_file_once(mutation):
    """A mutant whose pattern no longer matches is stale: re-target it (pattern and replacement on its file)."""
    stale = [(m.id, m.file, mutation.matches(ROOT, m)) for m in mutation.MUTANTS if mutation.matches(ROOT, m) != 1]
    assert not stale, f"stale mutants (id, file, matches): {stale}"
    assert all(m.pattern != m.replacement for m in mutation.MUTANTS)


def test_every_reach_names_a_check(mutation):
    checks = load_checks()
    known = {s.id for s in checks.values()} | set(checks)
    assert {r for m in mutation.MUTANTS for r in m.reach} <= known


def test_the_staged_tree_is_the_package(mutation, tmp_path):
    folders = mutation.stage(ROOT, tmp_path)
    staged = mutation.staged_path(folders, "symbolic/kinematics.py")
    assert staged == tmp_path / "inertiaproof" / "symbolic" / "kinematics.py" and staged.is_file()
    assert mutation.staged_path(folders, "inertiaproof/model/inertia.py") == tmp_path / "inertiaproof" / "model" / "inertia.py"
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    where = subprocess.run([sys.executable, "-c", "import inertiaproof.symbolic.kinematics as k; print(k.__file__)"],
                           env=env, capture_output=True, text=True, cwd=tmp_path, check=True).stdout.strip()
    assert Path(where) == staged


def test_a_mutant_that_no_longer_matches_is_stale(mutation, tmp_path):
    folders = mutation.stage(ROOT, tmp_path / "site")
    gone = mutation.Mutant("gone", "model", "inertiaproof/model/inertia.py", "this text is not in the file", "x", "none")
    row = mutation.judge(gone, tmp_path / "site", folders, tmp_path / "cache", tmp_path, full=False)
    assert row["status"] == "stale" and "0 times" in row["why"]


def test_the_kill_table_is_the_reports_appendix(tmp_path):
    table = {"schema": load.MUTATION_SCHEMA, "summary": {"mutants": 2, "killed": 1, "survived": 0, "stale": 0,
                                                         "inconclusive": 0, "equivalent": 1},
             "baseline": {"exit": 0, "seconds": 30.0},
             "mutants": [{"id": "model-z-sign", "area": "model", "what": "sign", "status": "killed",
                          "killed_by": ["GRE", "Prop1:numeric"], "equivalent": ""},
                         {"id": "dyn-christoffel-index", "area": "dynamics", "what": "swap", "status": "survived",
                          "killed_by": [], "equivalent": "M is symmetric"}]}
    path = tmp_path / load.MUTATION
    path.write_text(__import__("json").dumps(table))
    found = load.mutation(tmp_path, fallback=tmp_path / "none.json")
    assert found == (path, table)
    doc = content.build({"checks": [], "runtime_s": 1.0}, {}, found)
    appendix = doc.sections[-1]
    assert isinstance(appendix, Section) and appendix.key == "mutation"
    text = repr(appendix)
    assert "model-z-sign" in text and "Prop1:numeric" in text and "M is symmetric" in text
    assert load.mutation(tmp_path / "nothing", fallback=tmp_path / "none.json") is None
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / load.MUTATION).write_text("{}")
    assert "not a mutation table" in load.mutation(tmp_path / "bad")[1]
