"""The README and the documentation pages as the tests read them: their
fenced blocks, the commands in them and in the prose, their links.

A fenced ``sh`` block is run as written; an HTML comment on the line before
its fence says otherwise, with the reason::

    <!-- commands: slow (three trainings, about 10 minutes) -->
    <!-- commands: parse (hours: the paper's budget) -->
    <!-- commands: slow, prints the table below (three trainings) -->

``slow`` blocks run under ``pytest -m slow``; ``parse`` blocks (hours of
training, a cluster, installing into the environment or the system) are only
parsed: every ``locustjump`` line must be one the command line accepts. A
block that ``prints the table below`` must print every row of the Markdown
table that follows it: the page's numbers are that command's output.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import locustjump

ROOT = Path(locustjump.__file__).resolve().parents[2]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
#: every page a user reads: the README first, then the documentation
PAGES = (README, *sorted(DOCS.rglob("*.md")))
MODES = ("run", "slow", "parse")
_MARK = re.compile(
    r"^<!-- commands: (run|slow|parse)(, prints the table below)?(?: \((.+)\))? -->$"
)


@dataclass(frozen=True)
class Block:
    page: Path
    line: int  # of the opening fence, 1-based
    heading: str
    lang: str
    code: str
    mode: str = "run"
    reason: str = ""
    #: the rows of the table the block prints (``prints the table below``)
    table: tuple[str, ...] = ()

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line} ({self.heading})"


def blocks(page: Path) -> list[Block]:
    """Every fenced block of ``page``, in order."""
    found, heading = [], ""
    lines = page.read_text().splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("#") and not line.startswith("#!"):
            heading = line.lstrip("#").strip()
        elif line.startswith("```"):
            end = lines.index("```", i + 1)
            mark = _MARK.match(lines[i - 1]) if i else None
            mode, prints, reason = mark.groups() if mark else ("run", None, "")
            code = "\n".join(lines[i + 1 : end])
            table = _table_after(lines, end + 1) if prints else ()
            found.append(Block(page, i + 1, heading, line[3:].strip(), code, mode,
                               reason or "", table))  # fmt: skip
            i = end
        i += 1
    return found


def _table_after(lines: list[str], i: int) -> tuple[str, ...]:
    """The rows (header and separator aside) of the first table from line i."""
    while i < len(lines) and not lines[i].startswith("|"):
        i += 1
    rows = []
    while i < len(lines) and lines[i].startswith("|"):
        rows.append(lines[i])
        i += 1
    return tuple(rows[2:])


def all_blocks(lang: str) -> list[Block]:
    return [b for page in PAGES for b in blocks(page) if b.lang == lang]


def command_lines(code: str) -> list[list[str]]:
    """The argv (after ``locustjump``) of each ``locustjump`` command of a
    shell block: continuation lines joined, comments dropped, a for loop's
    variable taken as 0, brace lists as their first item."""
    code = re.sub(r"\\\n\s*", " ", code)
    found = []
    for line in code.splitlines():
        line = re.sub(r"(^|\s)#.*$", "", line).replace("$s", "0")
        line = re.sub(r"\{([^,{}]*),[^{}]*\}", r"\1", line)
        for part in re.split(r";\s*(?:do|done)?\s*|&&", line):
            words = shlex.split(part.strip()) if part.strip() else []
            if words and words[0] in ("locustjump", ".venv/bin/locustjump"):
                found.append(words[1:])
    return found


#: a word a reader replaces: DIR, OUT, FILE.toml, NAME, <stage>, S, ...
_PLACEHOLDER = re.compile(r"\b[A-Z][A-Z_]*\b|<[^>]+>|\.\.\.|…")


def inline_commands(page: Path) -> list[list[str]]:
    """The argv of each concrete ``locustjump ...`` code span of the prose
    (spans with a placeholder or an option list, like ``--budget
    quick|demo``, are a synopsis, and a bare command name a mention)."""
    text = re.sub(r"(?ms)^```.*?^```", "", page.read_text())
    found = []
    for span in re.findall(r"`(?:\.venv/bin/)?locustjump ([^`]+)`", text):
        span = " ".join(span.split())
        if _PLACEHOLDER.search(span) or any(c in span for c in "[]|{}*"):
            continue
        if len(span.split()) > 1:  # `locustjump reproduce` names a command
            found.append(shlex.split(span))
    return found


def out_dirs(argv: list[str]) -> list[str]:
    """The ``--out`` of a command line, unless it continues or overwrites
    (``--resume``, ``--force``)."""
    if "--resume" in argv or "--force" in argv:
        return []
    return [argv[i + 1] for i, a in enumerate(argv[:-1]) if a == "--out"]


def links(page: Path) -> list[tuple[str, str]]:
    """(label, target) of every Markdown link and image of ``page``'s prose."""
    text = re.sub(r"(?ms)^```.*?^```", "", page.read_text())
    text = re.sub(r"`[^`]*`", "", text)
    return re.findall(r"!?\[([^\]]*)\]\(([^)\s]+)\)", text)


def headings(page: Path) -> list[str]:
    text = re.sub(r"(?ms)^```.*?^```", "", page.read_text())
    return [h.strip() for h in re.findall(r"(?m)^#{1,6} (.+)$", text)]
