"""The question as one value: :class:`Query` (every option that shapes the table, checked once) and
:func:`resolve` (that question against one recording: the objects read once, statics built once, observers,
sensors and engine settled), which every front end builds and every later stage takes."""

from ..inputs.errors import OptionError
from .question import TABLE_KEYWORDS, Query, fold_keywords
from .resolve import Resolved, resolve

__all__ = ["TABLE_KEYWORDS", "OptionError", "Query", "Resolved", "fold_keywords", "resolve"]
