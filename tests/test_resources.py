"""``sim.resources``: the memory a command may plan to use, read from the
system, and the one-line refusal naming the estimate and the limit."""

import io

import pytest

from locustjump.errors import UserError
from locustjump.ranges import SettingValueError
from locustjump.sim import resources

GIB = 2**30


def _meminfo(monkeypatch, text=None, error=None):
    def fake_open(path, *a, **k):
        assert path == "/proc/meminfo"
        if error is not None:
            raise error
        return io.StringIO(text)

    monkeypatch.setattr(resources, "open", fake_open, raising=False)
    pages = {"SC_AVPHYS_PAGES": 3, "SC_PAGE_SIZE": 4096}
    monkeypatch.setattr(resources.os, "sysconf", pages.__getitem__)


def test_available_memory_is_memavailable(monkeypatch):
    _meminfo(monkeypatch, "MemTotal:  9999 kB\nMemFree: 5 kB\nMemAvailable:  2048 kB\n")
    assert resources.available_bytes() == 2048 * 1024


@pytest.mark.parametrize(
    ("text", "error"),
    [("MemTotal:  9999 kB\n", None),  # no such line
     ("MemAvailable:  lots kB\n", None),  # not a number
     (None, OSError("no /proc"))],
)  # fmt: skip
def test_otherwise_the_available_pages(monkeypatch, text, error):
    _meminfo(monkeypatch, text, error)
    assert resources.available_bytes() == 3 * 4096


def test_the_system_s_own_numbers_are_read():
    assert 0 < resources.available_bytes() < 1 << 62


def test_gib():
    assert resources.gib(1.5 * GIB) == "1.5 GiB"
    assert resources.gib(123456789012) == "115 GiB"


def test_a_plan_within_the_limit_passes_and_beyond_it_is_refused(monkeypatch):
    monkeypatch.setattr(resources, "available_bytes", lambda: 10 * GIB)
    assert resources.MEMORY_SHARE == 0.8
    resources.require_memory(8 * GIB, "the population")  # at the limit
    with pytest.raises(UserError) as e:
        resources.require_memory(9 * GIB, "the population")
    assert type(e.value) is UserError
    assert str(e.value) == (
        "the population needs about 9 GiB of memory; the limit is 8 GiB "
        "(80% of the 10 GiB available)"
    )
    with pytest.raises(SettingValueError) as e:
        resources.require_memory(9 * GIB, "the population", ("population", 5000))
    assert e.value.name == "population" and e.value.value == 5000
    assert e.value.expected == (
        "smaller: the population needs about 9 GiB of memory; the limit is "
        "8 GiB (80% of the 10 GiB available)"
    )


@pytest.mark.parametrize("error", [ValueError, OSError, AttributeError])
def test_with_neither_there_is_no_limit(monkeypatch, error):
    _meminfo(monkeypatch, error=OSError("no /proc"))

    def fails(name):
        raise error(name)

    monkeypatch.setattr(resources.os, "sysconf", fails)
    assert resources.available_bytes() == 1 << 62  # 4 EiB: no command is refused
