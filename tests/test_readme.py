"""The README's example runs as written."""

from __future__ import annotations

import os
import re
import warnings

from conftest import REPO


def test_readme_example_runs() -> None:
    text = (REPO / "README.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        namespace: dict = {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            exec(compile(code, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    assert namespace["properties"]["visibility"].height == namespace["df"].height
    assert "ego_idx" in namespace["everyone"].columns
