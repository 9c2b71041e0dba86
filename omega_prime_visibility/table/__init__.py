"""The table: the engines' observations per viewpoint turned into rows with one schema.

- :mod:`.schema`: the columns by name and type (:data:`SCHEMA`), the statuses and the policy on reason codes;
- :mod:`.rows`: row assembly from observations; :mod:`.pipeline`: frames in chunks through an engine, on any
  executor; :mod:`.output`: safe (atomic) writing of tables and datasets.

``omega_prime_visibility.table`` gives the schema's names (``SCHEMA``, ``STATUSES``, ...), as it always has.
"""

from .schema import (
    LIST_COLUMNS,
    OCCLUDED,
    OUT_OF_FOV,
    OUT_OF_RANGE,
    PARTLY_VISIBLE,
    SCHEMA,
    SENSOR_SCHEMA,
    STATUSES,
    VISIBLE,
    Columns,
    TableBuilder,
    empty_table,
    schema,
    to_polars,
    view_of,
    visibility_of,
)

__all__ = [
    "LIST_COLUMNS",
    "OCCLUDED",
    "OUT_OF_FOV",
    "OUT_OF_RANGE",
    "PARTLY_VISIBLE",
    "SCHEMA",
    "SENSOR_SCHEMA",
    "STATUSES",
    "VISIBLE",
    "Columns",
    "TableBuilder",
    "empty_table",
    "schema",
    "to_polars",
    "view_of",
    "visibility_of",
]
