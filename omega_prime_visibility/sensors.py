"""Sensors: where each sits on its observer and what it sees.

They live in :mod:`.inputs.sensors`; this module keeps the documented import path
``omega_prime_visibility.sensors``.
"""

from .inputs.sensor_files import read_sensors, resolve_sensors
from .inputs.sensors import (
    DRIVER_EYE_HEIGHT,
    LAYOUTS,
    Sensor,
    camera,
    check_sensors,
    fitted_layout,
    is_layout,
    lidar,
    nuscenes,
    roof,
    sensor_poses,
    typical,
)

__all__ = [
    "DRIVER_EYE_HEIGHT",
    "LAYOUTS",
    "Sensor",
    "camera",
    "check_sensors",
    "fitted_layout",
    "is_layout",
    "lidar",
    "nuscenes",
    "read_sensors",
    "resolve_sensors",
    "roof",
    "sensor_poses",
    "typical",
]
