"""Damage benchmark (issue 22): damaged run logs, scenes, jaw configs and calibrated
configs, and what the readers make of each. A benchmark, not a test
(tests/hand_driver/test_log_whole.py and tests/tactile_common/test_yaml_strict.py are).

    python -m tools.bench_damage [--seed 1] [--logs 700] [--yaml 700]

Logs: two runs of ``tactile demo --log`` (the default scene's ellipse and the circle
scene), then each damaged copy replayed in-process (``tactile replay L --json --touches T``).
Damage (seeded): bytes flipped, inserted or deleted; a line deleted, repeated, swapped with
the next, moved, or appended after the end; the file cut mid-record or at a record
boundary; CRLF line ends; and the record edits of issue 22 (a sample repeated, a sample
deleted, a sample appended after the result, a sample naming an earlier reading, a touch's
finger swapped, a field's value changed) written back as they were (their hash unchanged).
A quarter of the logs are made version 1 (no record numbers, hash chain or end record, as
earlier versions wrote them) before the damage.

YAML: every scene in config/scenes/, config/jaw.yaml and a calibrated config (what
``tactile calibrate --out`` writes), each damaged copy read by ``load_scene`` (as ``tactile
demo`` reads it: a scene without an object is refused) / ``load_config``. Damage: a line deleted, repeated, swapped or indented; a key misspelt; a
number written in a YAML 1.1 form (sexagesimal, 0x, 0o, leading zero, underscores) or a
value as yes/no/on/off; a byte flipped, a tab inserted; the file cut at a random byte.

Outcomes (the issue's criterion): **refused** exit 2 with one line naming "line N";
**same** accepted with the same answer and byte-identical recognition input (logs: the
``--touches`` request and the answer without timing; YAML: the parsed scene's classes,
object, profile and noise, or the whole parsed config); **cut, said** a log cut at a record
boundary or mid-record, replayed up to its last whole record and saying so (its answer may
differ); **unverified, said** a version 1 log read with its caveat; **valid edit** a YAML
file that is still valid and says something else (a digit changed for a digit, an optional
key deleted: no reader can tell); **silent change** accepted, different, not said (target
0); **refused without a line**; **crash** any other exit or a traceback (target 0).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import random
import re
import sys
import tempfile
import time
from collections import Counter, defaultdict
from dataclasses import asdict, replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUTCOMES = ("refused", "same", "cut, said", "unverified, said", "valid edit", "silent change",
            "refused without a line", "crash")


def _tactile(argv: list[str]) -> tuple[int, str, str]:
    from tools.cli import main

    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            rc = main(argv)
    except BaseException as exc:  # noqa: BLE001 - a bench counts crashes, it does not stop at one
        return -1, out.getvalue(), err.getvalue() + f"Traceback: {type(exc).__name__}: {exc}"
    return rc, out.getvalue(), err.getvalue()


def _without_timing(text: str) -> dict | None:
    try:
        rec = json.loads(text)
    except ValueError:
        return None
    rec.pop("timing", None)
    return rec


# ----------------------------------------------------------------------------- logs
def _base_logs(work: Path) -> list[Path]:
    scenes = ["config/scenes/default.yaml", "config/scenes/circle.yaml"]
    logs = []
    for k, scene in enumerate(scenes):
        log = work / f"base{k}.jsonl"
        rc, _, err = _tactile(["demo", "--scene", str(ROOT / scene), "--json", "--log", str(log)])
        if rc != 0:
            raise SystemExit(f"bench_damage: demo on {scene} failed: {err.strip()}")
        logs.append(log)
    return logs


def _as_version_1(lines: list[bytes]) -> list[bytes]:
    out = []
    for line in lines:
        rec = json.loads(line)
        if rec["type"] == "end":
            continue
        rec.pop("seq", None)
        rec.pop("h", None)
        if rec["type"] == "header":
            rec["version"] = 1
        out.append(json.dumps(rec, separators=(",", ":")).encode() + b"\n")
    return out


def _edit_record(line: bytes, rng: random.Random, fingers: list[str]) -> bytes:
    """A field of one record changed, the record written back with its old hash."""
    rec = json.loads(line)
    keys = [k for k in rec if k not in ("type", "seq", "h", "format", "version")]
    if not keys:
        return line + b" "
    key = rng.choice(keys)
    v = rec[key]
    if key == "finger":
        rec[key] = next(f for f in fingers if f != v)
    elif isinstance(v, bool):
        rec[key] = not v
    elif isinstance(v, int):
        rec[key] = v + rng.choice([-2, -1, 1, 2])
    elif isinstance(v, float):
        rec[key] = v * (1.0 + rng.choice([-1e-3, 1e-6, 1e-3]))
    elif isinstance(v, list) and v and isinstance(v[0], (int, float)) and not isinstance(v[0], bool):
        j = rng.randrange(len(v))
        v[j] = v[j] + 1
    elif isinstance(v, str):
        rec[key] = v + "x"
    else:
        rec.pop(key)
    body = json.dumps({k: x for k, x in rec.items() if k != "h"}, separators=(",", ":")).encode()
    return body[:-1] + (b',"h":"' + rec["h"].encode() + b'"}' if "h" in rec else b"}") + b"\n"


def _damage_log(lines: list[bytes], rng: random.Random, fingers: list[str]) -> tuple[str, bytes]:
    lines = list(lines)
    n = len(lines)
    idx = {t: [k for k, s in enumerate(lines) if s.startswith(b'{"type":"' + t.encode())]
           for t in ("sample", "result", "end", "touch_start")}
    kind = rng.choice(["flip", "insert", "delete bytes", "delete line", "repeat line", "swap lines", "move line",
                       "append line", "cut mid-record", "cut at a record", "crlf", "repeat samples", "delete sample",
                       "sample after result", "sample at an earlier reading", "swap a touch's finger", "edit a field",
                       "edit a field"])
    raw = b"".join(lines)
    if kind == "flip":
        b = bytearray(raw)
        for _ in range(rng.randint(1, 3)):
            i = rng.randrange(len(b) - 1)
            b[i] = rng.choice([c for c in range(256) if c not in (b[i], 10)])
        return kind, bytes(b)
    if kind == "insert":
        i = rng.randrange(len(raw))
        return kind, raw[:i] + bytes(rng.choice(b' 0a"{},:x\t\n') for _ in range(rng.randint(1, 4))) + raw[i:]
    if kind == "delete bytes":
        i = rng.randrange(len(raw) - 1)
        return kind, raw[:i] + raw[i + rng.randint(1, 4):]
    if kind == "cut mid-record":
        k = rng.randrange(n)
        start = sum(len(s) for s in lines[:k])
        return kind, raw[:start + rng.randrange(1, len(lines[k]))]
    if kind == "cut at a record":
        return kind, b"".join(lines[:rng.randrange(1, n)])
    if kind == "crlf":
        return kind, raw.replace(b"\n", b"\r\n")
    k = rng.randrange(1, n)
    if kind == "delete line":
        del lines[k]
    elif kind == "repeat line":
        lines.insert(k, lines[k])
    elif kind == "swap lines":
        k = min(k, n - 2)
        lines[k], lines[k + 1] = lines[k + 1], lines[k]
    elif kind == "move line":
        lines.insert(rng.randrange(1, n), lines.pop(k))
    elif kind == "append line":
        lines.append(lines[k])
    elif kind == "repeat samples":
        s = rng.choice(idx["sample"])
        lines[s + 1:s + 1] = [lines[s]] * rng.randint(1, 4)
    elif kind == "delete sample":
        del lines[rng.choice(idx["sample"])]
    elif kind == "sample after result":
        r = (idx["result"] or [n - 1])[0]
        lines.insert(r + 1, lines[rng.choice(idx["sample"])])
    elif kind == "sample at an earlier reading":
        s = rng.choice(idx["sample"])
        rec = json.loads(lines[s])
        rec["reading"] = max(0, rec["reading"] - rng.randint(1, 40))
        body = json.dumps({key: x for key, x in rec.items() if key != "h"}, separators=(",", ":")).encode()
        lines[s] = body[:-1] + (b',"h":"' + rec["h"].encode() + b'"}' if "h" in rec else b"}") + b"\n"
    elif kind == "swap a touch's finger":
        t = json.loads(lines[rng.choice(idx["touch_start"])])["touch"]
        other = {f.encode(): g.encode() for f, g in zip(fingers, fingers[::-1])}
        tag = b'"touch":%d,' % t
        lines = [re.sub(rb'"finger":"(\w+)"', lambda m: b'"finger":"' + other.get(m.group(1), m.group(1)) + b'"', s)
                 if tag in s else s for s in lines]
    else:  # edit a field
        lines[k] = _edit_record(lines[k], rng, fingers)
    return kind, b"".join(lines)


def _judge_log(rc: int, out: str, err: str, base: tuple[dict, bytes], touches: Path) -> str:
    if rc not in (0, 2) or "Traceback" in err:
        return "crash"
    said_cut = "the run was cut" in err
    unverified = "cannot be verified" in err
    if rc == 2:
        if said_cut:
            return "cut, said"
        if unverified:  # a version 1 log: what it holds is refused (too few touches), with its caveat
            return "unverified, said"
        return "refused" if re.search(r": line \d+: ", err) and err.count("\n") == 1 else "refused without a line"
    same = _without_timing(out) == base[0] and touches.exists() and touches.read_bytes() == base[1]
    if same:
        return "same"
    if said_cut:
        return "cut, said"
    return "unverified, said" if unverified else "silent change"


def _count(outcomes: Counter, by_kind: dict, outcome: str, kind: str, keep: Path, raw: bytes, progress,
           said: str) -> None:
    """Counts one damaged file's ``outcome`` overall and under its damage ``kind``; a file that
    showed a fault of ours (a silent change, a crash, a refusal without its line) is kept at
    ``keep`` and ``said`` with its path."""
    outcomes[outcome] += 1
    by_kind[kind][outcome] += 1
    if outcome in ("silent change", "crash", "refused without a line"):
        keep.write_bytes(raw)
        progress(f"{said} [{keep}]")


def bench_logs(n: int, rng: random.Random, work: Path, progress) -> tuple[Counter, dict, Counter]:
    from hand_driver.log import read_log

    outcomes, by_kind, versions = Counter(), defaultdict(Counter), Counter()
    bases = []
    for log in _base_logs(work) if n else []:
        touches = work / (log.stem + ".touches.json")
        rc, out, err = _tactile(["replay", str(log), "--json", "--touches", str(touches), "--force"])
        assert rc == 0, err
        fingers = [f.name for f in read_log(log).jaw_config().fingers]
        lines = log.read_bytes().splitlines(keepends=True)
        bases.append((lines, _as_version_1(lines), (_without_timing(out), touches.read_bytes()), fingers))
    damaged, touches = work / "damaged.jsonl", work / "damaged.touches.json"
    t0 = time.perf_counter()
    for i in range(n):
        lines, v1, base, fingers = rng.choice(bases)
        version = 1 if rng.random() < 0.25 else 2
        kind, raw = _damage_log(v1 if version == 1 else lines, rng, fingers)
        damaged.write_bytes(raw)
        touches.unlink(missing_ok=True)
        rc, out, err = _tactile(["replay", str(damaged), "--json", "--touches", str(touches), "--force"])
        outcome = _judge_log(rc, out, err, base, touches)
        versions[(version, outcome)] += 1
        _count(outcomes, by_kind, outcome, kind, work / f"kept-{i}.jsonl", raw, progress,
               f"log {i}: {outcome} ({kind}, version {version}): {err.strip()[:200]}")
        if (i + 1) % 100 == 0:
            progress(f"{i + 1}/{n} logs, {time.perf_counter() - t0:.0f} s")
    return outcomes, by_kind, versions


# ----------------------------------------------------------------------------- YAML
_NUMBER = re.compile(rb"(?<![\w.])-?\d+(?:\.\d+)?(?![\w.])")


def _yaml11_number(text: bytes, rng: random.Random) -> bytes:
    nums = list(_NUMBER.finditer(text))
    if not nums:
        return text
    m = rng.choice(nums)
    v = float(m.group())
    iv = int(abs(v))
    sign = "-" if v < 0 else ""
    forms = [f"{sign}{iv // 60}:{iv % 60:02d}", f"{sign}0x{iv:x}", f"{sign}0o{iv:o}", f"{sign}0{iv}",
             f"{sign}{iv // 10 or 1}_{iv % 10}"]
    return text[:m.start()] + rng.choice(forms).encode() + text[m.end():]


def _damage_yaml(raw: bytes, rng: random.Random) -> tuple[str, bytes]:
    lines = raw.splitlines(keepends=True)
    content = [k for k, s in enumerate(lines) if s.strip() and not s.lstrip().startswith(b"#")]
    kind = rng.choice(["delete line", "repeat line", "swap lines", "indent", "misspell key", "YAML 1.1 number",
                       "YAML 1.1 number", "yes/no/on/off", "flip", "tab", "cut"])
    k = rng.choice(content)
    if kind == "delete line":
        kind = "delete line", lines[k]
        del lines[k]
        return kind, b"".join(lines)
    elif kind == "repeat line":
        lines.insert(k, lines[k])
    elif kind == "swap lines":
        j = content[min(content.index(k) + 1, len(content) - 1)]
        lines[k], lines[j] = lines[j], lines[k]
    elif kind == "indent":
        lines[k] = (b" " + lines[k]) if rng.random() < 0.5 else lines[k][1:]
    elif kind == "misspell key":
        keys = list(re.finditer(rb"([A-Za-z_]{2,}):", lines[k]))
        if keys:
            m = rng.choice(keys)
            word = m.group(1)
            j = rng.randrange(len(word))
            lines[k] = lines[k][:m.start(1)] + word[:j] + word[j + 1:] + lines[k][m.end(1):]
    elif kind == "YAML 1.1 number":
        lines[k] = _yaml11_number(lines[k], rng)
    elif kind == "yes/no/on/off":
        values = list(re.finditer(rb": ([^\s,{}\[\]#]+)", lines[k]))
        if values:
            m = rng.choice(values)
            lines[k] = lines[k][:m.start(1)] + rng.choice([b"yes", b"no", b"on", b"off", b"Yes", b"NO"]) \
                + lines[k][m.end(1):]
    elif kind == "flip":
        b = bytearray(b"".join(lines))
        i = rng.randrange(len(b))
        b[i] = rng.randrange(256)
        return kind, bytes(b)
    elif kind == "tab":
        i = rng.randrange(len(lines[k]))
        lines[k] = lines[k][:i] + b"\t" + lines[k][i:]
    else:
        whole = b"".join(lines)
        return kind, whole[:rng.randrange(1, len(whole))]
    return kind, b"".join(lines)


def _scene_key(scene) -> tuple:
    """What a scene changes in any answer (its name and description do not)."""
    return scene.classes, scene.object, scene.profile, scene.noise


def _config_key(config) -> dict:
    return asdict(replace(config, source=""))


#: keys the formats make optional, with a documented default (docs/formats.md): deleting one
#: leaves a valid file that says something else
OPTIONAL_KEYS = {"scene": {"name", "description", "classes", "profile", "noise", "side", "extent", "closure"},
                 "config": {"bus", "port", "baudrate", "protocol", "retries", "timeout_s", "watchdog_ms", "motion",
                            "workspace", "profile_velocity", "profile_acceleration", "approach_speed_mm_s",
                            "approach_step_mm", "move_speed_mm_s", "turn_speed_deg_s", "contact_current_ma",
                            "goal_current_ma", "backoff_mm", "max_touch_s", "center_mm", "radius_mm", "direction",
                            "min_deg", "max_deg", "current_limit_ma"}}
OPTIONAL_KEYS["calibrated config"] = OPTIONAL_KEYS["config"]


def _valid_edit(what: str, kind: str, base: bytes, damaged: bytes, deleted: bytes) -> str | None:
    """Why a damaged file that is still valid and says something else cannot be told from a
    file written so (a digit for a digit; an optional key deleted: its default applies), or None."""
    if kind == "flip" and len(base) == len(damaged):
        i = next(k for k in range(len(base)) if base[k] != damaged[k])
        if chr(base[i]).isdigit() and chr(damaged[i]).isdigit():
            return "a digit for a digit"
    if kind == "delete line":
        m = re.match(rb"\s*(?:-\s*)?(\w+):", deleted)
        if m and m.group(1).decode() in OPTIONAL_KEYS[what]:
            return f"optional {m.group(1).decode()} deleted"
    if kind == "cut" and damaged.endswith(b"\n"):
        gone = set(re.findall(rb"^\s*(?:-\s*)?(\w+):", base[len(damaged):], re.M))
        if gone and all(k.decode() in OPTIONAL_KEYS[what] for k in gone):
            return "cut at a line end before optional keys only"
    return None


def bench_yaml(n: int, rng: random.Random, work: Path, progress) -> tuple[Counter, dict, Counter]:
    import numpy as np

    from hand_driver.config import dump_config, load_config, perturbed
    from recognizer.scene import load_scene
    from tactile_common.errors import InputError

    calibrated = work / "calibrated.yaml"
    dump_config(perturbed(load_config(ROOT / "config/jaw.yaml"), np.random.default_rng(rng.randrange(2 ** 32))),
                calibrated, header="tactile calibrate --out (bench_damage)\nrms after 0.02 mm")
    files = [("scene", p) for p in sorted((ROOT / "config/scenes").glob("*.yaml"))]
    files += [("config", ROOT / "config/jaw.yaml"), ("calibrated config", calibrated)]
    def demo_scene(p):  # as tactile demo reads a scene: its object is required (recognize ignores it)
        scene = load_scene(str(p))
        if scene.object is None:
            raise InputError(f"{p}: line 1: object: missing: the scene has no object for the emulator to show")
        return _scene_key(scene)

    readers = {"scene": demo_scene,
               "config": (lambda p: _config_key(load_config(p))),
               "calibrated config": (lambda p: _config_key(load_config(p)))}
    bases = [(what, path.read_bytes(), readers[what](path)) for what, path in files]
    outcomes, by_kind, by_file, edits = Counter(), defaultdict(Counter), Counter(), Counter()
    damaged = work / "damaged.yaml"
    for i in range(n):
        what, raw, base = rng.choice(bases)
        kind, text = _damage_yaml(raw, rng)
        kind, deleted = kind if isinstance(kind, tuple) else (kind, b"")
        damaged.write_bytes(text)
        try:
            got = readers[what](damaged)
        except InputError as exc:
            msg = str(exc)
            outcome = "refused" if re.search(r"line \d+", msg) and "\n" not in msg else "refused without a line"
        except Exception as exc:  # noqa: BLE001 - counted
            outcome, msg = "crash", f"{type(exc).__name__}: {exc}"
        else:
            msg = "" if got == base else _valid_edit(what, kind, raw, text, deleted)
            outcome = "same" if got == base else "valid edit" if msg else "silent change"
            if msg:
                edits[msg] += 1
        by_file[(what, outcome)] += 1
        _count(outcomes, by_kind, outcome, kind, work / f"kept-{i}.yaml", text, progress,
               f"yaml {i}: {outcome} ({kind}, {what}): {(msg or '')[:200]}")
    return outcomes, by_kind, by_file, edits


# ----------------------------------------------------------------------------- report
def _table(title: str, by_kind: dict, total: Counter) -> list[str]:
    cols = [o for o in OUTCOMES if total[o] or o in ("silent change", "crash")]
    rows = [f"| {title} | " + " | ".join(cols) + " |", "|---|" + "---|" * len(cols)]
    for kind in sorted(by_kind):
        rows.append(f"| {kind} | " + " | ".join(str(by_kind[kind][c]) for c in cols) + " |")
    rows.append(f"| **all {sum(total.values())}** | " + " | ".join(f"**{total[c]}**" for c in cols) + " |")
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--logs", type=int, default=700)
    ap.add_argument("--yaml", type=int, default=700)
    ap.add_argument("--keep", type=Path, default=None, help="directory for the damaged files that failed (default: temp)")
    args = ap.parse_args(argv)
    say = lambda m: print(f"  {m}", file=sys.stderr, flush=True)  # noqa: E731
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="bench_damage_") as tmp:
        work = args.keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        y_out, y_kind, y_file, y_edits = bench_yaml(args.yaml, random.Random(args.seed * 7919 + 1), work, say)
        l_out, l_kind, l_ver = bench_logs(args.logs, random.Random(args.seed), work, say)
    print(f"damage bench, seed {args.seed}: {args.logs} logs, {args.yaml} YAML files, "
          f"{time.perf_counter() - t0:.0f} s\n")
    print("\n".join(_table("run log damage", l_kind, l_out)))
    print("\nby log version: " + ", ".join(f"v{v} {o} {c}" for (v, o), c in sorted(l_ver.items())))
    print()
    print("\n".join(_table("YAML damage", y_kind, y_out)))
    print("\nby file: " + ", ".join(f"{w} {o} {c}" for (w, o), c in sorted(y_file.items())))
    if y_edits:
        print("valid edits: " + ", ".join(f"{k} {c}" for k, c in sorted(y_edits.items())))
    bad = l_out["silent change"] + l_out["crash"] + y_out["silent change"] + y_out["crash"]
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
