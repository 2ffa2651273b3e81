"""inertiaproof: proof-checking 'On robotic manipulators with time-dependent inertial parameters'.

The shared physical model lives here (inertia, consistency, chain, dynamics,
trajectory, scene, solids, robots); the paper's results are checked by the
subpackages ``inertiaproof.symbolic``, ``inertiaproof.checks``,
``inertiaproof.counterexamples`` and presented by ``inertiaproof.report``.
"""

__version__ = "0.1.0"
