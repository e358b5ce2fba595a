"""``DIR/report.html``: one self-contained page about a run or a reproduction.

Everything is embedded (figures as PNG data URIs, the video as an MP4/GIF data
URI, no script or style from the network), so the file can be mailed or
archived on its own. A training run's page holds its config, a summary of
``metrics.csv``, the fitness curves, the behaviour metrics of its best genome
(re-simulated and checked against the recorded fitness), its figures and its
video; a reproduction's page holds ``results.md`` (the table against the
paper) and a section per stage.
"""

from __future__ import annotations

import base64
import html
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

from markdown_it import MarkdownIt
from markdown_it.token import Token

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.present.evaluate import HELD_OUT_SEEDS, evaluate_run, evaluate_terrains
from locustjump.present.repertoire import archive_figure
from locustjump.present.results import held_out_markdown
from locustjump.version import __version__

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend
_MIME = {".png": "image/png", ".gif": "image/gif", ".mp4": "video/mp4"}
#: the largest figure or video embedded (a run's 2,500-frame video is ~10 MB)
MAX_FIGURE_BYTES = 256 << 20

_STYLE = """
body { font: 15px/1.45 system-ui, sans-serif; max-width: 1100px; margin: 2em auto;
       padding: 0 1em; color: #222; }
h1, h2, h3 { line-height: 1.2; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 14px; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left;
         vertical-align: top; }
th { background: #f2f2f2; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 13px; }
img, video { max-width: 100%; height: auto; display: block; margin: 0.6em 0; }
code { background: #f2f2f2; padding: 0 0.2em; }
footer { color: #777; font-size: 13px; margin-top: 3em; }
"""

# Sets <body data-images="loaded/total"> once the page has loaded, so a
# headless browser can check that every embedded image decodes.
_CHECK = """
window.addEventListener("load", () => {
  const imgs = Array.from(document.images);
  const ok = imgs.filter((i) => i.complete && i.naturalWidth > 0).length;
  document.body.dataset.images = ok + "/" + imgs.length;
});
"""


def _data_uri(path: Path) -> str:
    mime = _MIME[path.suffix.lower()]
    data = rundir.read_bytes(path, "figure", MAX_FIGURE_BYTES)
    return f"data:{mime};base64,{base64.b64encode(data).decode()}"


def _figure(path: Path, caption: str = "") -> str:
    if path.suffix.lower() == ".mp4":
        media = f'<video controls loop muted src="{_data_uri(path)}"></video>'
    else:
        media = f'<img alt="{html.escape(caption)}" src="{_data_uri(path)}">'
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return f"<figure>{media}{cap}</figure>"


#: CommonMark with pipe tables (what results.md is written in); raw HTML in
#: the Markdown is escaped, not passed through
_MARKDOWN = MarkdownIt("commonmark", {"html": False}).enable("table")


def _html_twin(href: str) -> str:
    """A link to a ``results.md`` goes to the ``report.html`` beside it."""
    if href.endswith(rundir.RESULTS):
        return href[: -len(rundir.RESULTS)] + rundir.REPORT
    return href


def _embed(token: Token, base: Path) -> None:
    """Make an image token of the Markdown self-contained: a figure relative
    to ``base`` becomes a data URI (a video, a <video>), a missing one text."""
    src = str(token.attrGet("src") or "")
    path = base / src
    alt = token.content
    if not (path.is_file() and path.suffix.lower() in _MIME):
        token.type, token.content, token.children = (
            "text",
            f"(missing figure {src})",
            None,
        )
    elif path.suffix.lower() == ".mp4":
        token.type, token.content, token.children = (
            "html_inline",
            _figure(path, alt),
            None,
        )
    else:
        token.attrSet("src", _data_uri(path))


def markdown_to_html(text: str, base: Path) -> str:
    """Markdown (CommonMark + pipe tables, by markdown-it-py) as HTML, images
    embedded from paths relative to ``base``, links to a ``results.md`` sent
    to the ``report.html`` beside it."""
    tokens = _MARKDOWN.parse(text)
    for block in tokens:
        for token in block.children or ():
            if token.type == "image":
                _embed(token, base)
            elif token.type == "link_open":
                token.attrSet("href", _html_twin(str(token.attrGet("href") or "")))
    html: str = _MARKDOWN.renderer.render(tokens, _MARKDOWN.options, {})
    return html


def _cell(v: Any) -> str:
    """One value of a table as HTML: a table of a table, a list as its items."""
    if isinstance(v, dict):
        return _table(v)
    if isinstance(v, list | tuple):
        return html.escape(", ".join(_text(x) for x in v))
    return html.escape(_text(v))


def _text(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, dict):
        return ", ".join(f"{k} {_text(x)}" for k, x in v.items())
    return str(v)


#: unit suffixes of metric names, as a reader writes them
_UNITS = (("_m_s", "m/s"), ("_deg", "deg"), ("_m", "m"), ("_s", "s"))


def _readable(key: str) -> str:
    """A metric's name as words with its unit: ``takeoff_speed_m_s`` ->
    ``takeoff speed (m/s)``."""
    for suffix, unit in _UNITS:
        if key.endswith(suffix) and len(key) > len(suffix):
            return f"{key[: -len(suffix)].replace('_', ' ')} ({unit})"
    return key.replace("_", " ")


def _metrics_table(metrics: dict[str, Any]) -> str:
    """The behaviour metrics, named in words (a nested table keeps its keys:
    joint names, behaviour names)."""
    return _table({_readable(k): v for k, v in metrics.items()})


def _table(d: dict[str, Any]) -> str:
    """A two-column table, key and value; a value that is a table nests."""
    rows = [
        f"<tr><th>{html.escape(str(k))}</th><td>{_cell(v)}</td></tr>"
        for k, v in d.items()
    ]
    return "<table>" + "".join(rows) + "</table>"


def _videos(d: Path) -> list[Path]:
    return sorted(p for p in d.glob("*") if p.suffix.lower() in (".mp4", ".gif"))


def _figures(d: Path, eval_dir: Path | None = None) -> list[Path]:
    found = []
    for sub in (eval_dir or d / rundir.EVAL, d / rundir.SWEEP):
        if sub.is_dir():
            found += sorted(sub.glob("*.png"))
    return found


#: a quality-diversity run's columns of metrics.csv, as the report names them
_QD_COLUMNS = {
    "qd_score": "QD score (sum of the elites' fitness less qd_offset each)",
    "coverage": "coverage (cells holding an elite)",
    "archive_best": "best elite's fitness",
}


def _run_section(
    d: Path,
    metrics: dict[str, Any] | None,
    level: int = 2,
    eval_dir: Path | None = None,
) -> str:
    """The part of the page about training run ``d`` (its evaluation's
    figures from ``eval_dir``, default ``d/eval``)."""
    h = f"h{level}"
    parts = [f"<{h}>Configuration</{h}>"]
    parts.append(
        f"<p>{html.escape(rundir.CONFIG)}: every setting of the run "
        "(a table per section)</p>"
    )
    parts.append(_table(rundir.read_toml(d / rundir.CONFIG)))
    rows = rundir.read_metrics(d / rundir.METRICS)
    if len(rows):
        last = rows[-1]
        parts.append(f"<{h}>Training</{h}>")
        training = {
            "generations": int(last["generation"]),
            "best fitness (last generation)": float(last["best"]),
            "population mean (last generation)": float(last["mean"]),
            "wall time (s)": round(float(rows["wall_s"].sum()), 1),
            "control steps/s (last generation)": float(last["steps_per_s"]),
        }
        for key, what in _QD_COLUMNS.items():  # a quality-diversity run's
            if key in (rows.dtype.names or ()):
                training[what] = float(last[key])
        parts.append(_table(training))
    fit = d / rundir.FITNESS_PNG
    if fit.is_file():
        parts.append(_figure(fit, "best and mean fitness per generation"))
    archive: Path | None = d / rundir.ARCHIVE_PNG
    if eval_dir is not None and not (d / rundir.ARCHIVE_PNG).is_file():
        # a shipped run keeps its archive, not the figure: drawn for the page
        (eval_dir / "archive").mkdir(exist_ok=True)
        archive = archive_figure(d, into=eval_dir / "archive")
    if archive is not None and archive.is_file():
        parts.append(
            _figure(
                archive,
                "the repertoire: each cell's elite's fitness over the behaviour "
                "descriptors (evaluate and render play the elite of one cell)",
            )
        )
    if metrics is not None:
        parts.append(f"<{h}>Best controller</{h}>")
        parts.append(_metrics_table(metrics))
    figs = _figures(d, eval_dir)
    if figs:
        parts.append(f"<{h}>Figures</{h}>")
        parts += [_figure(f, f.name) for f in figs]
    vids = _videos(d)
    if vids:
        parts.append(f"<{h}>Video</{h}>")
        parts += [_figure(v, v.name) for v in vids]
    return "\n".join(parts)


def _page(title: str, body: str, *, heading: bool = True) -> str:
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title>
<style>{_STYLE}</style>
<script>{_CHECK}</script>
</head>
<body>
{f"<h1>{html.escape(title)}</h1>" if heading else ""}
{body}
<footer>Written by <code>locustjump report</code> (locustjump {__version__}).
Self-contained: no network needed.</footer>
</body>
</html>
"""


def write_report(
    path: str | os.PathLike[str],
    *,
    backend: Backend | None = None,
    out: str | os.PathLike[str] | None = None,
) -> Path:
    """Write the report of a training run or a reproduction ``path`` into
    ``out``, by default ``path/report.html`` (for a shipped run under
    ``results/``: ``runs/shipped/<same path>/report.html``,
    :func:`locustjump.rundir.derived_dir`); rewritten on every call, it holds
    derived content only. Nothing else is written: a training run's best
    genome is re-simulated into a temporary directory, its figures embedded."""

    d = Path(path)
    if not d.is_dir():
        raise UserError(f"{d}: no such directory")
    if out is not None and Path(out).resolve().parent != d.resolve():
        return _write_report(d, backend, Path(out))  # written atomically
    with rundir.deriving(d) as dest:  # from the first file read to report.html
        return _write_report(d, backend, Path(out or dest / rundir.REPORT))


def _write_report(d: Path, backend: Backend | None, page: Path) -> Path:
    if rundir.is_multiseed(d):
        if not (d / rundir.RESULTS).is_file():
            raise UserError(f"{d}: the reproduction has no {rundir.RESULTS} yet")
        body = [markdown_to_html(rundir.read_text(d / rundir.RESULTS), d)]
        title = f"locustjump reproduction over seeds: {d.name}"
    elif rundir.is_reproduction(d):
        if not (d / rundir.RESULTS).is_file():
            raise UserError(f"{d}: the reproduction has no {rundir.RESULTS} yet")
        body = [markdown_to_html(rundir.read_text(d / rundir.RESULTS), d)]
        for stage in sorted(p for p in d.iterdir() if rundir.is_run(p)):
            mfile = rundir.eval_metrics_path(stage)
            metrics = rundir.read_json(mfile) if mfile.is_file() else None
            body.append(f"<h2>Stage {html.escape(stage.name)}</h2>")
            body.append(_run_section(stage, metrics, level=3))
        rules = d / rundir.RULES_DIR
        rules_videos = _videos(rules) if rules.is_dir() else []
        if rules_videos:
            body.append("<h2>Rule-based baseline</h2>")
            body += [_figure(v, v.name) for v in rules_videos]
        title = f"locustjump reproduction: {d.name}"
    elif rundir.is_run(d):
        rundir.read_metrics(d / rundir.METRICS)  # checked before anything runs
        with tempfile.TemporaryDirectory(prefix="locustjump-report-") as tmp:
            ev = evaluate_run(d, backend=backend, eval_dir=tmp)
            metrics = {
                "re-simulated fitness": ev.fitness,
                "recorded fitness": ev.recorded_fitness,
                "matches": ev.matches,
                **ev.metrics,
            }
            body = [_run_section(d, metrics, eval_dir=Path(tmp))]
        if rundir.load_config(d / rundir.CONFIG).scene.scene.seeded:
            te = evaluate_terrains(d, list(HELD_OUT_SEEDS), backend=backend)
            md = held_out_markdown({ev.behaviour: te.to_dict()})
            body.append(markdown_to_html("\n".join(md), d))
        title = f"locustjump run: {d.name} ({ev.behaviour})"
    else:
        raise UserError(f"{d}: holds no run (no {rundir.CONFIG}) and no reproduction")
    # a reproduction's results.md brings its own heading
    heading = not (rundir.is_reproduction(d) or rundir.is_multiseed(d))
    with rundir.made_dir(page.parent):  # removed again if the write fails
        rundir.atomic_write_text(page, _page(title, "\n".join(body), heading=heading))
    return page
