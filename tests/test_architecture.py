"""The house as docs/design.md draws it: one package, `soccer_lab`, whose parts import in one direction, with no
import circle anywhere and no kernel taking more than a dozen positional parameters."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PARTS = ("fuzzy", "ga", "soccer", "app")  # soccer_lab.<part>, from the folder of the same name
OWN_CODE = (*PARTS, "soccer_lab", "tests", "benchmarks", "scripts", "docs/hooks")
ALLOWED = {  # what each part may import of the project (SPEC 1: fuzzy nothing; ga fuzzy; soccer fuzzy; app all)
    "fuzzy": set(),
    "ga": {"fuzzy"},
    "soccer": {"fuzzy"},
    "app": {"fuzzy", "ga", "soccer"},
}
MAX_LOOSE_APP_MODULES = 6  # store, paths, words, rule inspection, rulebase files, pitch markings
MAX_POSITIONAL_PARAMETERS = 12


def python_files(folder: str) -> list[Path]:
    return [path for path in (ROOT / folder).rglob("*.py") if "__pycache__" not in path.parts]


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(["soccer_lab", *parts]) if parts[0] in PARTS else ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(path): path for part in (*PARTS, "soccer_lab") for path in python_files(part)}


def imported(path: Path, known: dict[str, Path]) -> set[str]:
    """The project modules `path` imports (at any depth of the file: a function's import is an edge too)."""
    package = module_name(path) if path.name == "__init__.py" else module_name(path).rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else []))
            names = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base for alias in node.names]
        else:
            continue
        for name in names:
            while name and name not in known:
                name = name.rpartition(".")[0]
            if name:
                found.add(name)
    found.discard(module_name(path))
    return found


def test_project_code_imports_the_project_only_as_soccer_lab():
    """A bare `import fuzzy` would find the package index's `fuzzy` once installed (and this checkout's folder
    only by accident of the working directory)."""
    offenders = []
    for folder in OWN_CODE:
        for path in python_files(folder):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                names = ([alias.name for alias in node.names] if isinstance(node, ast.Import)
                         else [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
                offenders += [f"{path.relative_to(ROOT)}:{node.lineno} {name}" for name in names
                              if name.split(".")[0] in PARTS]
    assert not offenders, "\n".join(offenders)


@pytest.mark.parametrize("part", list(ALLOWED))
def test_each_part_imports_only_what_the_design_allows(part):
    known = modules()
    wrong = []
    for path in python_files(part):
        for target in imported(path, known):
            other = target.split(".")[1] if target.startswith("soccer_lab.") and target.count(".") else None
            if other is not None and other != part and other not in ALLOWED[part]:
                wrong.append(f"{path.relative_to(ROOT)} imports {target}")
    assert not wrong, "\n".join(wrong)


def test_no_import_circle_anywhere():
    known = modules()
    graph = {name: imported(path, known) for name, path in known.items()}
    # the parents a package implies are not edges: importing soccer_lab.app.runs.run imports soccer_lab.app.runs
    circles, state = [], {}

    def visit(name: str, trail: list[str]) -> None:
        state[name] = "open"
        for target in sorted(graph[name]):
            if state.get(target) == "open":
                circles.append(" -> ".join(trail[trail.index(target):] + [target]))
            elif target not in state:
                visit(target, trail + [target])
        state[name] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    assert not circles, "\n".join(circles)


def test_app_names_its_parts_with_few_loose_modules():
    loose = sorted(path.name for path in (ROOT / "app").glob("*.py") if path.name != "__init__.py")
    assert len(loose) <= MAX_LOOSE_APP_MODULES, loose
    folders = {path.name for path in (ROOT / "app").iterdir() if (path / "__init__.py").is_file()}
    assert {"cli", "web", "runs", "lineage", "experiment"} <= folders


def compiled_by_call(tree: ast.AST) -> set[str]:
    """The functions a module compiles by calling numba on them, `numba.njit(cache=True)(alpha_cut)`."""
    return {node.args[0].id for node in ast.walk(tree)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Call) and "jit" in ast.unparse(node.func.func)
            and node.args and isinstance(node.args[0], ast.Name)}


def test_no_kernel_takes_more_than_a_dozen_positional_parameters():
    """numba kernels take plain arrays; more than a dozen means arrays want grouping by what they describe. A
    kernel is a function decorated with numba's jit, or one a module hands to it (fuzzy/batched.py does)."""
    trees = {path: ast.parse(path.read_text(encoding="utf-8")) for part in PARTS for path in python_files(part)}
    by_call = set().union(*(compiled_by_call(tree) for tree in trees.values()))
    assert {"trapezoid_membership", "alpha_cut"} <= by_call  # else the search below misses such kernels
    crowded = []
    for path, tree in trees.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and (node.name in by_call or any(
                    "jit" in ast.unparse(decorator) for decorator in node.decorator_list)):
                count = len(node.args.posonlyargs) + len(node.args.args)
                if count > MAX_POSITIONAL_PARAMETERS:
                    crowded.append(f"{path.relative_to(ROOT)}:{node.lineno} {node.name} ({count})")
    assert not crowded, "\n".join(crowded)
