"""Which class is a limit of which (docs/recognition.md#nested-classes): the one definition
of the relation the recognizer's model choice (recognizer.classify), its nested starts
(recognizer.nested) and the exploration's stopping rule (tactile_jaw.decide) use.
"""

from __future__ import annotations

__all__ = ["LIMIT_OF"]

#: the classes each class is a limit of (docs/recognition.md#nested-classes): the richer class
#: fits any touches of the limit at least as well, so its χ² is no evidence against it. A
#: line of every curved class, a circle of the ellipse, a parabola of the ellipse, the
#: hyperbola (a → ∞) and both cubic families (a hump far from the cusp or inflection)
LIMIT_OF = {"line": frozenset({"circle", "ellipse", "parabola", "hyperbola", "cubical_parabola",
                               "semicubical_parabola"}),
            "circle": frozenset({"ellipse"}),
            "parabola": frozenset({"ellipse", "hyperbola", "cubical_parabola", "semicubical_parabola"})}
