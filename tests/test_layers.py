"""The import graph of ``solver/``, read from the source (nothing is
imported): no cycle between modules, no import of a higher layer, and no
private (underscore) name imported from another module.

The layers, lowest first (a package may import only packages of lower
layers; packages on one layer are independent of each other):

errors, version → linalg, geometry, verification → ncp → problem →
examples → contact → mpi → front → output, studies → cli → the package
itself (``solver/__init__.py``, ``__main__``).

``ncp`` may use ``linalg`` (the BLAS thread limits); ``output`` never
imports ``contact`` or ``front`` (it writes what a result holds). The
reference for the rule: import-linter's "layers" contract, written out
here so that no extra dependency is needed.
"""

import ast
import collections
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1] / "solver"

LAYERS = [
    {"errors", "version"},
    {"linalg", "geometry", "verification"},
    {"ncp"},
    {"problem"},
    {"examples"},
    {"contact"},
    {"mpi"},
    {"front"},
    {"output", "studies", "studies3d"},
    {"cli"},
    {"solver", "__main__"},
]


def modules():
    """{module name: path} of every module under solver/."""
    out = {}
    for path in ROOT.rglob("*.py"):
        parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def imports():
    """(importer, imported module, names) for every import of solver."""
    mods = modules()
    found = []
    for name, path in mods.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        package = path.name == "__init__.py"
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parts = name.split(".") if package else \
                        name.split(".")[:-1]
                    parts = parts[:len(parts) - (node.level - 1)]
                    base = ".".join(parts + ([base] if base else []))
                if not base.startswith("solver"):
                    continue
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    target = sub if sub in mods else base
                    found.append((name, target, alias.name))
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.startswith("solver"):
                        found.append((name, alias.name, None))
    return found


def layer_of(module):
    parts = module.split(".")
    top = parts[1] if len(parts) > 1 else parts[0]
    for level, members in enumerate(LAYERS):
        if top in members:
            return level, top
    raise AssertionError(f"{module}: package {top!r} is in no layer of "
                         "tests/test_layers.py (add it)")


def test_no_import_cycle():
    mods = modules()
    graph = collections.defaultdict(set)
    for importer, target, _ in imports():
        while target and target not in mods:
            target = target.rpartition(".")[0]
        if target and target != importer \
                and not importer.startswith(target + "."):
            graph[importer].add(target)

    def reach(start):
        seen, stack = set(), [start]
        while stack:
            for nxt in graph[stack.pop()]:
                if nxt not in seen:
                    seen.add(nxt)
                    stack.append(nxt)
        return seen

    cycles = sorted(m for m in mods if m in reach(m))
    assert not cycles, f"modules in import cycles: {cycles}"


def test_no_import_of_a_higher_layer():
    wrong = []
    for importer, target, _ in imports():
        (low, a), (high, b) = layer_of(importer), layer_of(target)
        if a != b and high >= low:
            wrong.append(f"{importer} imports {target}")
    assert not wrong, wrong


def test_no_private_name_imported_from_another_module():
    wrong = [f"{importer} imports {name} from {target}"
             for importer, target, name in imports()
             if name and name.startswith("_") and not name.startswith("__")
             and target != importer]
    assert not wrong, wrong


def test_every_package_has_a_layer():
    for module in modules():
        layer_of(module)
