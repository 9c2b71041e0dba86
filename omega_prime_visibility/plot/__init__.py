"""Pictures of visibility: one frame (:func:`plot_frame`), what a camera sees (:func:`plot_camera`), an animation
(:func:`animate`), a timeline (:func:`timeline_chart`, :func:`save_timeline`) and an interactive offline HTML report
(:func:`write_report`).

The plotting libraries (matplotlib, altair, vl-convert, imageio, pillow) come with the ``plot`` extra:
``pip install 'omega-prime-visibility[plot]'``. They are imported only when a picture is drawn, and a missing one
raises an ``ImportError`` naming the extra.

>>> from omega_prime_visibility.plot import plot_frame
"""

from .. import _lazy_names

_WHERE = {
    "animate": "animate",
    "plot_camera": "camera",
    "plot_frame": "frame",
    "save_timeline": "timeline",
    "timeline_chart": "timeline",
    "write_report": "report",
}
"""Where each picture function lives, loaded on first use (PEP 562): the command line reads ``plot.window``'s
default without loading the rest."""

__all__ = sorted(_WHERE)


__getattr__, __dir__ = _lazy_names(__name__, _WHERE)
