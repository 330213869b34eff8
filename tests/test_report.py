"""The HTML report: self-contained, with the run's figures, tables, configuration, versions."""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest

from jointattention.cli import main
from jointattention.errors import JointAttentionError
from jointattention.figures.report import write_report

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A tiny reproduced run folder."""
    tmp = tmp_path_factory.mktemp("report")
    cfg = tmp / "tiny.toml"
    cfg.write_text(
        "[experiment]\nn_steps = 300\nn_seeds = 2\nbin_steps = 100\nn_ceiling_trials = 50\n"
        '[[experiment.conditions]]\nname = "n5-sigmoid"\nn_objects = 5\n')
    out = tmp / "run"
    assert main(["reproduce", "--config", str(cfg), "--out", str(out), "--workers", "1"]) == 0
    return out


def test_report_holds_everything_inline(run):
    """The page holds every figure, table and setting inline and refers to nothing else.

    Figures as data URIs (the held-out figure among them), the tables, the configuration and
    the versions.
    """
    page = write_report(run).read_text()
    assert page.count('src="data:image/png;base64,') == len(list(run.glob("*.png"))) == 7
    assert "Generalisation: training sets, new poses, unseen caregivers" in page
    assert "Diagnostics per learning-time bin" in page and "Why a seed fails" in page
    assert "One row per reading" in page and "Learning speed" in page
    assert "The paper&#x27;s claims" in page and "n5-sigmoid" in page
    assert "n_steps = 300" in page and "mujoco" in page
    assert not re.search(r'(src|href)="(https?:)?//', page)  # readable offline


def test_report_opens_with_a_summary_then_the_papers_figures(run):
    """The summary comes first, then Fig. 4 and 5, then generalisation, then diagnostics.

    Column names read as words with units, counts as integers, and a missed target of the
    project's own (learning speed) is not shown as a red NO.
    """
    page = write_report(run).read_text()
    at = [page.index(s) for s in ("<h2>Summary</h2>", "fig4a_success.png", "fig5_gates.png",
                                  "<h2>Claims</h2>", "held_out.png", "learning_speed.png",
                                  "diagnostics.png", "<h2>Configuration</h2>")]
    assert at == sorted(at)
    assert re.search(r"<b>\d+ of \d+ claims hold", page)
    headers = [h for head in re.findall(r"<thead><tr>(.*?)</tr></thead>", page)
               for h in re.findall(r"<th>([^<]*)</th>", head)]
    assert "Fraction of ceiling" in headers and "Unseen median (°)" in headers
    assert not [h for h in headers if "_" in h and h.islower()]
    assert not re.search(r"<td>\d{3,}\.0</td>", page)  # step counts as integers
    speed = page[page.index("Learning speed:"):page.index("learning_speed.png")]
    assert 'class="no"' not in speed
    assert '<div class="wide">' in page  # wide tables scroll in their box


def test_report_refuses_a_folder_that_is_not_a_run(tmp_path):
    """A folder without a run's configuration is refused, and nothing is written."""
    with pytest.raises(JointAttentionError, match="not a run folder"):
        write_report(tmp_path)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (apt-get install "
                    "chromium); .ci/run installs it")
def test_report_renders_in_headless_chromium(run, tmp_path):
    """Headless Chromium, with the network shut, renders the page with its figures.

    ``report --screenshot`` draws it (as docs/report_screenshot.png is made); the screenshot
    has the figures' coloured curves, not only text on white.
    """
    shot = tmp_path / "shot.png"
    assert main(["report", str(run), "--out", str(tmp_path / "r.html"), "--screenshot",
                 str(shot)]) == 0
    import cv2

    img = cv2.imread(str(shot))
    hsv = cv2.cvtColor(img, cv2.COLOR_BGR2HSV)
    coloured = np.mean(hsv[..., 1] > 80)  # saturated pixels come only from the figures
    assert coloured > 0.002, coloured
