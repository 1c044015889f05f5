"""The import graph keeps its layers: no package imports one from a higher layer, none imports a
sibling on its own layer, so there are no cycles between packages.

Every import under ``src/rcb4hv`` counts: module level, inside functions (lazy), under
``TYPE_CHECKING``, and ``importlib.import_module("rcb4hv....")`` with a literal name. The
drawing of these layers is in docs/architecture.md and the README's "Architecture" section.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parent.parent / "src" / "rcb4hv"
ROOT = SRC.parent.parent

# lowest first; a package may import packages on lower layers only
LAYERS: tuple[tuple[str, ...], ...] = (
    ("errors", "values"),  # the exception tree; values as given and as shown
    ("files", "__init__"),  # reading and atomic saves (typed FileAccessErrors), the root package
    ("protocol",),
    ("transport",),
    ("rom", "robot"),  # robot: models as data, kinematics, URDF/MJCF, the servos' figures
    ("ics",),  # ICS servos: codec, EEPROM, emulated bus (its servos move as robot.servos says)
    ("emulator", "hth4"),
    ("client", "asm", "physics"),  # physics: MuJoCo as a servo backend of the emulator
    ("project",),
    ("aio", "session", "hardware", "gait"),  # gait: walks made through the IK and project
    ("ui",),
    ("cli",),
    ("__main__",),  # python -m rcb4hv
)
RANK = {unit: rank for rank, units in enumerate(LAYERS) for unit in units}


@dataclass(frozen=True)
class Edge:
    source: str  # file relative to src/rcb4hv
    line: int
    importer: str  # the importing unit (a subpackage, or errors / __init__ / __main__)
    target: str  # the imported unit

    def __str__(self) -> str:
        return f"{self.source}:{self.line}: {self.importer} imports {self.target}"


def _unit(parts: tuple[str, ...]) -> str:
    """The layer unit of module ``rcb4hv.<parts>`` (parts without the leading rcb4hv)."""
    return parts[0] if parts else "__init__"


def _module_parts(path: Path) -> tuple[tuple[str, ...], bool]:
    rel = path.relative_to(SRC).with_suffix("")
    is_package = rel.name == "__init__"
    parts = rel.parts[:-1] if is_package else rel.parts
    return parts, is_package


def _is_module(name: str) -> bool:
    return (SRC / name / "__init__.py").exists() or (SRC / f"{name}.py").exists()


def _targets(node: ast.AST, parts: tuple[str, ...], is_package: bool) -> list[str]:
    """Absolute dotted names of the rcb4hv modules ``node`` imports (empty if none)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if isinstance(node, ast.ImportFrom):
        if node.level == 0:
            base = node.module or ""
            if base == "rcb4hv":  # from rcb4hv import errors -> the submodule
                return [f"rcb4hv.{a.name}" if _is_module(a.name) else "rcb4hv" for a in node.names]
            return [base]
        package = ("rcb4hv", *parts) if is_package else ("rcb4hv", *parts[:-1])
        up = package[: len(package) - (node.level - 1)]
        if node.module:
            return [".".join((*up, node.module))]
        return [".".join((*up, alias.name)) for alias in node.names]
    if isinstance(node, ast.Call):
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
        if name == "import_module" and node.args:
            arg = node.args[0]
            if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                return [arg.value]
            return ["<dynamic>"]
    return []


def _edges() -> list[Edge]:
    edges = []
    for path in sorted(SRC.rglob("*.py")):
        parts, is_package = _module_parts(path)
        importer = _unit(parts) if parts else "__init__"
        if path.name == "__main__.py" and len(parts) == 1:
            importer = "__main__"
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            for name in _targets(node, parts, is_package):
                if name == "<dynamic>":
                    target = "<dynamic>"
                elif name == "rcb4hv" or name.startswith("rcb4hv."):
                    target = _unit(tuple(name.split(".")[1:]))
                else:
                    continue
                if target != importer:
                    edges.append(
                        Edge(
                            str(path.relative_to(SRC)), getattr(node, "lineno", 0), importer, target
                        )
                    )
    return edges


EDGES = _edges()


def test_every_package_has_a_layer() -> None:
    units = {p.name for p in SRC.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    units |= {p.stem for p in SRC.glob("*.py")}
    assert units - set(RANK) == set(), "place the new package in LAYERS (and in the drawing)"
    assert set(RANK) - units == set(), "LAYERS names a package that no longer exists"


def test_the_scan_sees_real_imports() -> None:
    """Guard against a scan that finds nothing: known edges of each kind are seen."""
    seen = {(e.importer, e.target) for e in EDGES}
    assert ("client", "transport") in seen  # module level
    assert ("cli", "ui") in seen  # lazy, inside a command
    assert ("rom", "protocol") in seen
    assert len(EDGES) > 100


def test_no_import_goes_up_or_sideways() -> None:
    bad = [str(e) for e in EDGES if e.target != "<dynamic>" and RANK[e.target] >= RANK[e.importer]]
    assert bad == []


def test_dynamic_imports_only_at_the_top() -> None:
    """``import_module(name)`` with a computed name can reach anything: only the CLI may."""
    bad = [str(e) for e in EDGES if e.target == "<dynamic>" and RANK[e.importer] < RANK["cli"]]
    assert bad == []


def test_the_protocol_core_imports_only_itself_and_errors() -> None:
    assert {e.target for e in EDGES if e.importer == "protocol"} <= {"errors"}


@pytest.mark.parametrize("doc", ["README.md", "docs/architecture.md"])
def test_the_drawing_names_every_package(doc: str) -> None:
    text = (ROOT / doc).read_text(encoding="utf-8")
    start = text.index("## Architecture") if "## Architecture" in text else 0
    drawing = text[start:].split("```text", 1)[1].split("```", 1)[0]
    missing = [u for u in RANK if not u.startswith("__") and u not in drawing]
    assert missing == []


# ---------------------------------------------------------------------- module graph


def _module_name(path: Path) -> str:
    parts, _ = _module_parts(path)
    return ".".join(("rcb4hv", *parts))


MODULES = {_module_name(p): p for p in sorted(SRC.rglob("*.py"))}


def _module_target(name: str, node: ast.AST) -> list[str]:
    """The rcb4hv modules one import names: ``from pkg import sub`` names ``pkg.sub``."""
    if isinstance(node, ast.ImportFrom) and name in MODULES:
        subs = [f"{name}.{a.name}" for a in node.names if f"{name}.{a.name}" in MODULES]
        if subs and len(subs) == len(node.names):
            return subs
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return [name] if name else []


def _module_edges() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {name: set() for name in MODULES}
    for name, path in MODULES.items():
        parts, is_package = _module_parts(path)
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            for target in _targets(node, parts, is_package):
                if target == "rcb4hv" or target.startswith("rcb4hv."):
                    graph[name].update(t for t in _module_target(target, node) if t != name)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_two_modules_import_each_other() -> None:
    """No module imports another that imports it back, directly or in a circle, inside a
    package too (module level, lazy and TYPE_CHECKING imports all count; a package's
    ``__init__`` is a module)."""
    graph = _module_edges()
    assert sum(map(len, graph.values())) > 300  # the scan sees the imports
    assert _cycles(graph) == []


def _private_imports() -> list[str]:
    """``from rcb4hv.m import _name`` and ``m._name`` on an imported rcb4hv module, where
    ``_name`` is a function, class or constant (a package's private helper *module*, such as
    ``rcb4hv.cli._util``, may be imported inside its own package)."""
    found = []
    for name, path in MODULES.items():
        parts, is_package = _module_parts(path)
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        aliases: dict[str, str] = {}  # local name -> imported rcb4hv module
        for node in ast.walk(tree):
            if not isinstance(node, ast.ImportFrom):
                continue
            for base in _targets(node, parts, is_package):
                if not base.startswith("rcb4hv"):
                    continue
                for alias in node.names:
                    full = f"{base}.{alias.name}"
                    if full in MODULES:
                        aliases[alias.asname or alias.name] = full
                        if alias.name.startswith("_") and base != name.rpartition(".")[0]:
                            found.append(f"{path.relative_to(SRC)}:{node.lineno}: {full}")
                    elif alias.name.startswith("_") and not alias.name.startswith("__"):
                        found.append(f"{path.relative_to(SRC)}:{node.lineno}: {full}")
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in aliases
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
            ):
                found.append(f"{path.relative_to(SRC)}:{node.lineno}: {aliases[node.value.id]}")
    return sorted(set(found))


def test_private_names_stay_in_their_module() -> None:
    assert _private_imports() == []
