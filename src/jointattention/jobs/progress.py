"""Progress bars: over a run's cells then one status line per later phase, and a lazy one.

The runners report progress as messages (:func:`~jointattention.experiment.backends.run_jobs`,
:func:`~.reproduce.reproduce`); :class:`CellBar` turns them into a tqdm bar on stderr. When the
cells are done and a later phase begins (the ceilings, the tables and figures), the bar is
closed first, so that a status line never lands inside it. :class:`LazyBar` is drawn at its
first unit of work, so that a command refused before any work draws no bar.
"""

from __future__ import annotations

import sys

__all__ = ["PHASES", "CellBar", "LazyBar"]

PHASES = {  # a runner's phase message, and the status line it shows
    "ceilings": "measuring the oracle ceilings",
    "held-out ceilings": "measuring the oracle ceilings of the held-out sets",
    "tables": "writing the tables and figures",
}


class CellBar:
    """A progress bar over ``total`` cells, fed by the runners' progress messages."""

    def __init__(self, total: int):
        self.total, self.bar, self.closed = total, None, False

    def __call__(self, message: str) -> None:
        """Count a finished cell, or show a message of the runner."""
        if message in PHASES:
            self.close()
            print(PHASES[message], file=sys.stderr, flush=True)
            return
        if self.bar is None and not self.closed:  # shown from the first message: a refused
            from tqdm import tqdm  # run shows none

            self.bar = tqdm(total=self.total, desc="cells", unit="cell")
        if self.bar is None:
            return
        if message.endswith("already done"):  # "K of N cells already done"
            done = int(message.split()[0])
            if done:  # a fresh run says nothing
                self.bar.update(done)
                self.bar.write(message, file=sys.stderr)
        else:
            self.bar.update(1)
            self.bar.set_postfix_str(message)

    def close(self) -> None:
        """Close the bar (a later message of a cell shows no new one)."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None
        self.closed = True

    def __enter__(self) -> CellBar:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class LazyBar:
    """A tqdm progress bar drawn at its first update: a command refused before it draws none.

    ``update_to(n)`` moves it to ``n`` done; the keywords are tqdm's.
    """

    def __init__(self, **kwargs):
        self.kwargs, self.bar = kwargs, None

    def update_to(self, n: int) -> None:
        """Show ``n`` done (drawing the bar the first time)."""
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(**self.kwargs)
        self.bar.update(n - self.bar.n)

    def __enter__(self) -> LazyBar:
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()
