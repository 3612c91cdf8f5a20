"""The bench's "what each jaw can tell" table counts an object answered right only after
its advised move in a column of its own (tools.bench_explore.print_tell_table)."""

from pathlib import Path

from tools.bench_explore import print_tell_table


def _run(cls: str | None, reason: str = "", move: dict | None = None) -> dict:
    rec = None if cls is None else {"class": cls, "params": {"a": 5.0}, "reason": reason}
    return {"recognition": rec, "stderr": [""], "move": move, "robot_s": 20.0, "time_s": {}}


def test_right_after_the_advised_move_is_its_own_column(capsys):
    obj = {"class": "parabola", "params": {"a": 5.0}}
    scenes = [(Path(f"rand{k}.yaml"), obj) for k in range(5)]
    move = {"dx": 3.0, "dy": 0.0, "turn_deg": 0.0, "about": [100.0, 0.0]}
    results = [_run("parabola"), _run("unclassified", "no pad can roll", move),
               _run("unclassified", "no pad can roll", move), _run("unclassified", "x", move), _run("ellipse")]
    # the second runs: right, wrong, refused again; none for the right and the wrong first answers
    print_tell_table(scenes, results, "jaw.yaml", [None, "yes", "**WRONG**", "refused", None])
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| parabola")]
    assert len(rows) == 1
    assert "| 1 / 1 / 1 / 2 |" in rows[0]  # right, right after the move, refused, wrong (one first, one after)


def test_without_follow_the_table_keeps_three_counts(capsys):
    obj = {"class": "circle", "params": {"r": 5.0}}
    print_tell_table([(Path("c.yaml"), obj)], [_run("unclassified", "no pad can roll")], "jaw.yaml")
    out = capsys.readouterr().out
    assert "right / refused / wrong |" in out and "| 0 / 1 / 0 |" in out


def test_kappa_comparison_leaves_a_flat_press_out(monkeypatch):
    """``--kappa`` on a run answered from flat presses: a press's touch is a ContactTouch,
    without the envelope's curvature; it is left out of the κ table (it raised
    AttributeError and ended the bench: P-series jaw, seed 17, cubical 30)."""
    from types import SimpleNamespace

    import hand_driver.log
    import tactile_jaw.pipeline
    from recognizer.touches import ContactTouch
    from tools.bench_explore import kappa_comparison

    settings = {"touches": 8, "samples_per_touch": 9, "roll_span_deg": 18.0, "min_touches": 3}
    header = {"settings": settings, "scene": None}
    monkeypatch.setattr(hand_driver.log, "read_log",
                        lambda path: SimpleNamespace(header=header, jaw_config=lambda: None))
    press = SimpleNamespace(samples=ContactTouch(100.0, 0.0, 1.0, 0.0, 0.0))
    monkeypatch.setattr(tactile_jaw.pipeline, "logged_touches", lambda config, contents, settings: [press])
    monkeypatch.setattr(tactile_jaw.pipeline, "stated_noise", lambda touches: None)
    assert kappa_comparison(Path("unused.log"), {"class": "line", "params": {}}) == {"rows": []}
