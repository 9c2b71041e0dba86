"""Errors about the options of the question, worded by each front end.

An :class:`OptionError` names the option it is about and keeps its message as a template whose references to
options (:class:`Setting`) each front end spells in its own words: the API as ``mode='2d'``, the shell as
``--mode 2d`` (click's ``BadParameter(param_hint=...)`` does the same). No front end rewrites another layer's
text.

>>> e = OptionError("measure", "{given} measures footprints in 2D; use {two_d}",
...     given=Setting("measure", "area"), two_d=Setting("mode", "2d"))
>>> str(e)
"measure='area' measures footprints in 2D; use mode='2d'"
>>> e.words(lambda s: f"--{s.option} {s.value}")
'--measure area measures footprints in 2D; use --mode 2d'
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


class _Unset:
    def __repr__(self) -> str:
        return "UNSET"


UNSET: Any = _Unset()
"""A :class:`Setting` value that stands for the option itself (``engine``, ``--engine``), with no value."""


@dataclass(frozen=True)
class Setting:
    """An option, and the value a message refers to (:data:`UNSET` for the option alone)."""

    option: str
    value: Any = UNSET


def api_spelling(setting: Setting) -> str:
    """A setting as the Python API spells it: ``mode='2d'``, or ``engine`` alone."""
    return setting.option if setting.value is UNSET else f"{setting.option}={setting.value!r}"


class OptionError(ValueError):
    """A bad value of one option of the question.

    Parameters
    ----------
    option : str
        The option, as the API names it (``"ego_idx"``, ``"measure"``).
    message : str
        The text, with ``{name}`` fields for the settings it refers to; without a mention of the option, its name
        is put in front (``targets: ...``).
    **settings : Setting
        The options the message refers to, spelled by :meth:`words`.
    """

    def __init__(self, option: str, message: str, **settings: Setting) -> None:
        self.option = option
        self.template = message
        self.settings = settings
        super().__init__(self.words(api_spelling))

    @classmethod
    def plain(cls, option: str, message: str) -> OptionError:
        """An error whose message refers to no setting (its braces kept as they are)."""
        return cls(option, message.replace("{", "{{").replace("}", "}}"))

    @property
    def detail(self) -> str:
        """The message in the API's words, without the option's name put in front."""
        return self.template.format(**{k: api_spelling(s) for k, s in self.settings.items()})

    def words(self, spell: Callable[[Setting], str], name: str | None = None) -> str:
        """The message with every setting spelled by ``spell``. A message that starts with a setting stands as
        it is; one that starts with the option's API name gets ``name`` there instead (default: the API name);
        any other gets ``name: `` in front.

        >>> e = OptionError.plain("targets", "unknown object kind 'lorry'")
        >>> str(e), e.words(api_spelling, name="--targets")
        ("targets: unknown object kind 'lorry'", "--targets: unknown object kind 'lorry'")
        """
        text = self.template.format(**{k: spell(s) for k, s in self.settings.items()})
        name = self.option if name is None else name
        if self.template.startswith("{"):
            return text
        if text.startswith(self.option):
            return name + text[len(self.option) :]
        return f"{name}: {text}"


class RecordingReadError(ValueError):
    """A file could not be read as an omega-prime recording, or its map could not be read."""
