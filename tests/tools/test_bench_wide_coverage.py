"""tools.bench_wide --coverage-only: the Wilson interval and the per-class coverage row."""

import math

from tools.bench_wide import _wilson, coverage_report


def test_wilson_interval_matches_its_closed_form():
    lo, hi = _wilson(40, 40)
    assert abs(lo - 40 / (40 + 1.96**2)) < 1e-12 and abs(hi - 1.0) < 1e-12  # k = n: [n/(n + z²), 1]
    lo, hi = _wilson(38, 40)
    assert 0.83 < lo < 0.84 and 0.98 < hi < 0.99  # 95 % observed on 40 values


def test_coverage_report_counts_values_within_1_96_sigma():
    recs = [{"cls": "circle", "got3": "circle", "z": [0.5, -2.5]}, {"cls": "circle", "got3": "ellipse"},
            {"cls": "ellipse", "got3": "ellipse", "z": [1.0, 1.9]}]
    rows = {line.split("|")[1].strip(): line for line in coverage_report(recs).splitlines()[2:]}
    circle = [c.strip() for c in rows["circle"].split("|")[1:-1]]
    assert circle[:5] == ["circle", "2", "50.0", "2", "50.0"]
    assert circle[6] == f"{math.sqrt((0.25 + 6.25) / 2):.2f}"
    assert [c.strip() for c in rows["all"].split("|")[1:-1]][3:5] == ["4", "75.0"]
