"""The docs stay true to the tree: every module is listed in docs/ARCHITECTURE.md, every
relative link of the README and docs/ resolves, nothing points outside the repository,
and the README's set-up block (read by .ci/run) holds exactly two commands."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("tactile_common", "recognizer", "hand_driver", "tactile_jaw", "tools")
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _architecture_listing() -> set[str]:
    """Module paths named in ARCHITECTURE's module list, per package section."""
    listed, package = set(), None
    for line in (ROOT / "docs" / "ARCHITECTURE.md").read_text().splitlines():
        head = re.match(r"^`(" + "|".join(PACKAGES) + r")/`", line)
        if head:
            package = head.group(1)
            continue
        if line.startswith("#") or re.match(r"^`[a-z_]+/`", line):
            package = None
        if package:
            listed.update(f"{package}/{name}" for name in re.findall(r"`((?:[a-z_]+/)?[a-z_]+\.py)`", line))
            listed.update(f"tools/cmd_{name}.py" for name in re.findall(r"`([a-z]+)`", line)
                          if "cmd_<name>.py" in line or package == "tools")
    return listed


def test_architecture_lists_every_module_and_no_other():
    modules = {p.relative_to(ROOT).as_posix() for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")
               if p.name != "__init__.py"}
    listed = _architecture_listing()
    assert sorted(modules - listed) == [], "list each new module with its job in docs/ARCHITECTURE.md, under its package"
    named_files = {m for m in listed if not re.match(r"tools/cmd_[a-z]+\.py$", m)}
    assert sorted(named_files - modules) == [], "docs/ARCHITECTURE.md lists modules that do not exist"


def _anchors(text: str) -> set[str]:
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to hyphens."""
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
            for h in re.findall(r"^#+ (.*)$", text, re.M)}


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.name)
def test_relative_links_resolve(doc):
    text = doc.read_text()
    for target, anchor in re.findall(r"\]\(([^)#\s:]*\.md|[^)#\s:]*\.png|)(#[^)\s]+)?\)", text):
        path = (doc.parent / target).resolve() if target else doc
        assert path.exists(), f"{doc.name}: link to missing {target}"
        if anchor and path.suffix == ".md":
            assert anchor[1:] in _anchors(path.read_text()), f"{doc.name}: no heading for {target}{anchor}"


def test_nothing_points_outside_the_repository():
    """Users who clone the repository have no shared/ directory and no contract file
    (docs, code, and the comments of the shipped configs and scenes)."""
    files = [*DOCS, *(p for pkg in (*PACKAGES, "tests") for p in (ROOT / pkg).rglob("*.py")),
             *(ROOT / "config").rglob("*.yaml")]
    pattern = re.compile("CONTRACTS" + r"(\.md| §)|shared" + "/reference")
    offenders = [p.relative_to(ROOT).as_posix() for p in files if pattern.search(p.read_text())]
    assert offenders == [], "write the format into docs/ (formats.md) and point there instead"


def test_readme_setup_block_has_exactly_two_commands():
    text = (ROOT / "README.md").read_text()
    block = text[text.index("<!-- setup:start -->"):text.index("<!-- setup:end -->")]
    commands = [line for line in block.splitlines() if re.match(r"^(python3|\.venv)", line)]
    assert commands == [
        "python3 -m venv .venv && .venv/bin/pip install -e '.[test]' && .venv/bin/tactile demo",
        ".venv/bin/python -m pytest",
    ]
