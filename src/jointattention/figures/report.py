"""One self-contained HTML page for a run folder: figures, tables, configuration, versions.

Everything is inline (figures as data URIs, no scripts, no fonts or styles fetched), so the
page reads offline and can be mailed as one file.
"""

from __future__ import annotations

import base64
import html
import time
from pathlib import Path

from .._checks import check_path
from .._files import check_writable, write_text
from .._readers import read_bytes, read_json, read_text
from .._version import __version__
from ..analysis.tables import read_csv
from ..errors import JointAttentionError

__all__ = ["write_report"]

_FIGURES = {
    "fig4a_success.png": "Fig. 4(a): success against learning time for each object count, "
                         "mean and 95% interval over seeds, with chance and the oracle ceiling.",
    "fig4b_gate.png": "Fig. 4(b): the gate's rate of choosing the learning module.",
    "fig5_gates.png": "Fig. 5: five objects, the sigmoid gate against constant rates.",
    "diagnostics.png": "Diagnostics per learning-time bin: the share of learning situations on "
                       "the caregiver's target, the learning module's error, who moved the head, "
                       "how trials ended (diagnostics.csv).",
    "diagnostics_seeds.png": "Why a seed fails: every seed's share of learning situations on "
                             "the target, the learning module's error at the faces and its bias "
                             "(1: one direction for every face), coloured by the seed's final "
                             "success (diagnostics_seeds.csv).",
    "held_out.png": "Generalisation: each condition's model, frozen, on its training sets, new "
                    "poses of its caregivers and caregivers it never saw, as fractions of each "
                    "set's ceiling, against learning time (held_out.csv).",
    "learning_speed.png": "Learning fast against learning well: each seed's final success over "
                          "the ceiling against the learning time to 90% of it "
                          "(learning_speed.csv).",
}
_CONFIG = "a run's configuration (TOML)"
_TABLES = {"claims": "The paper's claims, checked", "table": "Final success per condition",
           "readings": "One row per reading, ranked by the rule (docs/readings.md)",
           "held_out": "Generalisation: training sets, new poses, unseen caregivers (frozen)",
           "learning_speed": "Learning speed: each seed's steps to 90% of its final success",
           "summary": "Sweep summary"}
_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.4; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; }
th { background: #eee; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
pre { background: #f6f6f6; padding: 1em; overflow-x: auto; font-size: 0.85em; }
.yes { color: #060; } .no { color: #a00; font-weight: bold; }
"""


def _table(run: Path, stem: str) -> str | None:
    """The run's table ``stem`` in HTML.

    From its CSV, or its Markdown text as it is (run folders of older versions wrote no claims.csv).
    """
    if (run / f"{stem}.csv").is_file():
        return read_csv(run / f"{stem}.csv").to_html()
    if (run / f"{stem}.md").is_file():
        return f"<pre>{html.escape(read_text(run / f'{stem}.md', 'a Markdown table'))}</pre>"
    return None


def _kv_table(data: dict) -> str:
    rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                   for k, v in data.items())
    return f"<table>{rows}</table>"


def _figure(path: Path, caption: str) -> str:
    data = base64.b64encode(read_bytes(path, "a PNG figure", 2**26)).decode("ascii")
    return (f'<figure><img alt="{html.escape(path.name)}" src="data:image/png;base64,{data}">'
            f"<figcaption>{html.escape(caption)} ({html.escape(path.name)})</figcaption>"
            "</figure>")


def write_report(run: str | Path, out: str | Path | None = None) -> Path:
    """Write ``report.html`` (or ``out``) for the run folder ``run``; returns its path."""
    run = Path(check_path(run, "run"))
    if out is not None:
        check_path(out, "out")
    points = sorted(p.parent for p in run.glob("*/config.toml"))  # a sweep's points
    if not (run / "config.toml").is_file() and not points:
        raise JointAttentionError(f"{run}: not a run folder (no config.toml); expected a folder "
                                  "written by `jointattention reproduce` or `sweep`")
    out = check_writable(run / "report.html" if out is None else Path(out), "file", "report")
    parts = [f"<h1>jointattention run: {html.escape(run.resolve().name)}</h1>",
             f"<p>Report made {time.strftime('%Y-%m-%d %H:%M')} by jointattention "
             f"{__version__} from <code>{html.escape(str(run))}</code>.</p>"]
    if (run / "timing.json").is_file():
        parts += ["<h2>Run</h2>", _kv_table(read_json(run / "timing.json", "a run's timing"))]
    for stem, title in _TABLES.items():
        table = _table(run, stem)
        if table is not None:
            parts += [f"<h2>{html.escape(title)}</h2>", table]
    figures = sorted(run.glob("*.png"))
    if figures:
        parts.append("<h2>Figures</h2>")
        parts += [_figure(p, _FIGURES.get(p.name, p.stem)) for p in figures]
    missing = [n for n in ("table.csv", "claims.csv", *_FIGURES) if not (run / n).is_file()]
    if missing and not points:
        parts.append(f"<p>Not in this folder (yet): {html.escape(', '.join(missing))}.</p>")
    if (run / "ceilings.json").is_file():
        ceilings = read_json(run / "ceilings.json", "a run's oracle ceilings")
        parts += ["<h2>Oracle ceilings (objects: success)</h2>", _kv_table(ceilings)]
    parts.append("<h2>Configuration</h2>")
    if (run / "config.toml").is_file():
        parts.append(f"<pre>{html.escape(read_text(run / 'config.toml', _CONFIG))}</pre>")
    parts += [f"<details><summary>{html.escape(p.name)}</summary>"
              f"<pre>{html.escape(read_text(p / 'config.toml', _CONFIG))}</pre></details>"
              for p in points]
    versions = next((d / "versions.json" for d in (run, *points)
                     if (d / "versions.json").is_file()), None)
    if versions is not None:
        parts += ["<h2>Versions it ran with</h2>",
                  _kv_table(read_json(versions, "a run's versions"))]
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>jointattention: {html.escape(run.resolve().name)}</title>"
            f"<style>{_STYLE}</style></head><body>\n" + "\n".join(parts) + "\n</body></html>\n")
    return write_text(out, page)
