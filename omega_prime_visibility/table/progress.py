"""A call's progress bar: tqdm's (in a notebook, its widget), drawn once the call has run :data:`DELAY_S` seconds.

A shorter call finishes before a bar would tell anything, and never imports tqdm (45 ms of a short call: tqdm reads
its own version with ``importlib.metadata``).

Examples
--------
>>> bar = Progress(total=10, show=True, desc="visibility", unit="frame")
>>> bar.update(4); bar.update(6); bar.close()  # (done within DELAY_S: nothing drawn)
>>> bar.done, bar.drawn
(10, False)
"""

from __future__ import annotations

import time
import warnings

DELAY_S = 0.5
"""Seconds a call runs before its progress bar is drawn."""


class Progress:
    """Frames done out of ``total``, drawn as tqdm's bar ``desc`` (in ``unit``) once :data:`DELAY_S` have passed,
    if ``show``."""

    def __init__(self, total: int, show: bool, desc: str, unit: str) -> None:
        self.total, self.show, self.desc, self.unit = total, show, desc, unit
        self.done = 0
        self.started = time.perf_counter()
        self._bar = None

    @property
    def drawn(self) -> bool:
        """Whether the bar is drawn (the call has run long enough)."""
        return self._bar is not None

    def update(self, n: int) -> None:
        """``n`` more frames done."""
        self.done += n
        if self._bar is not None:
            self._bar.update(n)
        elif self.show and time.perf_counter() - self.started >= DELAY_S:
            self._bar = _tqdm()(total=self.total, initial=self.done, desc=self.desc, unit=self.unit)
            self._bar.start_t -= time.perf_counter() - self.started  # (its rate from the call's start)
            self._bar.refresh()

    def close(self) -> None:
        """The bar finished (if drawn)."""
        if self._bar is not None:
            self._bar.close()


def _tqdm():
    from tqdm import TqdmExperimentalWarning

    with warnings.catch_warnings():  # (in a notebook it says it draws there: what tqdm.auto silences too)
        warnings.simplefilter("ignore", TqdmExperimentalWarning)
        # tqdm.auto without its asyncio mix-in, which imports asyncio (a tenth of a short run's imports) for nothing
        from tqdm.autonotebook import tqdm
    return tqdm
