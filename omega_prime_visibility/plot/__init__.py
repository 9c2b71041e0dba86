"""Pictures of visibility: one frame (:func:`plot_frame`), an animation (:func:`animate`), a timeline
(:func:`timeline_chart`, :func:`save_timeline`) and an interactive offline HTML report (:func:`write_report`).

The plotting libraries (matplotlib, altair, vl-convert, imageio, pillow) come with the ``plot`` extra:
``pip install 'omega-prime-visibility[plot]'``. They are imported only when a picture is drawn, and a missing one
raises an ``ImportError`` naming the extra.

>>> from omega_prime_visibility.plot import plot_frame
"""

from importlib import import_module

_WHERE = {
    "animate": "animate",
    "plot_frame": "frame",
    "save_timeline": "timeline",
    "timeline_chart": "timeline",
    "write_report": "report",
}
"""Where each picture function lives, loaded on first use (PEP 562): the command line reads ``plot.window``'s
default without loading the rest."""

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name in _WHERE:
        value = getattr(import_module(f".{_WHERE[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_WHERE})
