"""Simulation of the generalized robotics equation and the studies built on it (GRE-physics, stability).

- ``control``: controllers tracking a reference motion with nominal parameters
- ``simulate``: forward dynamics with SciPy's solve_ivp and the power balance of Prop1
- ``capture``: loading as the limit of many small plastic captures
- ``study``: error against run time and stability of solve_ivp's methods
- ``multibody``, ``crosscheck``, ``similarity``: the moving mass as its own body in Pinocchio; round-off by units
"""
