"""Where a command writes, as the user named it: checked, created and locked.

A command that writes a directory (``rules``, ``replay``) holds it through
:func:`output_dir`, one that writes a file (``model``, ``render``,
``compare``'s figure) through :func:`output_file`: both check the location
first (creating nothing), then take the write lock (:mod:`.lock`) of the
directory written into and check again under it (another process may have
been first); a directory the command made is removed again if the command
fails or is interrupted, so nothing half-made is left.
"""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Iterator
from pathlib import Path

from locustjump.errors import UserError, setting_ref
from locustjump.rundir import layout
from locustjump.rundir.lock import locked
from locustjump.rundir.migrations import FROZEN_BEFORE

#: the files that make a directory what it is (a run, a reproduction, a
#: rule-based run): never a command's output, even with ``--force``
RECORDS = (
    layout.CONFIG, layout.METRICS, layout.CHECKPOINT, layout.BEST, layout.FROZEN,
    FROZEN_BEFORE, layout.STOP, layout.MARKER, layout.SEEDS_MARKER,
    layout.RULES_SUMMARY, layout.TRAJECTORY_CSV,
)  # fmt: skip


def _holder(d: Path) -> str | None:
    """What directory ``d`` holds, if it is one whose :data:`RECORDS` these are."""
    for test, what in ((layout.is_run, "run"),
                       (layout.is_reproduction, "reproduction"),
                       (layout.is_multiseed, "reproduction"),
                       (layout.is_rules_run, "rule-based run")):  # fmt: skip
        if test(d):
            return what
    return None


def _exists(out: Path, setting: str) -> bool:
    """Whether ``out`` exists; ``UserError`` for a path that cannot be
    looked at (a symbolic-link loop, a broken link, a file on the way)."""
    try:
        os.stat(out)
    except FileNotFoundError:
        if os.path.lexists(out):
            raise UserError(
                f"{setting_ref(setting)} {out}: a broken symbolic link"
            ) from None
        return False
    except OSError as e:
        raise UserError(f"{setting_ref(setting)} {out}: {e.strerror or e}") from None
    return True


def check_out_dir(
    path: str | os.PathLike[str], *, force: bool = False, setting: str = "out"
) -> Path:
    """Refuse (``UserError``) an existing non-empty ``path`` unless ``force``;
    create nothing."""
    out = Path(path)
    if not _exists(out, setting):
        _exists(out.parent, setting)  # a file or a loop on the way is named
        return out
    if not out.is_dir():
        raise UserError(f"{setting_ref(setting)} {out}: exists and is not a directory")
    try:
        full = any(out.iterdir())
    except OSError as e:
        raise UserError(f"{setting_ref(setting)} {out}: {e.strerror or e}") from None
    if full and not force:
        raise UserError(
            f"{setting_ref(setting)} {out}: directory exists and is not empty (use "
            f"{setting_ref('force', True)} to write into it)"
        )
    return out


def prepare_out_file(
    path: str | os.PathLike[str], *, force: bool = False, setting: str = "out"
) -> Path:
    """Check that ``path`` (the setting ``setting``) can be written without
    overwriting, unless ``force``."""
    out = Path(path)
    if _exists(out, setting):
        if out.is_dir():
            raise UserError(
                f"{setting_ref(setting)} {out}: is a directory, expected a file"
            )
        if not force:
            raise UserError(
                f"{setting_ref(setting)} {out}: file exists (use "
                f"{setting_ref('force', True)} to overwrite)"
            )
    if not _exists(out.parent, setting) or not out.parent.is_dir():
        raise UserError(
            f"{setting_ref(setting)} {out}: directory {out.parent} does not exist"
        )
    holder = _holder(out.parent) if out.name in RECORDS else None
    if holder is not None:
        raise UserError(
            f"{setting_ref(setting)} {out}: one of the files of the {holder} in "
            f"{out.parent} (never overwritten, even with "
            f"{setting_ref('force', True)}); choose another file"
        )
    return out


def make_dir(out: Path, setting: str | None = "out") -> Path | None:
    """Create directory ``out`` (the setting ``setting``, if the user named
    it) and its missing parents; the topmost one made (``None`` if it
    existed), for :func:`remove_made`."""
    top = None
    p = out
    while not os.path.lexists(p) and p != p.parent:
        top, p = p, p.parent
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        where = f"{setting_ref(setting)} {out}" if setting else f"{out}"
        raise UserError(f"{where}: cannot be created ({e.strerror})") from None
    return top


def remove_made(top: Path | None) -> None:
    """Remove what :func:`make_dir` made (and everything written into it)."""
    if top is not None:
        shutil.rmtree(top, ignore_errors=True)


@contextlib.contextmanager
def made_dir(out: Path, setting: str | None = None) -> Iterator[Path]:
    """Directory ``out``, created with its missing parents if need be
    (:func:`make_dir`); what was created here is removed again if the body
    fails (a full disk, Ctrl-C), with what was written into it."""
    top = make_dir(Path(out), setting)
    try:
        yield Path(out)
    except BaseException:
        remove_made(top)
        raise


@contextlib.contextmanager
def deriving(run: Path) -> Iterator[Path]:
    """Where the files derived from ``run`` go (:func:`~.layout.derived_dir`),
    held by this process alone for the body: the run itself, locked, or a
    shipped run's directory under ``runs/shipped/``, made if need be and
    locked (if this call made it and the body fails, it is removed again,
    before the lock is let go), so that two commands never write one derived
    file at once."""
    dest = layout.derived_dir(Path(run))
    if dest == Path(run):
        with locked(dest):
            yield dest
        return
    # made here or not, it is removed only by the process that holds it, and
    # only itself: another command may have made it (or its parents' other
    # directories) at the same moment and hold it now
    made = make_dir(dest, None) is not None
    with locked(dest):
        try:
            yield dest
        except BaseException:
            if made:
                shutil.rmtree(dest, ignore_errors=True)
            raise


@contextlib.contextmanager
def output_dir(
    path: str | os.PathLike[str], *, force: bool = False, setting: str = "out"
) -> Iterator[Path]:
    """The directory ``path`` to write into, created and locked; refused if
    it is not empty (unless ``force``) before and again once locked; removed
    again if it was made here and the body fails."""
    out = check_out_dir(path, force=force, setting=setting)
    top = make_dir(out, setting)
    with locked(out):
        # another process may have been first (then what is there is its own)
        check_out_dir(out, force=force, setting=setting)
        try:
            yield out
        except BaseException:
            remove_made(top)
            raise


@contextlib.contextmanager
def output_file(
    path: str | os.PathLike[str], *, force: bool = False, setting: str = "out"
) -> Iterator[Path]:
    """The file ``path`` to write, checked (:func:`prepare_out_file`) before
    and again under the lock of its directory, held while the body runs."""
    out = prepare_out_file(path, force=force, setting=setting)
    with locked(out.parent):
        yield prepare_out_file(out, force=force, setting=setting)
