"""Hostile and broken inputs (tests/hostile/cases.py), each run in this process.

Every case must end cleanly: a refusal is exit status 2 with one ``error:`` line (naming what
was wrong), no traceback and nothing written; an API refusal is one ``JointAttentionError``
naming the argument; a case that expects success succeeds and passes its check. Cases that need
a fresh process (the OpenGL backend is chosen at MuJoCo's import) run in a subprocess, with the
same classification. ``scripts/hostile_corpus.py`` runs the same corpus against any tree.
"""

from __future__ import annotations

import contextlib
import io
import logging
import os
import signal
import sys
import traceback
from collections.abc import Iterator
from pathlib import Path

import pytest

from hostile import cases
from hostile.cases import CASES, Case, classify_api, classify_cli, run_api, snapshot

# A guard against work without a bound, not a speed test: 10x the corpus script's 20 s, as
# the machine may be shared.
TIMEOUT_S = float(os.environ.get("HOSTILE_TIMEOUT", "200"))  # per in-process case
REPO_SRC = Path(__file__).resolve().parents[1] / "src"


class HostileTimeout(BaseException):
    """A case ran past its time (its work has no bound)."""


@contextlib.contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Raise :class:`HostileTimeout` in this thread after ``seconds``."""
    def expire(signum, frame):
        raise HostileTimeout(f"still running after {seconds:g} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def build_in_process(directory: Path, argv: list[str]) -> None:
    """Make a finished tiny run with this process's jointattention (cases.BUILDER)."""
    from jointattention.cli import main

    cwd = os.getcwd()
    err = io.StringIO()
    os.chdir(directory)
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            status = main(argv)
    finally:
        os.chdir(cwd)
    if status != 0:
        raise RuntimeError(f"{argv} exited with {status}: {err.getvalue()[-400:]}")


cases.BUILDER = build_in_process
cases.SRC = REPO_SRC


@pytest.fixture(scope="session", autouse=True)
def warm_up() -> None:
    """Make the finished tiny run once (compiling the kernels) before any case is timed."""
    with contextlib.suppress(Exception):
        cases.pristine("run")


def _run_cli(argv: list[str]) -> tuple[int, bool]:
    """Run the CLI in-process; (exit status, timed out). Output goes to the captured fds."""
    from jointattention.cli import main

    # The CLI's warning handler keeps the stderr of the first main() in this process, as a
    # fresh process's would keep its own: point it at this case's captured stderr.
    for handler in logging.getLogger("jointattention").handlers:
        if type(handler) is logging.StreamHandler:
            handler.stream = sys.stderr  # not setStream: it flushes the old, closed stream
    try:
        with time_limit(TIMEOUT_S):
            return main(argv), False
    except HostileTimeout:
        return -1, True
    except SystemExit as exit_:
        code = exit_.code
        return (0 if code is None else code if isinstance(code, int) else 1), False
    except BaseException:
        traceback.print_exc()
        return 1, False


def _run(case: Case, tmp: Path, capfd: pytest.CaptureFixture[str]) -> tuple[str, str]:
    """Make the case in ``tmp``, run it in-process; (outcome, what to show on failure)."""
    reason = case.skip() if case.skip is not None else None
    if reason:
        pytest.skip(reason)
    invocation = case.make(tmp)
    before = snapshot(tmp)
    capfd.readouterr()
    if isinstance(invocation, str):
        timed_out = False
        try:
            with time_limit(TIMEOUT_S):
                result = run_api(invocation)
        except HostileTimeout:
            timed_out, result = True, {"kind": "none", "type": "", "message": ""}
        changed = snapshot(tmp) != before
        outcome = classify_api(case, tmp, result, changed, timed_out)
        return outcome, (f"{result.get('type')}: {result.get('message')}\n"
                         f"{result.get('traceback', '')[-1500:]}")
    status, timed_out = _run_cli(invocation)
    out, err = capfd.readouterr()
    changed = snapshot(tmp) != before
    outcome = classify_cli(case, tmp, status, out, err, changed, timed_out)
    return outcome, f"exit {status}, changed={changed}\nstderr: {err[-1500:]}"


IN_PROCESS = [c for c in CASES if not c.subprocess_only]
SUBPROCESS = [c for c in CASES if c.subprocess_only]


@pytest.mark.parametrize("case", IN_PROCESS, ids=lambda c: c.id)
def test_hostile_input_is_refused_cleanly(case: Case, tmp_path, monkeypatch, capfd):
    """A hostile input is refused in one named error line with nothing written (or succeeds)."""
    monkeypatch.chdir(tmp_path)
    outcome, shown = _run(case, tmp_path, capfd)
    assert outcome in case.good, (f"{case.id} [{case.fault}]: {outcome}, expected "
                                  f"{' or '.join(case.good)}\n{shown}")


@pytest.mark.parametrize("case", SUBPROCESS, ids=lambda c: c.id)
def test_hostile_environment_is_handled_in_a_fresh_process(case: Case):
    """A case needing a fresh process (OpenGL, a damaged installation) ends as expected."""
    result = cases.run_subprocess(case, REPO_SRC, timeout=600)  # a fresh process compiles
    if result["outcome"] == "skipped":
        pytest.skip(result["detail"])
    assert result["outcome"] in case.good, (f"{case.id} [{case.fault}]: {result['outcome']}, "
                                            f"expected {' or '.join(case.good)}\n"
                                            f"{result['detail']}")


def test_corpus_is_large_unique_and_covers_every_fault():
    """The corpus has at least 210 cases with unique ids, and every fault class has cases."""
    ids = [c.id for c in CASES]
    assert len(ids) >= 210
    assert len(set(ids)) == len(ids)
    assert {c.fault for c in CASES} == set(cases.FAULTS)
