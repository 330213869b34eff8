"""One self-contained HTML page for a run folder: figures, tables, configuration, versions.

Everything is inline (figures as data URIs, no scripts, no fonts or styles fetched), so the
page reads offline and can be mailed as one file.
"""

from __future__ import annotations

import base64
import html
import re
import time
from pathlib import Path

from .._checks import check_path
from .._files import atomic_path, check_writable, write_text
from .._readers import read_bytes, read_json, read_text
from .._version import __version__
from ..analysis.claims import SOURCES, claims_groups, claims_of, claims_summary
from ..analysis.tables import Table, read_csv
from ..errors import JointAttentionError

__all__ = ["screenshot", "write_report"]

_PAPER_FIGURES = {
    "fig4a_success.png": "Fig. 4(a): success against learning time for each object count, "
                         "mean and 95% interval over seeds, with chance and the oracle ceiling.",
    "fig4b_gate.png": "Fig. 4(b): the gate's rate of choosing the learning module.",
    "fig5_gates.png": "Fig. 5: five objects, the sigmoid gate against constant rates.",
}
_HELD_OUT_FIGURE = {
    "held_out.png": "Generalisation: each condition's model, frozen, on its training sets, new "
                    "poses of its caregivers and caregivers it never saw, as fractions of each "
                    "set's ceiling, against learning time (held_out.csv).",
}
_SPEED_FIGURE = {
    "learning_speed.png": "Learning fast against learning well: each seed's final success over "
                          "the ceiling against the learning time to 90% of it "
                          "(learning_speed.csv).",
}
_DIAGNOSTIC_FIGURES = {
    "diagnostics.png": "Diagnostics per learning-time bin: the share of learning situations on "
                       "the caregiver's target, the learning module's error, who moved the head, "
                       "how trials ended (diagnostics.csv).",
    "diagnostics_seeds.png": "Why a seed fails: every seed's share of learning situations on "
                             "the target, the learning module's error at the faces and its bias "
                             "(1: one direction for every face), coloured by the seed's final "
                             "success (diagnostics_seeds.csv).",
}
_FIGURES = {**_PAPER_FIGURES, **_HELD_OUT_FIGURE, **_SPEED_FIGURE, **_DIAGNOSTIC_FIGURES}
_CONFIG = "a run's configuration (TOML)"
_UNITS = {"deg": "°", "pct": "%"}  # a column name's last word, shown as its unit
_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.4; }
.wide { overflow-x: auto; max-width: 100%; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #eee; }
td { overflow-wrap: anywhere; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
pre { background: #f6f6f6; padding: 1em; overflow-x: auto; font-size: 0.85em; }
.summary { background: #f3f7fb; border: 1px solid #9bb; padding: 0.5em 1em; }
.yes { color: #060; } .no { color: #a00; font-weight: bold; } .own { color: #555; }
"""


def _header(column: str) -> str:
    """A column's name for a reader: ``unseen_median_deg`` -> "Unseen median (°)"."""
    words = column.split("_")
    unit = _UNITS.get(words[-1]) if len(words) > 1 else None
    text = " ".join(words[:-1] if unit else words)
    text = text[:1].upper() + text[1:]
    return f"{text} ({unit})" if unit else text


def _value(value, own: bool = False) -> tuple[str, str]:
    """A cell's text and class: integers as integers, yes/NO coloured (``own``: not red)."""
    if value is True or value == "yes":
        return "yes", "yes"
    if value is False or value == "NO":
        return ("not yet", "own") if own else ("NO", "no")
    text = str(value)
    if re.fullmatch(r"-?\d\d+\.0", text):  # a count that went through a float column
        text = text[:-2]
    return text, ""


def _html_table(table: Table, own: bool = False) -> str:
    """``table`` in HTML, in a box that scrolls when it is wider than the page."""
    def cell(tag, value):
        text, cls = _value(value, own) if tag == "td" else (_header(value), "")
        return f"<{tag}{f' class={cls!r}' if cls else ''}>{html.escape(text)}</{tag}>"

    head = "".join(cell("th", c) for c in table.columns)
    body = "".join("<tr>" + "".join(cell("td", v) for v in row) + "</tr>" for row in table.rows)
    return (f'<div class="wide"><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody>'
            "</table></div>")


def _table(run: Path, stem: str, own: bool = False) -> str | None:
    """The run's table ``stem`` in HTML.

    From its CSV, or its Markdown text as it is (run folders of older versions wrote no claims.csv).
    """
    if (run / f"{stem}.csv").is_file():
        return _html_table(read_csv(run / f"{stem}.csv"), own)
    if (run / f"{stem}.md").is_file():
        return f"<pre>{html.escape(read_text(run / f'{stem}.md', 'a Markdown table'))}</pre>"
    return None


def _claims(run: Path) -> tuple[str, list[str]]:
    """The claims' one-line summary, and their HTML: per source, per reading, settings once."""
    claims = claims_of(read_csv(run / "claims.csv"))
    rules = list(dict.fromkeys(c.rule for c in claims if c.rule))
    parts = []
    for source, readings in claims_groups(claims):
        parts.append(f"<h3>{html.escape(SOURCES[source])}</h3>")
        for reading, mine in readings:
            parts.append(f"<p>Reading: <code>{html.escape(reading or '(none)')}</code></p>")
            rows = [(c.claim, c.holds, c.evidence,
                     f"[{rules.index(c.rule) + 1}]" if c.rule else "") for c in mine]
            parts.append(_html_table(Table(("claim", "holds", "evidence", "rule"), rows),
                                     own=source == "project"))
    if rules:
        parts.append("<p>Rules:</p><ol>" + "".join(f"<li>{html.escape(r)}</li>" for r in rules)
                     + "</ol>")
    return claims_summary(claims), parts


def _kv_table(data: dict) -> str:
    rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                   for k, v in data.items())
    return f"<table>{rows}</table>"


def _figure(path: Path, caption: str) -> str:
    data = base64.b64encode(read_bytes(path, "a PNG figure", 2**26)).decode("ascii")
    return (f'<figure><img alt="{html.escape(path.name)}" src="data:image/png;base64,{data}">'
            f"<figcaption>{html.escape(caption)} ({html.escape(path.name)})</figcaption>"
            "</figure>")


def _figures(run: Path, captions: dict[str, str]) -> list[str]:
    """The figures of ``captions`` that the run drew, in that order."""
    return [_figure(run / name, text) for name, text in captions.items()
            if (run / name).exists()]  # one that is not a file is refused by the reader


def _summary(run: Path, claims: str | None) -> str:
    """The box at the top: the claims that hold, the run's size and time, and the order below."""
    items = []
    if claims is not None:
        items.append(f"<li><b>{html.escape(claims)}</b>; the project's own targets are "
                     "beyond the paper, and a missed one is not a failure of the paper.</li>")
    if (run / "timing.json").is_file():
        t = read_json(run / "timing.json", "a run's timing")
        items.append(f"<li>{html.escape(str(t.get('cells_total', '?')))} cells; the whole run "
                     f"{html.escape(str(t.get('wall_min', '?')))} min on "
                     f"{html.escape(str(t.get('workers', '?')))} workers.</li>")
    items.append("<li>Below: the paper's figures, the final success and the claims, "
                 "generalisation (held-out sets), learning speed, then the diagnostics, the "
                 "ceilings, the configuration and the versions.</li>")
    return f'<div class="summary"><h2>Summary</h2><ul>{"".join(items)}</ul></div>'


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
    claims, claim_parts = _claims(run) if (run / "claims.csv").is_file() else (None, [])
    parts = [f"<h1>jointattention run: {html.escape(run.resolve().name)}</h1>",
             f"<p>Report made {time.strftime('%Y-%m-%d %H:%M')} by jointattention "
             f"{__version__} from <code>{html.escape(str(run))}</code>.</p>"]
    if not points:
        parts.append(_summary(run, claims))
    sections = [
        ("The paper's figures", _figures(run, _PAPER_FIGURES)),
        ("Final success per condition", [_table(run, "table")]),
        ("Claims", claim_parts or [_table(run, "claims")]),
        ("Generalisation: training sets, new poses, unseen caregivers (frozen)",
         [_table(run, "held_out"), *_figures(run, _HELD_OUT_FIGURE)]),
        ("One row per reading, ranked by the rule (docs/readings.md)", [_table(run, "readings")]),
        ("Learning speed: each seed's steps to 90% of its final success (this project's own "
         "target, beyond the paper: 90% within 3x10^4 steps and a final of 0.95 of the ceiling)",
         [_table(run, "learning_speed", own=True), *_figures(run, _SPEED_FIGURE)]),
        ("Sweep summary", [_table(run, "summary")]),
        ("Diagnostics", _figures(run, _DIAGNOSTIC_FIGURES)),
        ("Other figures", [_figure(p, p.stem) for p in sorted(run.glob("*.png"))
                           if p.name not in _FIGURES]),
    ]
    for title, content in sections:
        content = [c for c in content if c]
        if content:
            parts += [f"<h2>{html.escape(title)}</h2>", *content]
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


_BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def screenshot(page: str | Path, png: str | Path, *, width_px: int = 1200,
               height_px: int = 1800) -> Path:
    """Draw the top of the HTML ``page`` into ``png`` with a headless Chromium, network shut.

    The manual's picture of the report (docs/report_screenshot.png) is made this way from the
    demo's run: ``jointattention report runs/demo --screenshot docs/report_screenshot.png``.
    Chromium is not a dependency of the package: without it, one error line says so.
    """
    import shutil
    import subprocess
    import tempfile

    page, png = Path(check_path(page, "page")), Path(check_path(png, "png"))
    if png.suffix.lower() != ".png":
        raise JointAttentionError(f"{png}: expected a file name ending in .png")
    browser = next((b for b in map(shutil.which, _BROWSERS) if b), None)
    if browser is None:
        raise JointAttentionError("no Chromium found (" + ", ".join(_BROWSERS) + "); expected "
                                  "one on the PATH to draw the screenshot (e.g. apt-get "
                                  "install chromium)")
    png = check_writable(png, "file", "--screenshot")
    with tempfile.TemporaryDirectory() as profile, atomic_path(png) as tmp:
        shot = Path(profile) / "shot.png"
        done = subprocess.run(
            [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             "--no-first-run", f"--user-data-dir={profile}/p",
             f"--window-size={width_px},{height_px}", f"--screenshot={shot}",
             page.resolve().as_uri()], capture_output=True, timeout=600)
        if done.returncode != 0 or not shot.is_file():
            last = (done.stderr.decode(errors="replace").strip().splitlines() or ["no output"])
            raise JointAttentionError(f"{browser} drew no screenshot of {page} ({last[-1]}); "
                                      "expected a PNG")
        shutil.copyfile(shot, tmp)
    return png
