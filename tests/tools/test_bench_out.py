"""`tactile bench` writes to a new scratch directory unless --out is given: a quick run never
overwrites the committed docs/bench results."""

import tempfile
from types import SimpleNamespace

from tools import bench, cli


def _stub_bench(monkeypatch):
    """The measurement itself is the benchmark's business; here only where it writes."""
    monkeypatch.setattr(bench, "run_bench", lambda *a, **k: SimpleNamespace(checks=[]))
    for name in ("write_csv", "write_markdown", "write_plot"):
        monkeypatch.setattr(bench, name, lambda result, path, *a: path.write_text(name))


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
