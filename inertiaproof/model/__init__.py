"""The physical model of one rigid body: inertial parameters and what a body can have.

- ``inertia``: Phi = (m, h, I), the pseudo-inertia f(Phi) (DefTrafoInertialParameters), Z(Phi) (DefMatrixZ)
- ``consistency``, ``exact``: physical consistency (Definition 1, Theorem 1), decided exactly where floats cannot
- ``solids``, ``density``, ``quadrature``: mass densities and their moments (MassDistributionToInertialParam)
- ``degenerate``, ``realise``: point, line and planar masses; a density realising any f(Phi) > 0
- ``particles``: a body's density as weighted particles (Section 3's integrals)
- ``positive_map``: the linear map f(Phi) -> Z(Phi) and certificates of its positivity (Theorems 2-4)
- ``rows``: rows of inertial parameters read from CSV or JSON
"""
