"""The recognizer's modules import one another without a circle (docs/ARCHITECTURE.md):
every import, module-level or inside a function, is an edge; a circle (scene ↔ touches,
once) hides an order dependence behind deferred imports."""

from __future__ import annotations

from tests.test_layers import ROOT, imported_modules


def _graph() -> dict[str, set[str]]:
    mods = {p.stem: p for p in (ROOT / "recognizer").glob("*.py") if p.stem != "__init__"}
    graph = {}
    for name, path in mods.items():
        deps = set()
        for _, imp in imported_modules(path.read_text(encoding="utf-8"), "recognizer"):
            parts = imp.split(".")
            if parts[0] == "recognizer" and len(parts) > 1 and parts[1] in mods and parts[1] != name:
                deps.add(parts[1])
        graph[name] = deps
    return graph


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(n: str) -> list[str] | None:
        state[n] = 1
        stack.append(n)
        for m in sorted(graph[n]):
            if state.get(m) == 1:
                return stack[stack.index(m):] + [m]
            if m not in state and (found := visit(m)):
                return found
        stack.pop()
        state[n] = 2
        return None

    for n in sorted(graph):
        if n not in state and (found := visit(n)):
            return found
    return None


def test_recognizer_imports_have_no_circle():
    assert _cycle(_graph()) is None, " -> ".join(_cycle(_graph()))


def test_a_circle_is_found():
    assert _cycle({"scene": {"touches"}, "touches": {"scene"}}) == ["scene", "touches", "scene"]
