"""The audit of robot descriptions: per-link consistency, authoring mistakes, repairs and mass-matrix bounds.

- ``urdf``, ``mjcf``, ``sdf``: URDF files read strictly, MJCF files read by MuJoCo, SDFormat files read by the
  specification, into links and joints
- ``geometry``, ``bodies_inside``: each URDF link's primitives; theorems on every body inside them
- ``mesh_files``, ``meshes``, ``mesh_bodies``: mesh URIs resolved, mesh files read once, the same theorems on
  links whose geometry holds meshes
- ``mjcf_geometry``: each MJCF body's geoms as primitives, and MuJoCo's own inertia from them
- ``mirror_twins``: left/right links placed mirrored whose inertials must be reflections of each other
- ``locate``: where each inertia element stands in its file (line, column, span)
- ``kinematic_tree``: the bodies of movable joints and their serial chains
- ``mistakes``, ``repair``: signs of common authoring mistakes; the nearest consistent inertia, printed consistent
- ``engines``: what MuJoCo, Drake, PyBullet and Gazebo do with an inertia as written
- ``document``: the audit of a robot and of many files, as one JSON-ready document
- ``api``: :func:`audit_urdf` and the :class:`Audit` object for Python and notebooks
- ``text``, ``annotations``, ``rewrite``: the document as tables, as SARIF and GitHub annotations, as repaired copies
- ``pytest_plugin``: ``pytest --inertiaproof-audit PATH``
"""
