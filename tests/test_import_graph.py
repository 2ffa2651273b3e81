"""Dependencies point one way (issue 25): no module of the distribution imports another that imports it back,
lazily inside a function included (bench/import_graph.py); and the independent checker inertiaproof.verify imports
nothing of inertiaproof outside itself, and nothing outside the standard library and python-flint."""

import importlib.util
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def import_graph():
    spec = importlib.util.spec_from_file_location("bench_import_graph", ROOT / "bench" / "import_graph.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_no_module_imports_one_that_imports_it_back(import_graph, capsys):
    edges = import_graph.graph()
    assert import_graph.circles(edges) == []
    assert import_graph.main([]) == 0
    assert "0 circles" in capsys.readouterr().out


def test_every_folder_of_the_distribution_is_parsed(import_graph):
    modules = import_graph.module_files()
    for name in ("inertiaproof", "inertiaproof.bounds.configuration", "inertiaproof.verify.claims",
                 "inertiaproof.symbolic.cache", "inertiaproof.checks.constant_hunt", "inertiaproof.report.cli"):
        assert name in modules
    assert modules["inertiaproof.checks.constant_hunt"] == ROOT / "checks" / "constant_hunt.py"
    edges = import_graph.graph()
    assert "inertiaproof.bounds.lengths" in edges["inertiaproof.bounds.taylor"]
    assert "inertiaproof.checks.constant_hunt" in edges["inertiaproof.checks.mass_matrix_bounds"]


def test_a_lazy_relative_circle_is_found(import_graph, tmp_path):
    """The script finds a circle closed by an import inside a function, a relative one and one under
    ``if __name__ == "__main__":``; a package __init__ re-exporting its submodules is no circle."""
    (tmp_path / "pyproject.toml").write_text(textwrap.dedent("""
        [tool.setuptools]
        packages = ["pkg", "pkg.sub", "pkg.extra"]
        [tool.setuptools.package-dir]
        "pkg" = "pkg"
        "pkg.extra" = "extra"
    """))
    for folder in ("pkg", "pkg/sub", "extra"):
        (tmp_path / folder).mkdir()
    files = {
        "pkg/__init__.py": "from . import low\nfrom .sub import a\n",
        "pkg/low.py": "import json\n",
        "pkg/sub/__init__.py": "from .a import helper\n",
        "pkg/sub/a.py": "from .. import low\nfrom .b import thing\n\ndef helper():\n    pass\n",
        "pkg/sub/b.py": "def thing():\n    from pkg.sub.a import helper\n    return helper\n",
        "extra/__init__.py": "",
        "extra/c.py": "from pkg.sub import helper\n",
        "extra/d.py": "import pkg.extra.c\n",
        "extra/e.py": "import pkg.low\nif __name__ == '__main__':\n    from pkg.extra import f\n",
        "extra/f.py": "from pkg.extra.e import x\n",
    }
    for path, text in files.items():
        (tmp_path / path).write_text(text)
    edges = import_graph.graph(tmp_path)
    assert edges["pkg"] == {"pkg.low", "pkg.sub.a"}
    assert edges["pkg.sub.a"] == {"pkg.low", "pkg.sub.b"}
    assert edges["pkg.extra.c"] == {"pkg.sub"}  # a name re-exported by the package's __init__: the package
    assert import_graph.circles(edges) == [["pkg.extra.e", "pkg.extra.f"], ["pkg.sub.a", "pkg.sub.b"]]


def test_the_checker_imports_only_itself_the_standard_library_and_flint(import_graph):
    modules = import_graph.module_files()
    found = [i for i in import_graph.all_imports() if i.source.split(".")[:2] == ["inertiaproof", "verify"]]
    assert found  # the checker's modules were parsed
    inside = [i for i in found if i.target in modules]
    assert inside and all(i.target.split(".")[:2] == ["inertiaproof", "verify"] for i in inside), \
        [f"{i.source} -> {i.target} (line {i.line})" for i in inside if not i.target.startswith("inertiaproof.verify")]
    outside = [i for i in found if i.target not in modules]
    foreign = [f"{i.source} -> {i.target} (line {i.line})" for i in outside
               if i.target.split(".")[0] not in sys.stdlib_module_names | {"flint"}]
    assert not foreign, foreign
    assert not [i for i in outside if i.target.split(".")[0] == "inertiaproof"]  # no missing module of ours
