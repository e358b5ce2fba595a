"""Resource checks made before anything is allocated or written: a command
that cannot fit in memory is refused with the estimate and the limit."""

from __future__ import annotations

import os
from typing import Any

from locustjump.errors import UserError
from locustjump.ranges import SettingValueError

#: the share of the memory available now that one command may plan to use
MEMORY_SHARE = 0.8


def available_bytes() -> int:
    """Memory available to a new allocation now (``MemAvailable`` on Linux)."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 1 << 62


def gib(n: float) -> str:
    return f"{n / 2**30:.3g} GiB"


def require_memory(
    nbytes: float, what: str, setting: tuple[str, Any] | None = None
) -> None:
    """``UserError`` naming ``what``, its estimate and the limit, if ``nbytes``
    exceeds :data:`MEMORY_SHARE` of the available memory; with ``setting``
    (name, value), the setting that asks for that much is named: a
    :class:`~locustjump.ranges.SettingValueError`."""
    limit = MEMORY_SHARE * available_bytes()
    if nbytes > limit:
        why = (
            f"{what} needs about {gib(nbytes)} of memory; the limit is {gib(limit)} "
            f"({MEMORY_SHARE:.0%} of the {gib(limit / MEMORY_SHARE)} available)"
        )
        if setting is not None:
            raise SettingValueError(setting[0], f"smaller: {why}", setting[1])
        raise UserError(why)
