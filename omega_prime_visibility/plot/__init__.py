"""Pictures of visibility: one frame (:func:`plot_frame`), an animation (:func:`animate`), a timeline
(:func:`timeline_chart`, :func:`save_timeline`) and an interactive offline HTML report (:func:`write_report`).

The plotting libraries (matplotlib, altair, vl-convert, imageio, pillow) come with the ``plot`` extra:
``pip install 'omega-prime-visibility[plot]'``. They are imported only when a picture is drawn, and a missing one
raises an ``ImportError`` naming the extra.

>>> from omega_prime_visibility.plot import plot_frame
"""

from .animate import animate
from .frame import plot_frame
from .report import write_report
from .timeline import save_timeline, timeline_chart

__all__ = ["animate", "plot_frame", "save_timeline", "timeline_chart", "write_report"]
