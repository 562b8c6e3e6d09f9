"""Layers you can see: no upward, sideways or circular imports, no private imports across.

Every module under ``src/tactilecal`` is parsed with :mod:`ast`; every import counts, also
those inside functions (the package imports heavy parts where they are used). The layers,
lowest first, are :data:`LAYERS` (the same list is in ``docs/developer-guide.md``):

- the core: the top-level private modules ``tactilecal._*`` (and the lazy
  ``tactilecal/__init__.py``); anyone may import them, they import no subpackage;
- a subpackage may import the core and the public names of lower layers, nothing of its own
  layer's other subpackages or above;
- ``tactilecal.<a>`` may not import a private module or name of ``tactilecal.<b>``
  (``tactilecal.<b>._x``, ``from tactilecal.<b> import _x``);
- ``importlib.import_module("tactilecal....")`` with a literal name is an import hidden from
  readers and tools: only the lazy top-level ``__init__`` may do it.

The test also checks itself on a small synthetic package in ``tmp_path``, so it cannot pass
because it found nothing.
"""

import ast
import re
from functools import cache
from pathlib import Path

import pytest

import tactilecal

ROOT = Path(tactilecal.__file__).parent

CORE = "<core>"
LAYERS = (
    (CORE,),
    ("sensors", "geotech"),
    ("io",),
    ("simulate", "dynamic"),
    ("calibration",),
    ("analysis",),
    ("report",),
    ("demo",),
    ("cli",),
)
"""Subpackages by layer, lowest first; those sharing a layer may not import each other."""

KNOWN_UNTIL_MERGE = frozenset()
"""(importing module, imported module) pairs tolerated, each with its reason and its end."""

MODULE_PATH = re.compile(r"[A-Za-z_]\w*(\.[A-Za-z_]\w*)+")


def module_name(path, root):
    """Dotted module name of ``path`` in the package rooted at folder ``root``."""
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _resolve(node, module, is_package):
    """Absolute module named by an ``ImportFrom`` (relative imports resolved)."""
    if not node.level:
        return node.module
    base = module.split(".")
    base = base[:len(base) - node.level + (1 if is_package else 0)]
    return ".".join(base + ([node.module] if node.module else []))


def imports_of(path, root):
    """Yield ``(line, imported module, how)`` for every import in the file ``path``.

    ``from a.b import c`` yields ``a.b.c`` (a module or a name: either way the edge is to
    ``a.b``'s subpackage, and a private ``_c`` shows). A call given a dotted name of the
    package as a literal (``import_module("pkg.x")``, or a helper that imports what it is
    given) yields that name with ``how="import_module"``.

    Each file is parsed once per test process (and its text read again to see that it is
    unchanged): the package's ~200 modules are read by four tests.
    """
    text = path.read_text(encoding="utf-8")
    yield from _parsed_imports(path, root, text)


@cache
def _parsed_imports(path, root, text):
    return tuple(_imports_in(path, root, text))


def _imports_in(path, root, text):
    module = module_name(path, root)
    tree = ast.parse(text, filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name, "import"
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(node, module, path.name == "__init__.py")
            for alias in node.names:
                yield node.lineno, f"{target}.{alias.name}", "import"
        elif isinstance(node, ast.Call):
            # import_module("pkg.x"), or "pkg.x" handed to a helper that imports it
            for arg in node.args:
                if isinstance(arg, ast.Constant) and isinstance(arg.value, str) \
                        and MODULE_PATH.fullmatch(arg.value) \
                        and arg.value.split(".")[0] == root.name:
                    yield node.lineno, arg.value, "import_module"


def subpackage(module, package):
    """The subpackage of ``module`` (``CORE`` for the core), or None outside ``package``."""
    parts = module.split(".")
    if parts[0] != package:
        return None
    if len(parts) == 1 or parts[1].startswith("_"):
        return "cli" if parts[1:2] == ["__main__"] else CORE
    return parts[1]


def _is_private_of(target):
    """True if ``target`` is a private module or name inside a subpackage."""
    parts = target.split(".")
    return len(parts) > 2 and not parts[1].startswith("_") \
        and any(p.startswith("_") for p in parts[2:])


def find_violations(root, layers=LAYERS, allowed=frozenset()):
    """Return ``(messages, edges)``: each breach as "module:line: what", subpackage edges."""
    package = root.name
    rank = {pkg: i for i, layer in enumerate(layers) for pkg in layer}
    found, edges = [], {}
    for path in sorted(root.rglob("*.py")):
        if path == root / "__init__.py":
            continue  # the lazy top-level facade: it may name anything, lazily
        module = module_name(path, root)
        source = subpackage(module, package)
        for line, target, how in imports_of(path, root):
            dest = subpackage(target, package)
            if dest is None or (module, target) in allowed or any(
                    module == a and target.startswith(b + ".") for a, b in allowed):
                continue
            where = f"{module}:{line}"
            found.extend(_breaches(where, source, dest, target, how, rank))
            if dest != source:
                edges.setdefault(source, {}).setdefault(dest, where)
    return found, edges


def _breaches(where, source, dest, target, how, rank):
    if how == "import_module":
        yield f"{where}: {target!r} imported by name hides an import; import it normally"
    if source not in rank:
        yield f"{where}: subpackage {source!r} is in no layer; add it to LAYERS"
        return
    if dest not in rank:
        yield f"{where}: imports {target} of subpackage {dest!r}, which is in no layer"
        return
    if dest == source:
        return
    if dest == "cli":
        yield f"{where}: imports {target}: only the CLI imports the CLI"
    elif rank[dest] > rank[source]:
        yield f"{where}: imports {target}, up the layers ({source} is below {dest})"
    elif rank[dest] == rank[source] and dest != CORE:
        yield f"{where}: imports {target} sideways ({source} and {dest} share a layer)"
    if dest != CORE and _is_private_of(target):
        yield f"{where}: imports private {target} of subpackage {dest}; use a public name"


def _components(edges):
    """Strongly connected components of ``{a: {b: ...}}`` (Tarjan 1972): ``{node: index}``."""
    index, low, on_stack, stack, component = {}, {}, set(), [], {}

    def connect(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in edges.get(node, {}):
            if nxt not in index:
                connect(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component[member] = node
                if member == node:
                    break

    for node in sorted(set(edges) | {n for targets in edges.values() for n in targets}):
        if node not in index:
            connect(node)
    return component


def find_cycles(edges):
    """Cycles of the graph ``{a: {b: where}}``, each as "a -> b -> a (where...)".

    Every simple cycle lies inside one strongly connected component, so paths are followed
    only inside components of two or more nodes (an acyclic graph has none, and its many
    paths are never walked).
    """
    component = _components(edges)
    cycles, seen = [], set()

    def visit(node, trail):
        for nxt, where in edges.get(node, {}).items():
            if component.get(nxt) != component[node]:
                continue
            hops = [*trail, (node, where)]
            if nxt == hops[0][0]:
                key = frozenset(n for n, _ in hops)
                if key not in seen:
                    seen.add(key)
                    names = " -> ".join([n for n, _ in hops] + [nxt])
                    cycles.append(f"{names} ({', '.join(w for _, w in hops)})")
            elif nxt not in {n for n, _ in hops}:
                visit(nxt, hops)

    for start in sorted(edges):
        visit(start, [])
    return cycles


def test_every_subpackage_has_a_layer():
    packages = {p.name for p in ROOT.iterdir()
                if (p / "__init__.py").is_file() and not p.name.startswith("_")}
    placed = {pkg for layer in LAYERS for pkg in layer} - {CORE}
    assert packages == placed


def test_the_developer_guide_names_every_core_module():
    """Its layer table's core row names exactly the modules ``tactilecal/_*.py``."""
    guide = (ROOT.parents[1] / "docs" / "developer-guide.md").read_text()
    row = next(line for line in guide.splitlines() if line.startswith("| 0 core |"))
    named = set(re.findall(r"`(_[a-z]\w*)`", row))
    assert named == {p.stem for p in ROOT.glob("_*.py")} - {"__init__", "__main__"}


def test_no_upward_sideways_private_or_hidden_imports():
    found, _ = find_violations(ROOT, allowed=KNOWN_UNTIL_MERGE)
    assert not found, "\n".join(found)


def test_no_cycles_between_subpackages():
    _, edges = find_violations(ROOT, allowed=KNOWN_UNTIL_MERGE)
    cycles = find_cycles(edges)
    assert not cycles, "\n".join(cycles)


def module_edges(root):
    """The module import graph ``{module: {imported module: "file:line"}}`` of a package.

    Every import counts, those inside functions too; ``from a.b import c`` is an edge to
    the module ``a.b.c`` when it exists, else to ``a.b``.
    """
    modules = {module_name(p, root): p for p in root.rglob("*.py")}
    edges = {}
    for name, path in modules.items():
        for line, target, _ in imports_of(path, root):
            while target and target not in modules:
                target = target.rpartition(".")[0]
            if target and target != name:
                edges.setdefault(name, {}).setdefault(target, f"{path.name}:{line}")
    return edges


def test_no_cycles_between_modules():
    """Not even between two modules of one package (imports inside functions included)."""
    cycles = find_cycles(module_edges(ROOT))
    assert not cycles, "\n".join(cycles)


def test_benchmarks_do_not_import_the_cli():
    # benchmarks measure the library; the fuzzer runs the CLI as a user does (a process)
    folder = ROOT.parents[1] / "benchmarks"
    if not folder.is_dir():
        pytest.skip("no benchmarks folder next to src (installed package)")
    found = [f"benchmarks/{p.name}:{line}: imports {target}"
             for p in sorted(folder.glob("*.py")) for line, target, _ in imports_of(p, folder)
             if target == "tactilecal.cli" or target.startswith("tactilecal.cli.")]
    assert not found, "\n".join(found)


def test_known_offenders_are_still_there():
    # each allowlisted pair must still occur, so the list shrinks as the branches merge
    seen = {(module_name(p, ROOT), t) for p in ROOT.rglob("*.py") for _, t, _ in
            imports_of(p, ROOT)}
    stale = [pair for pair in KNOWN_UNTIL_MERGE
             if not any(pair[0] == m and (t == pair[1] or t.startswith(pair[1] + "."))
                        for m, t in seen)]
    assert not stale, f"no longer imported, remove from KNOWN_UNTIL_MERGE: {stale}"


# --- the test catches offenders: a synthetic package in tmp_path ---------------------------

FAKE = {
    "__init__.py": "from importlib import import_module\nimport_module('pkg.low')\n",
    "_core.py": "import json\n",
    "low/__init__.py": "from pkg.low._impl import f\n",
    "low/_impl.py": "from pkg._core import json\n\ndef f():\n    from pkg.high import g\n",
    "mid/__init__.py": "from pkg.low import f\nfrom pkg.low import _impl\n",
    "mid/_x.py": "import pkg.low._impl as impl\nfrom pkg.side import h\n",
    "side/__init__.py": "from ..mid import _x\n",
    "high/__init__.py": ("import importlib\nfrom pkg.low import f\n"
                         "def g():\n    importlib.import_module('pkg.mid')\n"
                         "    plots('pkg.low._impl', 'pkg is a package')\n"),
    "cli/__init__.py": "from pkg.high import g\n",
    "orphan/__init__.py": "from pkg.cli import main\n",
}
FAKE_LAYERS = ((CORE,), ("low",), ("mid", "side"), ("high",), ("cli",))


@pytest.fixture
def fake(tmp_path):
    root = tmp_path / "pkg"
    for name, text in FAKE.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


def test_the_test_catches_each_kind_of_offender(fake):
    found, edges = find_violations(fake, FAKE_LAYERS)
    text = "\n".join(found)
    expected = [
        "pkg.low._impl:4: imports pkg.high.g, up the layers (low is below high)",
        "pkg.mid:2: imports private pkg.low._impl of subpackage low; use a public name",
        "pkg.mid._x:1: imports private pkg.low._impl of subpackage low",
        "pkg.mid._x:2: imports pkg.side.h sideways (mid and side share a layer)",
        "pkg.side:1: imports pkg.mid._x sideways",
        "pkg.side:1: imports private pkg.mid._x of subpackage mid",
        "pkg.high:4: 'pkg.mid' imported by name hides an import",
        "pkg.high:5: 'pkg.low._impl' imported by name hides an import",
        "pkg.high:5: imports private pkg.low._impl of subpackage low",
        "pkg.orphan:1: subpackage 'orphan' is in no layer",
    ]
    for message in expected:
        assert message in text, f"missing {message!r} in:\n{text}"
    # the lazy top-level __init__ may use import_module; importing the core is fine
    assert "pkg:2" not in text and "pkg._core" not in text
    assert "pkg.cli:1" not in text and "pkg.mid:1:" not in text
    assert len(found) == len(expected)
    cycles = find_cycles(edges)
    assert any(c.startswith("high -> mid -> low -> high") or "low -> high -> mid -> low" in c
               or "mid -> low -> high -> mid" in c for c in cycles), cycles
    assert any("mid -> side -> mid" in c or "side -> mid -> side" in c for c in cycles), cycles


def test_the_module_cycle_check_sees_a_circle_inside_one_package(fake):
    (fake / "low" / "_a.py").write_text("def f():\n    from pkg.low._b import g\n")
    (fake / "low" / "_b.py").write_text("from pkg.low import _a\n")
    cycles = find_cycles(module_edges(fake))
    assert any("pkg.low._a -> pkg.low._b -> pkg.low._a" in c
               or "pkg.low._b -> pkg.low._a -> pkg.low._b" in c for c in cycles), cycles


def test_cli_imported_from_below_is_named(fake):
    (fake / "low" / "_impl.py").write_text("from pkg.cli import main\n")
    found, _ = find_violations(fake, FAKE_LAYERS)
    assert "pkg.low._impl:1: imports pkg.cli.main: only the CLI imports the CLI" in found


def test_allowlist_silences_exactly_its_pairs(fake):
    allowed = {("pkg.low._impl", "pkg.high")}
    found, edges = find_violations(fake, FAKE_LAYERS, allowed=allowed)
    assert not any(m.startswith("pkg.low._impl:4") for m in found)
    assert "high" not in edges.get("low", {})
    assert any(m.startswith("pkg.mid._x:1") for m in found)
