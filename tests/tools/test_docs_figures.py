"""The README's demo block is what ``tactile demo`` prints (tools/docs_figures.py writes
it): every line but the wall time, robot time included (the emulator runs in lockstep).
When this fails, the code changed what the demo prints: run ``python -m tools.docs_figures``
and commit the docs it rewrote."""

from __future__ import annotations

from tools.docs_figures import EXPLORATION, README, WALL_TIME, block


def _lines(text: str) -> list[str]:
    return [WALL_TIME.sub("wall time … s", ln) for ln in text.strip().strip("`").strip().splitlines()
            if not ln.startswith(("log: ", "mcap: "))]


def test_readme_demo_block_is_what_the_demo_prints(default_demo):
    printed = _lines(default_demo["out"])
    assert printed[0].startswith("recognized: ellipse") and printed[-1].startswith("touches: ")
    assert _lines(block(README.read_text(), "demo")) == printed, \
        "the README's demo block is stale: run python -m tools.docs_figures"
    assert block(EXPLORATION.read_text(), "demo") == block(README.read_text(), "demo")
