"""Which arms a study compares, and its comparisons grouped into families.

Each scored arm is compared with the study's reference, or, without one,
every pair of scored arms. The comparisons of a table (pairs x physics
resolutions, and on debris the height term alone) are one family for the
Holm–Bonferroni correction, unless the study file declares some primary
(``[primary]``, declared before the runs' results were known): those are
then a family of their own and the rest a second, secondary family. Where
none of the declared ones is in a table, its comparisons are one family
again, and the table says so.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from locustjump.present.stats import Comparison, compare_samples, family_table
from locustjump.present.study_figure import resolution_label
from locustjump.runs.studyarms import Arm
from locustjump.runs.studyfile import Study


def pairs(study: Study) -> list[tuple[Arm, Arm]]:
    """The pairs compared: each arm with the reference, or every pair."""
    arms = study.scored
    if study.reference:
        ref = study.arms[study.reference]
        return [(a, ref) for a in arms if a is not ref]
    return [(a, b) for i, a in enumerate(arms) for b in arms[i + 1 :]]


def compared(study: Study, samples: dict[str, np.ndarray]) -> list[Comparison]:
    """The study's pairs (:func:`pairs`) compared on ``samples`` (per arm)."""
    return [
        compare_samples(samples[x.name], samples[y.name],
                        names=(x.label, y.label), margin=study.margin)
        for x, y in pairs(study)
    ]  # fmt: skip


def families(study: Study, out: dict[str, Any]) -> list[str]:
    """The table's comparisons as families (Holm–Bonferroni within each):
    all as one, or, where the study declares primary ones, those and the
    rest (secondary) apart. ``out`` is the table's JSON so far (its ``pairs``
    and ``pairs_height_term``); sets its ``holm``, and its ``primary`` to what
    the study file declares; returns Markdown lines."""
    tagged: list[tuple[str, dict[str, Any], bool]] = []  # (scores, row, primary?)
    for key, score, tag in (
        ("pairs", "full", ""),
        ("pairs_height_term", "height-term", ", height term"),
    ):
        for sub in study.evaluation.substeps:
            rows = out.get(key, {}).get(str(sub))
            if not rows:  # not compared there (an arm with fewer than 2 runs)
                continue
            for (x, y), c in zip(pairs(study), rows, strict=True):
                declared = study.primary is not None and study.primary.names(
                    x.name, y.name, sub, score
                )
                where = f"{resolution_label(str(sub))}{tag}"
                tagged.append((where, c, declared))
    if study.primary is None:
        if len(tagged) < 2:
            return []
        text, out["holm"] = family_table([(w, c) for w, c, _ in tagged])
        return ["", text]
    d = study.primary  # what was declared, beside what it gave
    out["primary"] = {"pairs": [list(x) for x in d.pairs],
                      "substeps": list(d.substeps), "score": d.score}  # fmt: skip
    first = [(w, c) for w, c, p in tagged if p and c["p"] is not None]
    rest = [(w, c) for w, c, p in tagged if not p]
    if not first:
        lines = ["", "No comparison declared primary (the study file's "
                 "[primary]) is in this table: none is tested as such."]  # fmt: skip
        if len(rest) > 1:
            text, held = family_table(rest)
            lines += ["", text]
            out["holm"] = [dict(r, primary=False) for r in held]
        return lines
    n = len(first)
    text, held = family_table(first, title=(
        f"Declared primary (the study file's [primary]): {n} comparison"
        f"{'s' if n > 1 else ''}, one family"))  # fmt: skip
    lines = ["", text]
    out["holm"] = [dict(r, primary=True) for r in held]
    if rest:
        k = len(rest)
        title = ("The other comparison, secondary, alone" if k == 1 else
                 f"The other {k}, secondary, as one family")  # fmt: skip
        text, other = family_table(rest, title=title)
        lines += ["", text]
        out["holm"] += [dict(r, primary=False) for r in other]
    return lines
