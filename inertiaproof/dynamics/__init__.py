"""Kinematic chains and the terms of the generalized robotics equation (RoboticEquation).

- ``twists``, ``chain``: serial chains, the stacked body-twist Jacobian QJ and dQJ/dq
- ``terms``: M (MassMatrix), C (DefCoriolis), G (DefGravitation), H (DefH), J^T Q^T Psidot, literally
- ``composite``: M(q, Theta) by composite rigid bodies (the fast path)
- ``regressors``: R_l and R_M,l (RoboticRegressor, RoboticRegressorVel)
- ``trajectory``: Theta(t), Thetadot(t), Psi(t) of payloads, scalings and moving masses
- ``energy``, ``motion``: energies and the power balance; the terms along a motion
"""
