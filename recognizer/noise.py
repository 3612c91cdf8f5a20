"""The measurement noise a request or scene states (docs/formats.md): one definition,
read by the touches' and the scenes' parsers alike."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from recognizer.limits import MIN_NOISE
from tactile_common.errors import InputError, check_keys
from tactile_common.inputs import finite_number

__all__ = ["NoiseModel", "parse_noise"]


@dataclass(frozen=True)
class NoiseModel:
    """Measurement noise: standard deviation of a tangent angle (rad) and of a position (mm);
    optionally ``pos_along``, the deviation of a sample's position along the boundary's
    tangent when it differs from across it (``pos``): a flat pad fixes the tangent line
    well but the contact point along it only from neighbouring readings."""

    phi: float = 0.0
    pos: float = 0.0
    pos_along: float | None = None

    @property
    def along(self) -> float:
        """σ of a position along the tangent (``pos_along``, else ``pos``)."""
        return self.pos if self.pos_along is None else self.pos_along

    def to_json(self) -> dict:
        out = {"phi": self.phi, "pos": self.pos}
        if self.pos_along is not None:
            out["pos_along"] = self.pos_along
        return out


def parse_noise(raw, where: str = "noise") -> NoiseModel:
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping {{phi: rad, pos: mm, pos_along: mm (optional)}}")
    check_keys(raw, ("phi", "pos", "pos_along"), where)
    vals = {k: finite_number(raw.get(k, 0.0), f"{where}.{k}") for k in ("phi", "pos")}
    if raw.get("pos_along") is not None:
        vals["pos_along"] = finite_number(raw["pos_along"], f"{where}.pos_along")
    for k, v in vals.items():
        if v < 0:
            raise InputError(f"{where}.{k}: must be >= 0, got {v}")
        if 0 < v < MIN_NOISE:
            raise InputError(f"{where}.{k}: {v:.3g} is below {MIN_NOISE:g} (mm, rad): no instrument resolves "
                             f"errors that small; write 0 for exact data")
    return NoiseModel(**vals)
