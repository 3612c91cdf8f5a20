"""Errors a person can act on.

Every user-facing failure (a bad touches file, scene, jaw config or option) raises a
subclass of :class:`InputError` whose message is one line naming the file, key and the
allowed range. The ``tactile`` command turns it into exit status 2 with that line on
stderr and no traceback.
"""


class InputError(ValueError):
    """Bad input: the message is one line a person can act on."""


class DeviceFault(RuntimeError):
    """A fault at run time that no input change fixes now (bus timeout, CRC error,
    servo hardware error, unplugged adapter). The ``tactile`` command prints its one-line
    message and exits with status 1; torque is already off when it propagates."""


def check_keys(raw, allowed, where: str, hint: str | None = None) -> None:
    """Refuse a mapping's keys outside ``allowed`` (an ordered sequence) with one line naming
    them and what is allowed (``hint`` replaces the list of allowed keys)."""
    extra = sorted(map(str, set(raw) - set(allowed)))
    if extra:
        hint = hint or f"allowed: {', '.join(map(str, allowed)) or 'none'}"
        raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; {hint}")
