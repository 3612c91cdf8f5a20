"""`tactile demo` of the cubical parabola example on the P-series jaw: answered right, and
`tactile replay --json` of its log gives the same answer. On main 6613250+i21 it was refused
("no class fits", χ² 41.3 on 9 dof): the whitening of its touches' rank-deficient noise
factors depended on the scale-free unit (tests/tactile_jaw/test_whitening_units.py)."""

from __future__ import annotations

import json

from tactile_common.yamlfile import read_yaml

SCENE = "config/scenes/cubical_parabola.yaml"


def test_the_cubical_example_on_the_p_series_jaw_is_right_and_replays_the_same(tmp_path, demo_answer, tactile_in_process):
    scene = read_yaml(SCENE, "scene")
    log = tmp_path / "cubical.jsonl"
    answer = demo_answer(scene, tmp_path / "cubical.yaml", log, config="config/jaw-p.yaml")
    assert answer["class"] == "cubical_parabola", answer.get("reason")
    for k, truth in scene["object"]["params"].items():
        assert abs(answer["params"][k] / truth - 1.0) < 0.03, (k, answer["params"][k], truth)
    rc, out, err = tactile_in_process(["replay", "--json", str(log)])
    assert rc == 0, err
    again = json.loads(out)
    assert again["class"] == answer["class"] and again["params"] == answer["params"]
