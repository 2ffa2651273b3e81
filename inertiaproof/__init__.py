"""inertiaproof: proof-checking 'On robotic manipulators with time-dependent inertial parameters'.

The core, by concern (dependencies point down this list, never up):

- ``model``: one rigid body's inertial parameters, physical consistency, densities
- ``dynamics``: chains, QJ, the terms of the generalized robotics equation, parameter trajectories
- ``scene``, ``bounds``: scenes and built-in robots; the Section 4 brackets and constants
- ``sim``, ``audit``: simulation and the studies on it; the audit of URDF and MJCF robots
- ``suite``: the catalog, checks, runs, hunts and replays; ``cli``: the command

``inertiaproof.symbolic``, ``inertiaproof.checks``, ``inertiaproof.counterexamples`` and
``inertiaproof.report`` derive, check, attack and present the paper's results. The names below
are the Python API; they are imported on first use::

    >>> import numpy as np, inertiaproof as ip
    >>> ip.physical_consistency(np.array([1.0, 0, 0, 0, 0.1, 0.1, 0.1, 0, 0, 0])).labels
    'consistent'
"""

import importlib

__version__ = "0.1.0"

_API = {
    "physical_consistency": "inertiaproof.model.consistency",
    "pseudo_inertia": "inertiaproof.model.inertia",
    "spatial_inertia": "inertiaproof.model.inertia",
    "Chain": "inertiaproof.dynamics.chain",
    "Joint": "inertiaproof.dynamics.chain",
    "mass_matrix": "inertiaproof.dynamics.composite",
    "load_scene": "inertiaproof.scene.format",
    "audit_urdf": "inertiaproof.audit.api",
    "payload_envelope": "inertiaproof.cli.envelope",
    "run_checks": "inertiaproof.suite.runner",
}
__all__ = ["__version__", *_API]


def __getattr__(name):
    if name in _API:
        value = getattr(importlib.import_module(_API[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'inertiaproof' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_API))
