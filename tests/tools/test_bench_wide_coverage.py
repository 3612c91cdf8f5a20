"""tools.bench_wide --coverage-only: the Wilson interval and the per-class coverage row."""

import math

from tools.bench_wide import _wilson, coverage_report


def test_wilson_interval_matches_its_closed_form():
    lo, hi = _wilson(40, 40)
    assert abs(lo - 40 / (40 + 1.96**2)) < 1e-12 and abs(hi - 1.0) < 1e-12  # k = n: [n/(n + z²), 1]
    lo, hi = _wilson(38, 40)
    assert 0.83 < lo < 0.84 and 0.98 < hi < 0.99  # 95 % observed on 40 values


def test_coverage_report_counts_values_within_1_96_sigma_per_class_and_decade():
    recs = [{"cls": "circle", "got3": "circle", "L": 3.3, "z": [0.5, -2.5], "zi": [0.5, -2.2]},
            {"cls": "circle", "got3": "ellipse", "L": 40.0},
            {"cls": "ellipse", "got3": "ellipse", "L": 5.0, "z": [1.0, 3.5], "zi": [1.0, 2.9]}]
    rows = {line.split("|")[1].strip(): line for line in coverage_report(recs).splitlines()[2:]}
    circle = [c.strip() for c in rows["circle"].split("|")[1:-1]]
    assert circle[:5] == ["circle", "2", "50.0", "2", "50.0"]
    assert circle[6] == "100.0" and circle[7] == f"{math.sqrt((0.25 + 6.25) / 2):.2f}"
    assert circle[8] == "50.0 / 100.0" and circle[9] == "2.5"  # the interval's z; the largest |z|
    assert [c.strip() for c in rows["all"].split("|")[1:-1]][3:5] == ["4", "50.0"]
    ones = [c.strip() for c in rows["L 1e0 mm"].split("|")[1:-1]]  # L 3.3 and 5 mm: decade 0
    assert ones[1:5] == ["2", "100.0", "4", "50.0"] and ones[6] == "75.0" and ones[8] == "50.0 / 100.0"
    assert "L 1e1 mm" not in rows  # its one trial answered another class: no value


def test_coverage_after_suggestions_reads_that_stages_answers():
    """``stage`` "S": the right answers after ≤ 2 suggested touches (``gotS``, ``zS``), apart
    from the 3-touch ones: a trial wrong with 3 touches and right after its suggestions counts."""
    recs = [{"cls": "semicubical_parabola", "got3": "parabola", "gotS": "semicubical_parabola", "L": 2.0,
             "zS": [0.4, 3.2], "ziS": [0.4, 2.8]},
            {"cls": "semicubical_parabola", "got3": "semicubical_parabola", "gotS": "semicubical_parabola", "L": 3.0,
             "z": [5.0, 5.0], "zS": [1.0, -1.5]}]
    rows = {line.split("|")[1].strip(): line for line in coverage_report(recs, "S").splitlines()[2:]}
    row = [c.strip() for c in rows["semicubical_parabola"].split("|")[1:-1]]
    assert row[1:5] == ["2", "100.0", "4", "75.0"] and row[6] == "75.0" and row[8] == "75.0 / 100.0"
    assert row[9] == "3.2"
