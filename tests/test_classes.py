"""One meaning of visible, partly hidden, hidden and out of view (analysis/classes.py), against the table's own
policy: over random observations through a sensor, the classes part the rows and agree with the sensors' status."""

from __future__ import annotations

import polars as pl
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from omega_prime_visibility.analysis.classes import CLASSES, class_shares, occlusion_class
from omega_prime_visibility.engines import Reason
from omega_prime_visibility.table.schema import STATUSES, view_of

angles = st.floats(0.0, 1.0, allow_nan=False)


@st.composite
def observations(draw):
    """A target through a sensor as an engine reports it: its extent, the parts in the field and in view, the part
    seen, and the reason (nothing in front: seen wherever in view)."""
    extent = draw(st.floats(1e-6, 1.0))
    in_fov = extent * draw(st.sampled_from([0.0, 1.0, draw(angles)]))
    in_view = in_fov * draw(st.sampled_from([0.0, 1.0, draw(angles)]))
    reason = draw(st.sampled_from([Reason.IN_VIEW, Reason.OCCLUDED]))
    seen = in_view if reason == Reason.IN_VIEW else in_view * draw(st.sampled_from([0.0, draw(angles)]))
    return int(reason), seen, extent, in_view, in_fov


@settings(max_examples=300, deadline=None)
@given(st.lists(observations(), min_size=1, max_size=40))
def test_the_classes_part_the_rows_and_agree_with_the_status(rows) -> None:
    table = []
    for reason, seen, extent, in_view_angle, in_fov in rows:
        visibility, in_view, status = view_of(reason, seen, extent, in_view_angle, in_fov)
        table.append({"visibility": visibility, "in_view": in_view, "status": STATUSES[status], "reason": reason})
    frame = pl.DataFrame(table)
    classes = frame.with_columns(occlusion_class(frame.columns)).rows(named=True)
    for row in classes:
        assert row["class"] in CLASSES
        # hidden is the status occluded, out of view the two statuses of nothing in view: nothing else
        assert (row["class"] == "hidden") == (row["status"] == "occluded")
        assert (row["class"] == "out_of_view") == (row["status"] in ("out_of_fov", "out_of_range"))
        # partly hidden needs something in front; nothing in front of a target in view is visible, however
        # much of it lies outside the field of view
        if row["class"] == "partly_hidden":
            assert row["reason"] == Reason.OCCLUDED and row["status"] == "partly_visible"
        if row["reason"] == Reason.IN_VIEW and row["in_view"] > 0:
            assert row["class"] == "visible"
    shares = frame.select(**class_shares(frame.columns)).row(0, named=True)
    assert sum(shares[c] for c in CLASSES) == pytest.approx(1.0)
