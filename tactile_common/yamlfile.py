"""Reading the project's YAML files (scenes, jaw configs, logs' settings) in one place.

Every failure is an :class:`~tactile_common.errors.InputError` of one line that names the
file, what it was meant to be, and (for a syntax error) the line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from tactile_common.errors import InputError


def read_yaml(path: str | Path, what: str) -> Any:
    """Parse ``path`` as YAML; ``what`` names the file's role in error messages."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read {what} ({exc.strerror or exc})") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}: not valid YAML{where}") from None
