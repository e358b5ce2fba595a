"""The one exception the command line prints on one line (:mod:`locustjump.errors`)
and a behaviour's options (:mod:`locustjump.tasks.options`): how a message
names its settings in Python and on the command line, and what an option may
declare and hold."""

import dataclasses

import pytest

from helpers import exactly
from locustjump.errors import UserError, setting_ref
from locustjump.ranges import Range, SettingTypeError, SettingValueError
from locustjump.tasks.options import (
    MAX_SCORE_SUBSTEPS,
    OPTION_HELP,
    CommonOptions,
    option,
    option_fields,
)


def test_a_setting_is_marked_in_a_message():
    assert setting_ref("out") == "⟦out⟧"
    assert setting_ref("force", True) == "⟦force=True⟧"
    assert setting_ref("force", False) == "⟦force=False⟧"
    assert setting_ref("a_b2", 0) == "⟦a_b2=False⟧"  # on or off, as a bool
    for bad in ("Out", "2a", "a-b", "", "a b", "out\n"):
        with pytest.raises(ValueError, match=exactly(
            f"setting names are lower-case identifiers, got {bad!r}"
        )):  # fmt: skip
            setting_ref(bad)


def _spell(name, value):
    flag = "--" + name.replace("_", "-")
    return flag if value is None else (flag if value else f"--no-{name}")


def test_a_message_names_its_settings_in_python_and_on_the_command_line():
    e = UserError(
        f"{setting_ref('out_dir')} x: exists (use {setting_ref('force', True)} "
        f"or {setting_ref('resume', False)})"
    )
    assert str(e) == "out_dir x: exists (use force=True or resume=False)"
    assert e.render() == str(e)
    assert e.render(_spell) == "--out-dir x: exists (use --force or --no-resume)"
    assert e.settings == ("out_dir", "force", "resume")
    assert e.setting == "out_dir"
    assert e.message.startswith("⟦out_dir⟧ x: ")  # still marked, to wrap
    seen = []
    UserError(f"{setting_ref('a', True)} {setting_ref('b')}").render(
        lambda n, v: seen.append((n, v)) or ""
    )
    assert seen == [("a", True), ("b", None)]


def test_a_message_without_settings():
    plain = UserError("nothing named ⟦Not⟧ ⟦x=maybe")
    assert str(plain) == "nothing named ⟦Not⟧ ⟦x=maybe"
    assert plain.settings == () and plain.setting is None
    assert UserError().message == "" and str(UserError()) == ""
    assert UserError().settings == () and UserError().setting is None
    assert str(UserError(3)) == "3"


def _options():
    """An ``Options`` class, declared when a test runs (not at import: the
    mutation tool's mutant is live only within a test)."""

    @dataclasses.dataclass(frozen=True)
    class Options:
        steps: int = option(5, "how many", "N", Range(1, 9, integer=True))
        cells: tuple[int, ...] = option((1, 2), "which", "I,J", Range(0, integer=True))
        name: str = option("a", "what", "NAME")
        share: float = option(0.5, "how much", "X")
        hidden: int = 3

    return Options


def test_an_option_declares_its_help_metavar_and_range():
    _Options = _options()
    fields = {f.name: f for f in option_fields(_Options)}
    assert list(fields) == ["steps", "cells", "name", "share"]  # not hidden
    assert dict(fields["steps"].metadata) == {
        OPTION_HELP: "how many", "metavar": "N", "range": Range(1, 9, integer=True)
    }  # fmt: skip
    assert dict(fields["cells"].metadata) == {
        OPTION_HELP: "which", "metavar": "I,J", "each": Range(0, integer=True)
    }  # fmt: skip
    assert dict(fields["name"].metadata) == {OPTION_HELP: "what", "metavar": "NAME"}
    assert _Options() == _Options(5, (1, 2), "a", 0.5, 3)
    assert option((), "none", "S").default == ()  # an empty tuple: of ints
    for default in (0, -2.5, "", (3, -1)):
        assert option(default, "h", "M").default == default


@pytest.mark.parametrize("default", [True, None, [1], (1, 2.0), (True,), {"a": 1}])
def test_an_options_default_is_a_number_a_text_or_integers(default):
    with pytest.raises(TypeError, match=exactly(
        "an option's default is an int, a float, a str or a tuple of ints, "
        f"not {default!r}"
    )):  # fmt: skip
        option(default, "h", "M")


def test_common_options_hold_distinct_substeps_in_range():
    assert CommonOptions().score_substeps == ()
    assert CommonOptions([6, 1]).score_substeps == (6, 1)
    assert CommonOptions((MAX_SCORE_SUBSTEPS,)).score_substeps == (48,)
    what = f"distinct integers each in [1, {MAX_SCORE_SUBSTEPS}]"
    for given, kind, shown in (
        ((0,), SettingValueError, "[0]"),
        ([49, 2], SettingValueError, "[49, 2]"),
        ((3, 3), SettingValueError, "[3, 3]"),
        ((1.5,), SettingTypeError, "[1.5]"),
        ((True,), SettingTypeError, "[True]"),
        ("12", SettingTypeError, "'12'"),
        (b"1", SettingTypeError, "b'1'"),
        (3, SettingTypeError, "3"),
        ({1: 2}, SettingTypeError, "{1: 2}"),
    ):
        with pytest.raises(kind) as e:
            CommonOptions(given)
        assert str(e.value) == f"score_substeps must be {what}, got {shown}", given
        assert type(e.value) is kind
