"""`tactile replay --json` of P semicubical 131 (held-out finite 499 of session 31, config/jaw-p.yaml):
its roll 6's first sample lies on the object's end corner (69 µm off the curve). Answered with
it: a −0.445 % (z −3.67), b −0.636 % (z +3.95); the end-sample test (tactile_jaw.decide.
without_corner_end, z 4.08 against 3.48 over 4 tested ends) leaves it out: a −0.03 %, b −0.03 %."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

LOG = Path(__file__).parents[1] / "tactile_jaw" / "data" / "p_semicubical_131_end_corner.log.gz"
TRUTH = {"a": 0.3300712990162086, "b": -1.2}


def test_the_end_corner_sample_is_left_out_on_replay(tmp_path, tactile_in_process):
    log = tmp_path / "rand131.log"
    log.write_bytes(gzip.decompress(LOG.read_bytes()))
    rc, out, err = tactile_in_process(["replay", "--json", str(log)])
    assert rc == 0, err
    answer = json.loads(out)
    assert answer["class"] == "semicubical_parabola", answer["reason"]
    assert "left: touch 6's first sample (reading 447) left out" in answer["reason"]
    for k, truth in TRUTH.items():
        z = (answer["params"][k] - truth) / answer["uncertainty"][k]
        assert abs(z) < 1.0, (k, answer["params"][k], z)
