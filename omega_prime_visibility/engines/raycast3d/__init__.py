"""The 3D ray engine on Embree: oriented boxes and static solids, adaptive sampling (see :mod:`.engine`)."""

from .engine import SETTINGS, FastRaycastEngine, HighRaycastEngine, RaycastEngine, Setting

__all__ = ["SETTINGS", "FastRaycastEngine", "HighRaycastEngine", "RaycastEngine", "Setting"]
