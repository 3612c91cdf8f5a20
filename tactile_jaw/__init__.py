"""The layer above the recognizer and the jaw driver: servo ticks → pad lines → touches →
recognition (:mod:`tactile_jaw.pipeline`), the exploration's settings
(:mod:`tactile_jaw.settings`), probe planning and the object model
(:mod:`tactile_jaw.plan`), the stopping rule (:mod:`tactile_jaw.decide`) and the
exploration loop (:mod:`tactile_jaw.explore`). Used by every command of ``tools/``."""
