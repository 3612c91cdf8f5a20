"""Fuzz benchmark of the recognition service: ≥ 10,000 hostile lines to ONE
``tactile recognize --stream`` process, one line at a time, and what it did with them.

    python -m tools.bench_fuzz [--lines 10000] [--seed 1]

The lines (seeded): valid requests (exact contacts and noisy samples of random shapes);
the same with one value anywhere in the tree replaced by a hostile one (wrong types,
huge, tiny, non-finite or 400-digit numbers, deep nesting, long strings, device paths,
600-sample touches, 100 touches); byte-level damage (flipped bytes, invalid UTF-8, cut
lines, random bytes); and every case of issue 12 (a list as a class name, 10**20 in a
scene, a 5,000-character or /dev/zero scene path, a 100,000-sample touch, 100,000
contacts, κ = 1e200, a 3 MiB line, 20,000-deep nesting, 64 contacts with a 10 ms timeout).

Printed: lines sent, answers (recognitions / errors / cut off by the timeout), crashes
(the process ended, or wrote a traceback; target 0), hangs (no answer within
``--hang-s``; target 0), peak memory of the service and of its worker (RSS sampled every
20 ms) and the latency per line (median, p99, worst, and which kind was worst).
A benchmark, not a test (tests/test_fuzz_inputs.py is the fast property test).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import select
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from recognizer import synth
from recognizer.curves import CURVES, Pose
from tools.bench_recognizer import exact_request

ROOT = Path(__file__).resolve().parents[1]
_RAW = "\u0000RAW{}\u0000"  # placeholder for a JSON token json.dumps cannot write (NaN, 400 digits)


def _valid_requests(rng: random.Random, n: int) -> list[dict]:
    """Valid requests: exact contacts of random shapes, and noisy samples touches."""
    out = []
    nrng = np.random.default_rng(rng.randrange(2 ** 32))
    for i in range(n):
        shape = synth.random_shape(rng.choice(list(CURVES)), nrng)
        lo, hi = shape.t_range
        if i % 2 == 0:
            t = sorted(rng.uniform(lo, hi) for _ in range(rng.randint(2, 6)))
            req = exact_request(shape.cls, shape.params, t, shape.pose, False)
        else:
            touches = []
            for t_c in sorted(rng.uniform(lo, hi) for _ in range(rng.randint(3, 5))):
                st, _ = synth.sample_touch(shape.curve, shape.pose, t_c, rng.randint(5, 15), 0.02 * shape.size,
                                           rng=nrng)
                touches.append(st.to_json())
            req = {"touches": touches, "noise": {"phi": 1.5e-3, "pos": 0.03}}
        if rng.random() < 0.3:
            req["scene"] = rng.choice(["config/scenes/all.yaml", "config/scenes/conics.yaml", {"classes": [shape.cls]}])
        out.append(req)
    return out


def _hostile_values(rng: random.Random) -> list:
    deep = []
    for _ in range(40):
        deep = [deep]
    return [None, True, False, "x", "", [], {}, deep, -1, 0, 1e308, -1e308, 5e-324, 2 ** 53 + 1,
            _RAW.format("1" + "0" * 20), _RAW.format("9" * 400), _RAW.format("NaN"), _RAW.format("-Infinity"),
            _RAW.format("1e400"), "a" * 5000, [0] * 600, [1e200] * 3, {"a": 1}, "/dev/zero", "/", "../" * 50,
            "\u202e\ud7ff\U0001F600", ["circle"], [["circle"]], {"classes": [["circle"]]}, 1e200, -1e200,
            rng.uniform(-1e6, 1e6), [rng.random() for _ in range(7)]]


def json_paths(obj, max_items: int | None = None, prefix: tuple = ()):
    """Every path (tuple of keys and indices) into a decoded JSON value, the root first;
    ``max_items`` limits how many items of each list are entered."""
    yield prefix
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from json_paths(v, max_items, prefix + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj[:max_items]):
            yield from json_paths(v, max_items, prefix + (i,))


def replace_at(obj, path: tuple, value):
    """A copy of ``obj`` with the value at ``path`` replaced by ``value``."""
    if not path:
        return value
    obj = json.loads(json.dumps(obj))
    node = obj
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    return obj


def _encode(obj) -> bytes:
    text = json.dumps(obj)
    while '"\\u0000RAW' in text:
        a = text.index('"\\u0000RAW')
        b = text.index('\\u0000"', a + 10)
        text = text[:a] + text[a + 10:b] + text[b + 7:]
    return text.encode("utf-8", "surrogatepass")


def _issue_cases() -> list[tuple[str, bytes]]:
    good = exact_request("ellipse", {"a": 28.6, "b": 17.3}, [0.36, 1.86, 4.23], Pose(0.3, 120.0, 15.0), False)
    c = good["touches"][0]["contact"]
    t = good["touches"]
    slow = exact_request("ellipse", {"a": 28.6, "b": 17.3}, np.linspace(0.1, 6.0, 64), Pose(0.3, 120.0, 15.0), False)
    return [
        ("list as class", b'{"scene":{"classes":[["circle"]]},"touches":[]}'),
        ("10**20 in scene", _encode({"scene": {"classes": ["circle"], "object": {"class": "circle", "params": {
            "r": _RAW.format("1" + "0" * 20)}}}, "touches": t})),
        ("5000-char scene path", _encode({"scene": "a" * 5000, "touches": t})),
        ("/dev/zero scene", _encode({"scene": "/dev/zero", "touches": t})),
        ("100,000-sample touch", _encode({"touches": [{"phi": [0.001 * i for i in range(100000)],
                                                       "x": list(range(100000)), "y": [0] * 100000}] * 2})),
        ("100,000 contacts", _encode({"touches": [{"contact": dict(c, x=c["x"] + 1e-3 * i)} for i in range(100000)]})),
        ("invalid UTF-8", b'{"touches": [], "meta": "\xff\xfe"}'),
        ("400 digits", _encode({"touches": [{"contact": dict(c, x=_RAW.format("1" * 400))}] + t[1:]})),
        ("5000 digits", _encode({"touches": [{"contact": dict(c, x=_RAW.format("1" * 5000))}] + t[1:]})),
        ("kappa 1e200", _encode({"touches": [t[0], {"contact": dict(t[1]["contact"], kappa=1e200)}, t[2]]})),
        ("3 MiB line", b'{"touches": [' + b"0," * (3 * 2 ** 19) + b"0]}"),
        ("20000-deep", b"[" * 20000 + b"]" * 20000),
        ("64 contacts, timeout 10 ms", _encode({**slow, "options": {"timeout_s": 0.01}})),
    ]


def _damage(rng: random.Random, raw: bytes) -> bytes:
    b = bytearray(raw)
    kind = rng.randrange(4)
    if kind == 0:
        for _ in range(rng.randint(1, 5)):
            b[rng.randrange(len(b))] = rng.randrange(256)
    elif kind == 1:
        del b[rng.randrange(len(b)):]
    elif kind == 2:
        i = rng.randrange(len(b))
        b[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 20)))
    else:
        b = bytearray(rng.randrange(256) for _ in range(rng.randint(1, 200)))
    out = bytes(b).replace(b"\n", b" ")
    return out if out.strip() else b"{" + out  # a blank line is rightly not answered: not a probe


def hostile_lines(n: int, seed: int) -> list[tuple[str, bytes]]:
    rng = random.Random(seed)
    valid = _valid_requests(rng, 200)
    values = _hostile_values(rng)
    lines = list(_issue_cases())
    while len(lines) < n:
        base = rng.choice(valid)
        r = rng.random()
        if r < 0.05:
            lines.append(("valid", _encode(base)))
        elif r < 0.70:
            path = rng.choice(list(json_paths(base, 8)))
            lines.append(("value " + "/".join(map(str, path[:2])), _encode(replace_at(base, path, rng.choice(values)))))
        else:
            lines.append(("bytes", _damage(rng, _encode(base))))
    return lines[:max(n, len(lines))]


class _Memory(threading.Thread):
    """Peak RSS of the service and of any worker it forks, sampled every 20 ms."""

    def __init__(self, pid: int) -> None:
        super().__init__(daemon=True)
        self.pid, self.service_kb, self.worker_kb, self.stop = pid, 0, 0, threading.Event()

    @staticmethod
    def _rss_kb(pid: int) -> int:
        try:
            for line in Path(f"/proc/{pid}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
        except (OSError, ValueError):
            pass
        return 0

    def run(self) -> None:
        while not self.stop.wait(0.02):
            self.service_kb = max(self.service_kb, self._rss_kb(self.pid))
            try:
                kids = Path(f"/proc/{self.pid}/task/{self.pid}/children").read_text().split()
            except OSError:
                kids = []
            for k in kids:
                self.worker_kb = max(self.worker_kb, self._rss_kb(int(k)))


SERVICE_ROOT = ROOT  # --repo: the checkout whose service is fuzzed (to measure another version)


def _start(stderr) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(SERVICE_ROOT), "LC_ALL": "C.UTF-8", "PYTHONIOENCODING": "utf-8:strict"}
    return subprocess.Popen([sys.executable, "-m", "tools.cli", "recognize", "--stream", "-"], cwd=SERVICE_ROOT, env=env,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=stderr, bufsize=0)


def _answer(proc, t0: float, hang_s: float, buf: bytes) -> tuple[bytes | None, bytes, str]:
    """The next answer line, the rest of the buffer, and "" or "hang" / "died"."""
    while b"\n" not in buf:
        ready, _, _ = select.select([proc.stdout], [], [], max(0.0, hang_s - (time.perf_counter() - t0)))
        if not ready:
            return None, buf, "hang"
        chunk = os.read(proc.stdout.fileno(), 1 << 16)
        if not chunk:
            return None, buf, "died"
        buf += chunk
    answer, buf = buf.split(b"\n", 1)
    return answer, buf, ""


def run(n: int, seed: int, hang_s: float, progress) -> dict:
    lines = hostile_lines(n, seed)
    warm = _encode(_valid_requests(random.Random(seed), 1)[0]) + b"\n"
    stats = {"lines": len(lines), "recognized": 0, "errors": 0, "cut_off": 0, "crashes": 0, "hangs": 0,
             "bad_answers": 0, "latency": [], "worst": ("", 0.0), "crash_kinds": {}, "hang_kinds": {}}
    with tempfile.TemporaryFile() as errlog:

        def start():
            p = _start(errlog)
            p.stdin.write(warm)  # start-up (imports, first worker) is not a line's latency
            p.stdout.readline()
            return p

        proc = start()
        mem = _Memory(proc.pid)
        mem.start()
        buf = b""
        t_all = time.perf_counter()
        for i, (kind, raw) in enumerate(lines):
            t0 = time.perf_counter()
            try:
                proc.stdin.write(raw + b"\n")
                answer, buf, fault = _answer(proc, t0, hang_s, buf)
            except BrokenPipeError:
                answer, fault = None, "died"
            if fault:
                key = "hangs" if fault == "hang" else "crashes"
                stats[key] += 1
                kinds = stats["hang_kinds" if fault == "hang" else "crash_kinds"]
                kinds[kind] = kinds.get(kind, 0) + 1
                stats.setdefault("fault_lines", []).append(i)
                proc.kill()
                proc.wait()
                proc, buf = start(), b""
                mem.pid = proc.pid
                continue
            dt = time.perf_counter() - t0
            stats["latency"].append(dt)
            if dt > stats["worst"][1]:
                stats["worst"] = (kind, dt)
            try:
                obj = json.loads(answer)
            except ValueError:
                stats["bad_answers"] += 1
                continue
            if isinstance(obj, dict) and "error" in obj:
                stats["cut_off" if "cut off" in obj["error"] else "errors"] += 1
            elif isinstance(obj, dict) and "class" in obj:
                stats["recognized"] += 1
            else:
                stats["bad_answers"] += 1
            if progress and (i + 1) % 500 == 0:
                progress(f"{i + 1}/{len(lines)} lines, {time.perf_counter() - t_all:.0f} s")
        proc.stdin.close()
        rc = proc.wait(timeout=60)
        mem.stop.set()
        mem.join()
        errlog.seek(0)
        err = errlog.read().decode("utf-8", "replace")
    if rc != 0:
        stats["crashes"] += 1
    stats.update(wall_s=time.perf_counter() - t_all, service_mb=mem.service_kb / 1024, worker_mb=mem.worker_kb / 1024,
                 tracebacks=err.count("Traceback"), stderr=err.strip().splitlines()[-3:])
    return stats


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--hang-s", type=float, default=30.0, help="no answer within this long is a hang (default 30)")
    ap.add_argument("--repo", type=Path, default=ROOT, help="checkout whose service to fuzz (default: this one)")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    global SERVICE_ROOT
    SERVICE_ROOT = args.repo.resolve()
    s = run(args.lines, args.seed, args.hang_s, None if args.quiet else lambda m: print(f"  {m}", file=sys.stderr))
    lat = np.array(s["latency"]) * 1e3
    print(f"lines sent            {s['lines']} (seed {args.seed}) to one tactile recognize --stream")
    print(f"answers               {len(lat)}: {s['recognized']} recognitions, {s['errors']} errors, "
          f"{s['cut_off']} cut off by the timeout, {s['bad_answers']} not JSON / neither")
    print(f"crashes               {s['crashes']} (tracebacks on stderr: {s['tracebacks']})"
          + (f": {s['crash_kinds']}" if s["crash_kinds"] else ""))
    print(f"hangs (> {args.hang_s:g} s)       {s['hangs']}" + (f": {s['hang_kinds']}" if s["hang_kinds"] else ""))
    print(f"peak memory (RSS)     service {s['service_mb']:.0f} MB, worker {s['worker_mb']:.0f} MB")
    print(f"latency per line      median {np.median(lat):.2f} ms, p99 {np.percentile(lat, 99):.1f} ms, "
          f"worst {lat.max():.0f} ms ({s['worst'][0]})")
    print(f"wall time             {s['wall_s']:.0f} s")
    if s.get("fault_lines"):
        print(f"lines that crashed or hung (0-based): {s['fault_lines'][:20]}")
    if s["stderr"]:
        print("stderr tail:", *s["stderr"], sep="\n  ")
    return 0 if s["crashes"] == s["hangs"] == s["bad_answers"] == s["tracebacks"] == 0 else 1


if __name__ == "__main__":
    raise SystemExit(main())
