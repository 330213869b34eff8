"""The HTML report: self-contained, with the run's figures, tables, configuration, versions."""

from __future__ import annotations

import re
import shutil
import subprocess

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
    assert "The paper&#x27;s claims, checked" in page and "n5-sigmoid" in page
    assert "n_steps = 300" in page and "mujoco" in page
    assert not re.search(r'(src|href)="(https?:)?//', page)  # readable offline


def test_report_refuses_a_folder_that_is_not_a_run(tmp_path):
    """A folder without a run's configuration is refused, and nothing is written."""
    with pytest.raises(JointAttentionError, match="not a run folder"):
        write_report(tmp_path)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (apt-get install "
                    "chromium); .ci/run installs it")
def test_report_renders_in_headless_chromium(run, tmp_path):
    """Headless Chromium, with the network shut, renders the page with its figures.

    The screenshot has the figures' coloured curves, not only text on white.
    """
    page = write_report(run)
    shot = tmp_path / "shot.png"
    subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                    "--disable-background-networking", "--disable-component-update",
                    "--disable-sync", "--no-first-run", f"--user-data-dir={tmp_path / 'p'}",
                    "--window-size=1000,2400", f"--screenshot={shot}", page.as_uri()],
                   check=True, capture_output=True, timeout=600)
    import cv2

    img = cv2.imread(str(shot))
    hsv = cv2.cvtColor(img, cv2.COLOR_BGR2HSV)
    coloured = np.mean(hsv[..., 1] > 80)  # saturated pixels come only from the figures
    assert coloured > 0.002, coloured
