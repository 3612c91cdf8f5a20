"""A scene whose finite object's closure makes the boundary cross itself is refused by
every command that reads it: exit 2, one line naming the key, no traceback."""

from __future__ import annotations

import pytest

SELF_CROSSING = """\
name: bad
classes: [parabola]
object:
  class: parabola
  params: {a: 8.0}
  pose: {theta: 0.0, x: 85.0, y: 0.0}
  extent: [-1.4, 1.4]
  closure: [[40.0, -30.0], [40.0, 30.0]]   # corners in the wrong order: the segments cross
"""


@pytest.mark.parametrize("command", [["demo", "--scene"], ["sim", "--scene"]])
def test_self_crossing_closure_is_refused_in_one_line(tmp_path, command, tactile_in_process):
    path = tmp_path / "bad.yaml"
    path.write_text(SELF_CROSSING)
    rc, out, err = tactile_in_process([*command, str(path)])
    lines = err.strip().splitlines()
    assert rc == 2 and out == "" and len(lines) == 1
    assert "bad.yaml" in lines[0] and "object.closure: the boundary crosses itself" in lines[0]
