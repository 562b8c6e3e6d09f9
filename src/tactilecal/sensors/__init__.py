"""Sensor catalogue: Tekscan models (5051, 5101, 9500, 6900, 4010N, F-Scan) and custom matrices."""

from tactilecal.sensors._catalogue import (
    CATALOGUE,
    SensorModel,
    custom_sensor,
    get_sensor,
    match_sensor,
)

__all__ = ["CATALOGUE", "SensorModel", "custom_sensor", "get_sensor", "match_sensor"]

