"""No function of the exploration rebinds the name of a function nested in it: a later call of
the nested function would call the value (X finite 643, moved semicubical 121: ``ends``, the pad
normals where the finger's pad ends met the object, rebound to a bool once a roll aimed beyond a
parabola's vertex fell off, and the next planned roll raised "'bool' object is not callable",
a fault that ended the run)."""

import ast
from pathlib import Path

import pytest

PACKAGES = ("tactile_jaw", "recognizer", "hand_driver", "tools")
ROOT = Path(__file__).resolve().parents[2]


def _rebound_nested(tree: ast.AST) -> list[str]:
    found = []
    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        nested = {n.name for n in fn.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}
        if not nested:
            continue
        for node in ast.walk(fn):
            targets = []
            if isinstance(node, ast.Assign):
                targets = node.targets
            elif isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.NamedExpr)):
                targets = [node.target]
            elif isinstance(node, (ast.For, ast.AsyncFor)):
                targets = [node.target]
            for t in targets:
                for name in ast.walk(t):
                    if isinstance(name, ast.Name) and name.id in nested and isinstance(name.ctx, ast.Store):
                        found.append(f"{fn.name}: {name.id} (line {name.lineno})")
    return found


def test_the_check_finds_a_rebound_nested_function():
    src = "def run():\n    def ends(n):\n        return n\n    if True:\n        ends = False\n    return ends(1)\n"
    assert _rebound_nested(ast.parse(src)) == ["run: ends (line 5)"]


@pytest.mark.parametrize("package", PACKAGES)
def test_no_nested_function_name_is_rebound(package):
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        bad += [f"{path.relative_to(ROOT)}: {b}" for b in _rebound_nested(ast.parse(path.read_text()))]
    assert bad == []
