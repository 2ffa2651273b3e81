"""The import graph of inertiaproof and its circles (issue 25).

Dependencies point one way: no module imports another that imports it back, lazily inside a
function included. This script parses every module of the distribution (the folders that
``pyproject.toml`` maps to ``inertiaproof``, ``inertiaproof.symbolic``, ``inertiaproof.checks``, ...)
with :mod:`ast`, collects every import statement wherever it stands (top level, inside a function,
under ``if __name__ == "__main__":``), builds the module graph and prints its strongly connected
components of more than one module. Exit status 1 if there is one.

Edges:

- ``import a.b.c`` is an edge to ``a.b.c`` (or to its longest prefix that is a module of ours), and so is
  ``importlib.import_module("a.b.c")`` with a literal name (computed names are not followed);
- ``from X import name`` is an edge to ``X.name`` when that is a module (``from . import x`` is an
  edge to the submodule ``x``), otherwise to ``X`` (importing a name re-exported by a package's
  ``__init__`` is an edge to the package);
- relative imports are resolved against the importing module;
- the parent packages that Python executes on the way (``import a.b.c`` runs ``a/__init__`` and
  ``a/b/__init__``) are not edges: otherwise every submodule would be in a circle with a package
  ``__init__`` that re-exports it.

    python bench/import_graph.py            # the circles; exit 1 if any
    python bench/import_graph.py --edges    # and every edge
"""

from __future__ import annotations

import ast
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Import:
    """One import statement's target, as written and resolved."""

    source: str  # the importing module
    target: str  # the imported module (absolute dotted name)
    line: int
    lazy: bool  # inside a function, a class or an ``if``/``try`` block


def package_folders(root: Path = ROOT) -> dict[str, Path]:
    """Package name -> its folder, from ``[tool.setuptools]`` in pyproject.toml."""
    config = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]
    mapping = config.get("package-dir", {})
    folders = {}
    for package in config["packages"]:
        parts = package.split(".")
        for i in range(len(parts), 0, -1):  # the longest mapped prefix
            prefix = ".".join(parts[:i])
            if prefix in mapping:
                folders[package] = root / mapping[prefix] / Path(*parts[i:])
                break
        else:
            folders[package] = root / Path(*parts)
    return folders


def module_files(root: Path = ROOT) -> dict[str, Path]:
    """Module name -> its file, for every module of every package (a package is its ``__init__``)."""
    modules = {}
    for package, folder in package_folders(root).items():
        for path in sorted(folder.glob("*.py")):
            modules[package if path.stem == "__init__" else f"{package}.{path.stem}"] = path
    return modules


def _resolve_relative(module: str, is_package: bool, level: int, name: str | None) -> str:
    base = module.split(".") if is_package else module.split(".")[:-1]
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join([*base, *([name] if name else [])])


def _statements(tree: ast.Module):
    """Every import statement, with whether it stands outside the module's top level; and every call
    ``importlib.import_module("name")`` or ``__import__("name")`` with a literal name, as ``import name``."""
    top = set(map(id, tree.body))
    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node, id(node) not in top
        elif (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
              and isinstance(node.args[0].value, str) and not node.args[0].value.startswith(".")
              and (isinstance(node.func, ast.Attribute) and node.func.attr == "import_module"
                   or isinstance(node.func, ast.Name) and node.func.id in ("import_module", "__import__"))):
            yield ast.Import([ast.alias(node.args[0].value)], lineno=node.lineno), True


def imports(module: str, path: Path, modules: dict[str, Path]) -> list[Import]:
    """The targets of every import statement of one module; outside modules keep their full name."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    is_package = path.stem == "__init__"

    def ours(name: str) -> str:
        parts = name.split(".")
        for i in range(len(parts), 0, -1):
            if ".".join(parts[:i]) in modules:
                return ".".join(parts[:i])
        return name

    found = []
    for node, lazy in _statements(tree):
        if isinstance(node, ast.Import):
            targets = [ours(alias.name) for alias in node.names]
        else:
            base = (_resolve_relative(module, is_package, node.level, node.module) if node.level
                    else node.module)
            targets = []
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                targets.append(sub if sub in modules else ours(base))
        found += [Import(module, t, node.lineno, lazy) for t in dict.fromkeys(targets) if t != module]
    return found


def graph(root: Path = ROOT) -> dict[str, set[str]]:
    """Module -> the modules of ours it imports."""
    modules = module_files(root)
    return {m: {i.target for i in imports(m, p, modules) if i.target in modules} for m, p in modules.items()}


def all_imports(root: Path = ROOT) -> list[Import]:
    modules = module_files(root)
    return [i for m, p in modules.items() for i in imports(m, p, modules)]


def circles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan), each sorted, largest first."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    counter = 0
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges.get(child, ())))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return sorted(found, key=lambda c: (-len(c), c))


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    every = all_imports()
    edges = graph()
    if "--edges" in argv:
        for i in every:
            if i.target in edges:
                print(f"{i.source} -> {i.target}  (line {i.line}{', lazy' if i.lazy else ''})")
    found = circles(edges)
    for component in found:
        members = set(component)
        print(f"circle of {len(component)} modules: {', '.join(component)}")
        for i in every:
            if i.source in members and i.target in members:
                print(f"    {i.source} -> {i.target}  (line {i.line}{', lazy' if i.lazy else ''})")
    print(f"{len(edges)} modules, {sum(map(len, edges.values()))} imports between them, {len(found)} circles")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
