"""The 3D side: oriented boxes, static occluders with heights, OpenDRIVE objects, and the front ends' 3D mode
(the 3D columns of a recording are read in :mod:`..inputs.boxes3d`).

- :mod:`.boxes`: oriented 3D boxes (OSI rotations, corners, ray-box distances, the eye point), used by the 3D
  engines;
- :mod:`.statics`: static occluders raised to heights, meshes, the 2D height rule;
- :mod:`.mapobjects`: OpenDRIVE ``<object>`` elements as static occluders;
- :mod:`.mode`: what ``mode="3d"`` means to the front ends (engine, statics, ``can_see``).

Nothing is imported here: the engines use :mod:`.boxes` and :mod:`.statics`, while :mod:`.mode` uses the engines,
so each module is imported by its own name.
"""
