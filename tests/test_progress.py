"""A call's progress bar (table/progress.py): drawn once the call has run DELAY_S seconds, counting what was done
before, never for a shorter call (which then never imports tqdm)."""

from __future__ import annotations

import subprocess
import sys

from conftest import REPO

from omega_prime_visibility.table import progress
from omega_prime_visibility.table.progress import Progress


def test_a_call_that_runs_long_enough_draws_the_frames_done_before(monkeypatch, capsys) -> None:
    monkeypatch.setattr(progress, "DELAY_S", 0.0)
    bar = Progress(total=10, show=True, desc="visibility", unit="frame")
    bar.update(4)
    bar.update(6)
    bar.close()
    drawn = capsys.readouterr().err
    assert bar.drawn and "visibility: 100%" in drawn and "10/10" in drawn, drawn


def test_a_short_call_or_a_hidden_bar_draws_nothing(monkeypatch, capsys) -> None:
    bar = Progress(total=10, show=True, desc="visibility", unit="frame")
    bar.update(10)
    bar.close()
    monkeypatch.setattr(progress, "DELAY_S", 0.0)
    hidden = Progress(total=10, show=False, desc="visibility", unit="frame")
    hidden.update(10)
    hidden.close()
    assert not bar.drawn and not hidden.drawn and capsys.readouterr().err == ""


def test_a_call_done_before_the_bar_is_due_never_imports_tqdm() -> None:
    code = (
        "import sys; from omega_prime_visibility import get_visibility_df; from omega_prime_visibility.table import"
        " progress; progress.DELAY_S = 1e9; get_visibility_df('highway_merge.mcap', 0, progress=True);"
        " print('tqdm' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True)
    assert done.stdout.split()[-1] == "False" and "visibility:" not in done.stderr
