"""Plot of one exploration: pad lines in contact, touch samples, recognized (and true) curve.

A finite true object (docs/formats.md, scene) is drawn whole: its solid shaded, the curved part over
its extent as a dashed line, the straight closing segments dotted, the corners marked.
Written with matplotlib's Agg backend (no screen needed) to a PNG file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import numpy as np

from recognizer.curves import CURVES, Pose
from recognizer.touches import touch_points
from tactile_common.files import atomic_path

_FINGER_COLORS = ("tab:blue", "tab:orange", "tab:purple", "tab:brown")


def curve_points(cls: str, params: dict, pose: Pose, t_contacts: Sequence[float], reach_mm: float):
    """Hand-frame points of a curve: the whole of a closed curve, else ``reach_mm`` of arc
    either side of the contacts' parameters."""
    curve = CURVES[cls](params)
    if curve.t_period is not None:
        t = np.linspace(curve.t_period[0], curve.t_period[1], 721)
    else:
        ts = np.asarray(t_contacts, dtype=float) if len(t_contacts) else np.zeros(1)
        lo = float(curve.t_at_arc_length(float(ts.min()), -reach_mm))
        hi = float(curve.t_at_arc_length(float(ts.max()), reach_mm))
        t = np.linspace(lo, hi, 721)
    return pose.apply(*curve.point(t))


def _draw_finite(ax, truth) -> None:
    """The whole finite object: solid, curved part, closing segments, corners."""
    x, y = truth.outline()
    ax.fill(x, y, color="0.85", zorder=0, label=f"true object ({truth.cls} over t in "
                                                 f"[{truth.extent[0]:g}, {truth.extent[1]:g}])")
    n = len(x) - len(truth.corners()) + 1  # the curve's samples come first
    ax.plot(x[:n], y[:n], color="0.3", lw=1.0, ls="--", label=f"true {truth.cls}")
    ax.plot(x[n - 1:], y[n - 1:], color="0.3", lw=1.0, ls=":", label="closing segments")
    cx, cy = truth.pose.apply(*truth.corners().T)
    ax.plot(cx, cy, "s", color="0.3", ms=3, label="corners")


def plot_exploration(path: str | Path, *, touches: Sequence[dict[str, Any]], pad_segments: Sequence[dict[str, Any]],
                     recognition: dict[str, Any] | None, truth: Any | None, workspace: tuple[tuple[float, float], float],
                     title: str = "") -> Path:
    """Write the plot. ``touches``: samples or contact touches (docs/formats.md) (with ``finger``);
    ``pad_segments``: ``{"finger", "p0": (x, y), "p1": (x, y)}`` for each in-contact pad;
    ``recognition``: the answer mapping (docs/formats.md); ``truth``: a ``SceneObject`` or None."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (cx, cy), radius = workspace
    reach = 2.0 * radius
    fingers = sorted({t.get("finger", "") for t in touches} | {p["finger"] for p in pad_segments})
    color = {f: _FINGER_COLORS[i % len(_FINGER_COLORS)] for i, f in enumerate(fingers)}
    fig, ax = plt.subplots(figsize=(7, 7))
    ax.add_patch(plt.Circle((cx, cy), radius, fill=False, ls=":", color="0.6", label="workspace"))
    for seg in pad_segments:
        (x0, y0), (x1, y1) = seg["p0"], seg["p1"]
        ax.plot([x0, x1], [y0, y1], color=color[seg["finger"]], lw=0.6, alpha=0.35)
    for k, touch in enumerate(touches):
        f = touch.get("finger", "")
        points = touch_points(touch)
        ax.plot(points["x"], points["y"], ".", ms=4, color=color[f], label=f"{f} touches" if k == [
            t.get("finger", "") for t in touches].index(f) else None)
    if truth is not None and getattr(truth, "extent", None) is not None:
        _draw_finite(ax, truth)
    elif truth is not None:
        x, y = curve_points(truth.cls, truth.params, truth.pose, [], reach)
        ax.plot(x, y, color="0.3", lw=1.0, ls="--", label=f"true {truth.cls}")
    if recognition is not None and recognition.get("class") not in (None, "unclassified") and recognition.get("pose"):
        pose = Pose(**recognition["pose"])
        t_contacts = [c["t"] for c in recognition.get("contacts", [])]
        x, y = curve_points(recognition["class"], recognition["params"], pose, t_contacts, reach)
        params = ", ".join(f"{k}={v:.3g}" for k, v in recognition["params"].items())
        ax.plot(x, y, color="tab:red", lw=1.4, label=f"recognized {recognition['class']} ({params})")
        ax.plot([c["x"] for c in recognition["contacts"]], [c["y"] for c in recognition["contacts"]], "x",
                color="tab:red", ms=7, label="recovered contacts")
    elif recognition is not None:
        ax.text(0.02, 0.02, f"unclassified: {recognition.get('reason')}", transform=ax.transAxes, fontsize=8)
    ax.set_xlim(cx - 1.4 * radius, cx + 1.4 * radius)
    ax.set_ylim(cy - 1.4 * radius, cy + 1.4 * radius)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm, hand frame)")
    ax.set_ylabel("y (mm)")
    ax.set_title(title or "tactile exploration")
    ax.legend(loc="upper right", fontsize=7)
    ax.grid(alpha=0.3)
    try:
        with atomic_path(path, "--plot") as tmp:
            fig.savefig(tmp, dpi=120, bbox_inches="tight", format=Path(path).suffix.lstrip(".") or "png")
    finally:
        plt.close(fig)
    return Path(path)
