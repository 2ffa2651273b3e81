"""The audit of robot descriptions: per-link consistency, authoring mistakes, repairs and mass-matrix bounds.

- ``urdf``: URDF files read strictly into links and joints
- ``kinematic_tree``: the bodies of movable joints and their serial chains
- ``mistakes``, ``repair``: signs of common authoring mistakes; the nearest consistent inertia
- ``document``: the audit of a robot and of many files, as one JSON-ready document (:func:`audit_urdf`)
- ``text``: that document as readable tables
"""
