"""Files are never destroyed: outputs refuse an existing file without --force and, even with
it, a file the same command reads; whole files are replaced atomically."""

import os
from pathlib import Path

import pytest

from tactile_common.errors import InputError
from tactile_common.files import atomic_path, atomic_write, check_output, create_exclusive
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_check_output_refuses_existing_and_inputs(tmp_path):
    f = tmp_path / "x.json"
    assert check_output(f, force=False) == f
    f.write_text("keep")
    with pytest.raises(InputError, match="exists; pass --force"):
        check_output(f, force=False)
    assert check_output(f, force=True) == f
    with pytest.raises(InputError, match="reads"):
        check_output(tmp_path / "." / "x.json", force=True, reads=[f])
    link = tmp_path / "link.json"
    link.symlink_to(f)
    with pytest.raises(InputError, match="reads"):
        check_output(link, force=True, reads=[f])
    with pytest.raises(InputError, match="directory"):
        check_output(tmp_path, force=True)
    assert f.read_text() == "keep"


def test_atomic_write_replaces_whole_or_nothing(tmp_path):
    f = tmp_path / "t.csv"
    f.write_text("old")
    atomic_write(f, "new")
    assert f.read_text() == "new"
    with pytest.raises(RuntimeError):
        with atomic_path(f) as tmp:
            tmp.write_text("half")
            raise RuntimeError("writer died")
    assert f.read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.csv"]  # no temporary left behind
    mode = os.stat(f).st_mode & 0o777
    assert mode & 0o600 == 0o600 and not mode & 0o022


def test_log_created_exclusively(tmp_path):
    f = tmp_path / "run.jsonl"
    create_exclusive(f, force=False).close()
    with pytest.raises(InputError, match="exists"):
        create_exclusive(f, force=False)
    create_exclusive(f, force=True).close()


@pytest.mark.parametrize("argv_of", [
    lambda t: ["demo", "--config", str(t / "jaw.yaml"), "--log", str(t / "jaw.yaml"), "--force"],
    lambda t: ["demo", "--config", str(t / "jaw.yaml"), "--plot", str(t / "jaw.yaml"), "--force"],
    lambda t: ["demo", "--config", str(t / "jaw.yaml"), "--log", str(t / "keep.txt")],
    lambda t: ["replay", str(t / "keep.txt"), "--touches", str(t / "keep.txt"), "--force"],
    lambda t: ["replay", str(t / "jaw.yaml"), "--touches", str(t / "keep.txt")],
    lambda t: ["calibrate", "--config", str(t / "jaw.yaml"), "--reference", str(t / "keep.txt"),
               "--port", "/dev/null", "--out", str(t / "keep.txt"), "--force"],
])
def test_commands_refuse_before_any_work(tmp_path, capsys, argv_of):
    (tmp_path / "jaw.yaml").write_bytes((ROOT / "config/jaw.yaml").read_bytes())
    (tmp_path / "keep.txt").write_text("keep")
    assert main(argv_of(tmp_path)) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and ("exists; pass --force" in err or "reads" in err)
    assert (tmp_path / "keep.txt").read_text() == "keep"
    assert (tmp_path / "jaw.yaml").read_bytes() == (ROOT / "config/jaw.yaml").read_bytes()


def test_bench_out_refuses_existing_table(tmp_path, capsys):
    (tmp_path / "bench.md").write_text("committed")
    assert main(["bench", "--quick", "--out", str(tmp_path)]) == 2
    assert "exists; pass --force" in capsys.readouterr().err
    assert (tmp_path / "bench.md").read_text() == "committed"
