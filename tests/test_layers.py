"""The import rule (docs/ARCHITECTURE.md): every import of every module, module-level or
inside a function, parsed with ``ast``. ``tactile_common`` imports no project package;
``recognizer`` and ``hand_driver`` import nothing of each other (except
``hand_driver/sim/boundary.py``, the emulator's boundary of a scene's object, which takes
curves from ``recognizer.curves`` only) nor of the layers
above them; ``tactile_jaw`` imports nothing of ``tools``."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PROJECT = ("tactile_common", "recognizer", "hand_driver", "tactile_jaw", "tools")
#: package → project packages it must not import
FORBIDDEN = {
    "tactile_common": {"recognizer", "hand_driver", "tactile_jaw", "tools"},
    "recognizer": {"hand_driver", "tactile_jaw", "tools"},
    "hand_driver": {"recognizer", "tactile_jaw", "tools"},
    "tactile_jaw": {"tools"},
}
#: the one narrow interface across the two middle packages: the emulator's boundary of a
#: scene's object takes curves from the recognizer
SIM_INTERFACE = ("hand_driver", "sim", "boundary.py")
SIM_MAY_IMPORT = ("recognizer.curves",)


def imported_modules(source: str, package: str) -> list[tuple[int, str]]:
    """(line, absolute module name) of every import in ``source``; a relative import is
    resolved against ``package`` (the dotted package of the file)."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.append((node.lineno, name))
            out += [(node.lineno, f"{name}.{alias.name}") for alias in node.names if name in PROJECT]
    return out


def violations(path: Path, root: Path = ROOT) -> list[str]:
    rel = path.relative_to(root)
    top = rel.parts[0]
    package = ".".join(rel.with_suffix("").parts[:-1])
    in_sim = rel.parts == SIM_INTERFACE
    bad = []
    for line, name in imported_modules(path.read_text(encoding="utf-8"), package):
        root = name.split(".")[0]
        if root not in FORBIDDEN.get(top, ()):
            continue
        if in_sim and any(name == m or name.startswith(m + ".") for m in SIM_MAY_IMPORT):
            continue
        if in_sim and name == "recognizer":
            continue  # the "from recognizer import ..." line itself; its names are checked one by one
        bad.append(f"{rel}:{line}: {top} imports {name}")
    return bad


def project_files() -> list[Path]:
    return sorted(p for pkg in FORBIDDEN for p in (ROOT / pkg).rglob("*.py"))


def test_the_packages_exist():
    assert {p.relative_to(ROOT).parts[0] for p in project_files()} == set(FORBIDDEN)


@pytest.mark.parametrize("path", project_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_imports_point_down(path):
    assert violations(path) == []


@pytest.mark.parametrize("source, where, expected", [
    ("import hand_driver.bus\n", "recognizer/x.py", ["recognizer imports hand_driver.bus"]),
    ("def f():\n    from tools import cli\n", "tactile_jaw/x.py",
     ["tactile_jaw imports tools", "tactile_jaw imports tools.cli"]),
    ("from recognizer.classify import recognize\n", "hand_driver/x.py", ["hand_driver imports recognizer.classify"]),
    ("from recognizer.classify import recognize\n", "hand_driver/sim/boundary.py",
     ["hand_driver imports recognizer.classify"]),
    ("from recognizer import touches\n", "hand_driver/sim/boundary.py", ["hand_driver imports recognizer.touches"]),
    ("from recognizer.curves import CURVES\n", "hand_driver/sim/boundary.py", []),
    ("from recognizer import curves\n", "hand_driver/sim/boundary.py", []),
    ("from recognizer.curves import CURVES\n", "hand_driver/sim/physics.py", ["hand_driver imports recognizer.curves"]),
    ("import yaml\nfrom hand_driver import kinematics\n", "tactile_common/x.py",
     ["tactile_common imports hand_driver", "tactile_common imports hand_driver.kinematics"]),
    ("from .. import classify\n", "hand_driver/sim/x.py", []),  # hand_driver.classify: not another package
    ("from recognizer.scene import load_scene\nfrom hand_driver.cycle import Jaw\n", "tactile_jaw/x.py", []),
])
def test_the_rule_catches_forbidden_imports(tmp_path, source, where, expected):
    """The check itself can fail: hand-written modules, module-level and function-local."""
    path = tmp_path / where
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(source)
    assert [v.split(": ", 1)[1] for v in violations(path, tmp_path)] == expected
