"""`tactile bench` writes to a new scratch directory unless --out is given: a quick run never
overwrites the committed docs/bench results."""

import tempfile
from types import SimpleNamespace

from tools import bench, bench_report, cli


def _stub_bench(monkeypatch):
    """The measurement itself is the benchmark's business; here only where it writes."""
    monkeypatch.setattr(bench, "run_bench", lambda *a, **k: SimpleNamespace(checks=[]))
    for name in ("write_csv", "write_markdown", "write_plot"):
        monkeypatch.setattr(bench_report, name, lambda result, path, *a: path.write_text(name))


def test_bench_without_out_writes_to_scratch_not_docs(tmp_path, monkeypatch, capsys):
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    work = tmp_path / "repo"
    (work / "docs" / "bench").mkdir(parents=True)
    monkeypatch.chdir(work)
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    _stub_bench(monkeypatch)
    assert cli.main(["bench", "--quick"]) == 0
    assert list((work / "docs" / "bench").iterdir()) == []
    (out,) = list(scratch.iterdir())
    assert out.name.startswith("tactile-bench-")
    assert sorted(p.name for p in out.iterdir()) == ["bench.csv", "bench.md", "bench.png"]
    assert str(out / "bench.md") in capsys.readouterr().out


def test_bench_out_is_honoured(tmp_path, monkeypatch):
    _stub_bench(monkeypatch)
    assert cli.main(["bench", "--quick", "--out", str(tmp_path / "mine")]) == 0
    assert sorted(p.name for p in (tmp_path / "mine").iterdir()) == ["bench.csv", "bench.md", "bench.png"]


def test_bench_wide_trials_writes_bench_wide(tmp_path, monkeypatch, capsys):
    """--wide-trials N runs the widened distribution (stubbed here: its trials are the
    benchmark's business) and writes its tables beside the others."""
    from tools import bench_wide

    _stub_bench(monkeypatch)
    rec = {"cls": "line", "region": "segment", "i": 0, "got3": "line", "err3": 0.0, "ms": 1.0, "nt_ms": 0.5,
           "got5": "line", "err5": 0.0, "gotS": "line", "errS": 0.0, "used": 0}
    monkeypatch.setattr(bench_wide, "run_wide", lambda classes, trials, seed, jobs, progress: [rec] * trials)
    assert cli.main(["bench", "--quick", "--wide-trials", "2", "--out", str(tmp_path / "w")]) == 0
    text = (tmp_path / "w" / "bench_wide.md").read_text()
    assert "--wide-trials 2" in text and "| line | 2 | 100.0 |" in text
    assert cli.main(["bench", "--quick", "--wide-trials", "-1", "--out", str(tmp_path / "x")]) == 2
