"""Scenes: a chain, its bodies and how their parameters change in time.

- ``format``: the TOML scene format (:func:`load_scene`, :class:`Scene`)
- ``robots``: the built-in scenes (planar 2R, spatial 3R, UR5-like, Panda-like, ...)
"""
