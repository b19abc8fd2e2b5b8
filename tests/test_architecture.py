"""The package's layering rule (docs/ARCHITECTURE.md): each subpackage imports only from the
layers below it, modules never import each other in a cycle, `zedo_cli` itself stays light, and inside
`analysis` the measure families keep their own order, few modules a folder and short modules."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "zedo_cli"

# Lowest first. A module may import from its own group and from any group of a lower layer.
LAYERS: list[set[str]] = [
    {"errors", "version", "lazy", "strict_json", "collection"},
    {"files", "rotation", "versioned_json", "stats"},
    {"data", "camera"},
    {"prior"},
    {"lifting"},
    {"formats"},
    {"analysis", "footage"},
    {"augment", "evaluation", "settings"},
    {"pipeline"},
    {"cli"},
    {"__main__"},
]
LAYER_OF = {group: level for level, groups in enumerate(LAYERS) for group in groups}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _nodes(tree: ast.AST, runtime_only: bool) -> list[ast.AST]:
    """Every node of `tree`; with `runtime_only`, not those under `if TYPE_CHECKING:`."""
    found, stack = [], [tree]
    while stack:
        node = stack.pop()
        found.append(node)
        if runtime_only and isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            stack.extend(node.orelse)
            continue
        stack.extend(ast.iter_child_nodes(node))
    return found


def imported_modules(path: Path, runtime_only: bool = False) -> set[str]:
    """Every zedo_cli module `path` imports, at the top or inside a function (with
    `runtime_only`, without the imports made for type annotations only)."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found: set[str] = set()
    for node in _nodes(ast.parse(path.read_text()), runtime_only):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] == "zedo_cli":
                # `from .pkg import module` imports the module itself
                for alias in node.names:
                    sub = f"{target}.{alias.name}"
                    found.add(sub if _is_module(sub) else target)
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.split(".")[0] == "zedo_cli"}
    return found


def _is_module(dotted: str) -> bool:
    rel = Path(*dotted.split(".")[1:])
    return (PACKAGE / rel).with_suffix(".py").is_file() or (PACKAGE / rel / "__init__.py").is_file()


def group_of(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None  # None: the top package (its lazy public API)


def import_graph(runtime_only: bool = False) -> dict[str, set[str]]:
    return {module_name(p): imported_modules(p, runtime_only) for p in sorted(PACKAGE.rglob("*.py"))}


def test_every_group_is_assigned_a_layer():
    groups = {group_of(m) for m in import_graph()} - {None}
    assert groups == set(LAYER_OF), "a new subpackage or top-level module needs a layer here and in ARCHITECTURE.md"


def test_imports_go_down_the_layers_only():
    upward = []
    for module, targets in import_graph().items():
        source = group_of(module)
        if source is None:
            continue
        for target in targets:
            dest = group_of(target)
            if dest is None:
                upward.append(f"{module} -> {target} (the top package is for users, not for zedo_cli itself)")
            elif dest != source and LAYER_OF[dest] >= LAYER_OF[source]:
                upward.append(f"{module} -> {target}")
    assert not upward, "imports against the layering rule:\n" + "\n".join(sorted(upward))


# Inside formats/ readers live apart from writers (docs/ARCHITECTURE.md): only the orchestration
# that reads a stored result and writes it again, and the package's exports, may use both.
BOTH_READERS_AND_WRITERS = {"zedo_cli.formats", "zedo_cli.formats.export"}


def test_no_formats_module_both_reads_and_writes():
    def side(module: str) -> str | None:
        parts = module.split(".")
        return parts[2] if len(parts) > 2 and parts[1] == "formats" and parts[2] in ("readers", "writers") else None

    graph = import_graph()
    assert any(side(m) == "readers" for m in graph) and any(side(m) == "writers" for m in graph)
    mixed = []
    for module, targets in graph.items():
        if group_of(module) != "formats" or module in BOTH_READERS_AND_WRITERS:
            continue
        sides = {side(t) for t in targets} - {None}
        own = side(module)
        if len(sides | ({own} if own else set())) > 1:
            mixed.append(f"{module} -> {sorted(t for t in targets if side(t))}")
    assert not mixed, "formats modules that hold both reading and writing:\n" + "\n".join(sorted(mixed))


# Inside analysis/ (docs/ARCHITECTURE.md): folders by measure family, lowest first, then the modules at its
# top (the orchestration: analyse, outputs, compare), then the report, which renders an Analysis. A module
# imports only from its own part and from lower ones.
ANALYSIS = PACKAGE / "analysis"
ANALYSIS_ORDER = ["uncertainty", "pose", "clip", "norms", "", "report"]  # "": the modules at analysis/'s top
MAX_MODULES_PER_FOLDER = 8  # under analysis/, __init__.py not counted
MAX_MODULE_LINES = 600  # under analysis/


def analysis_part(module: str) -> str | None:
    """The part of analysis/ that `module` belongs to: its folder, "" for a module at analysis/'s top (and for
    the package itself), None outside analysis/."""
    parts = module.split(".")
    if parts[:2] != ["zedo_cli", "analysis"]:
        return None
    return parts[2] if len(parts) > 2 and (ANALYSIS / parts[2]).is_dir() else ""


def test_every_analysis_folder_has_a_place_in_its_order():
    folders = {p.name for p in ANALYSIS.iterdir() if (p / "__init__.py").is_file()}
    assert folders == set(ANALYSIS_ORDER) - {""}, "a new folder of analysis/ needs a place here and in ARCHITECTURE.md"
    assert analysis_part("zedo_cli.analysis.report.report") == "report"
    assert analysis_part("zedo_cli.analysis.analyse") == analysis_part("zedo_cli.analysis") == ""
    assert analysis_part("zedo_cli.formats.readers.result") is None


def test_analysis_imports_go_down_its_order():
    graph = import_graph()
    assert {analysis_part(m) for m in graph} - {None} == set(ANALYSIS_ORDER)
    upward = []
    for module, targets in graph.items():
        source = analysis_part(module)
        if source is None:
            continue
        for target in targets:
            dest = analysis_part(target)
            if dest is not None and ANALYSIS_ORDER.index(dest) > ANALYSIS_ORDER.index(source):
                upward.append(f"{module} -> {target}")
    order = " < ".join(part or "(top)" for part in ANALYSIS_ORDER)
    assert not upward, f"analysis/ imports against its order {order}:\n" + "\n".join(sorted(upward))


def test_analysis_folders_hold_few_modules():
    crowded = {
        str(folder.relative_to(PACKAGE)): n
        for folder in [ANALYSIS, *(p.parent for p in ANALYSIS.rglob("__init__.py"))]
        if (n := len([m for m in folder.glob("*.py") if m.name != "__init__.py"])) > MAX_MODULES_PER_FOLDER
    }
    assert not crowded, f"more than {MAX_MODULES_PER_FOLDER} modules in a folder of analysis/: {crowded}"


def test_analysis_modules_are_short():
    long = {
        str(path.relative_to(PACKAGE)): n
        for path in sorted(ANALYSIS.rglob("*.py"))
        if (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES
    }
    assert not long, f"modules of analysis/ over {MAX_MODULE_LINES} lines: {long}"


def test_no_import_cycles():
    graph = import_graph(runtime_only=True)  # an annotation-only import cannot close a cycle
    # a package's __init__ importing its own modules is how it exports them, not a cycle
    edges = {m: {t for t in ts if t in graph and not m.startswith(t + ".")} for m, ts in graph.items()}
    state: dict[str, int] = {}
    cycles: list[str] = []

    def visit(node: str, stack: list[str]) -> None:
        state[node] = 1
        for nxt in edges[node]:
            if state.get(nxt) == 1:
                cycles.append(
                    " -> ".join(stack[stack.index(nxt) :] + [node, nxt]) if nxt in stack else f"{node} -> {nxt}"
                )
            elif nxt not in state:
                visit(nxt, stack + [node])
        state[node] = 2

    for node in edges:
        if node not in state:
            visit(node, [])
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def test_the_top_package_stays_light_and_exports_the_api():
    code = (
        "import sys, zedo_cli\n"
        "heavy = sorted(m for m in ('torch', 'matplotlib', 'scipy', 'typer') if m in sys.modules)\n"
        "assert not heavy, heavy\n"
        "from zedo_cli import analyze, lift, lift_file, load_prior, read_keypoints, write_result\n"
        "assert callable(lift_file) and callable(analyze)\n"
        "assert callable(lift) and callable(load_prior) and callable(read_keypoints) and callable(write_result)\n"
        "assert set(zedo_cli.__all__) <= set(dir(zedo_cli))\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_unknown_api_name_is_an_attribute_error():
    import zedo_cli

    with pytest.raises(AttributeError, match="no_such_name"):
        zedo_cli.no_such_name  # noqa: B018


# The repository's other code (benchmarks/README.md, experiments/README.md): benchmarks/ holds only folders of
# scripts and their shared lib/, experiments/ the rejected remedies, which the default suite never imports.
ROOT = PACKAGE.parent


def test_benchmarks_holds_folders_not_scripts():
    loose = sorted(p.name for p in (ROOT / "benchmarks").iterdir() if p.is_file() and p.name != "README.md")
    assert loose == [], "a benchmark script belongs in one of benchmarks/'s folders (benchmarks/README.md)"
    assert (ROOT / "benchmarks" / "lib" / "__init__.py").is_file()


def _reaches_experiments(node: ast.AST) -> bool:
    """An import of experiments, or a call that puts it on the path or imports it by name."""
    if isinstance(node, ast.Import):
        return any(a.name.split(".")[0] == "experiments" for a in node.names)
    if isinstance(node, ast.ImportFrom):
        return (node.module or "").split(".")[0] == "experiments"
    if isinstance(node, ast.Call):
        func = node.func
        name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
        if name in ("insert", "append", "extend", "import_module", "__import__", "benchmark_module"):
            return any(isinstance(n, ast.Constant) and "experiments" in str(n.value) for n in ast.walk(node))
    return False


def test_experiments_stand_apart_from_the_default_suite():
    assert (ROOT / "experiments" / "README.md").is_file()
    assert sorted((ROOT / "experiments").glob("*.py")), "experiments/ holds the rejected remedies' scripts"
    reaching = [
        f"{path.relative_to(ROOT)}:{node.lineno}"
        for path in sorted((ROOT / "tests").rglob("*.py"))
        for node in ast.walk(ast.parse(path.read_text()))
        if _reaches_experiments(node)
    ]
    assert reaching == [], "tests/ must not import experiments/ or put it on the path: " + ", ".join(reaching)


def test_the_experiments_check_sees_an_import_and_a_path_insert():
    code = (
        "import sys\nsys.path.insert(0, str(ROOT / 'experiments'))\nfrom experiments.x import y\nimport experiments\n"
    )
    assert sum(_reaches_experiments(n) for n in ast.walk(ast.parse(code))) == 3


MAX_FUNCTION_LINES = 80  # def to its last line, outside zedo_cli/cli/
# Known longer functions, to be split: each entry must still be too long (else remove it)
LONG_FUNCTIONS: set[str] = set()


def _function_lengths() -> dict[str, int]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        if rel.parts[0] == "cli":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                out[f"{rel.as_posix()}::{node.name}"] = node.end_lineno - node.lineno + 1
    return out


def test_no_module_of_the_package_is_over_600_lines() -> None:
    long = {str(p.relative_to(PACKAGE)): n for p in sorted(PACKAGE.rglob("*.py"))
            if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}  # fmt: skip
    assert not long, long


def test_no_function_outside_the_cli_is_over_80_lines() -> None:
    lengths = _function_lengths()
    long = {name for name, n in lengths.items() if n > MAX_FUNCTION_LINES}
    assert long <= LONG_FUNCTIONS, sorted(long - LONG_FUNCTIONS)
    assert LONG_FUNCTIONS <= long, f"shorter now, drop from LONG_FUNCTIONS: {sorted(LONG_FUNCTIONS - long)}"
