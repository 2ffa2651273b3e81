"""Section 4: extremes of M(q, Theta), QJ and the skew partials over configurations and time, and the constants
of Theorems 2-5.

- ``domain``: the configuration box and where certification stops
- ``lengths``: what the link lengths bound for every q (columns of QJ), and unit bodies (Z = I)
- ``spectral``: spectral functions and their convexity
- ``extremes``: two-sided brackets of an extreme (a certified side and a side attained at a witness)
- ``configuration``: the quantities over configurations (Definition 2, Theorems 2-4): a bracket, then its strategies
- ``strategies``: the declared strategies that tighten a bracket, their ordered registry and the loop that runs them
- ``families``: the matrix families QJ, M(q, Theta), the skew partials, and vertex bounds on a box
- ``branch``: branch and bound over configurations (vertex and Taylor box bounds), the first certified side
- ``apriori``: certified bounds from link lengths alone (a-priori sups, the block-triangular floor)
- ``ladders``: pivot ladders on lower forms of M and on gamma I - M; ``block_form``, ``axial_form``: the forms
- ``perron``: Perron-Frobenius bounds from M's exact Fourier coefficients; ``skew``: Theorem 5's skew partials
- ``memo``: the one content-keyed memo of proofs and the values they rest on
- ``certificate``, ``written``: the certificates for the independent checker, and the chain as they write it
- ``taylor``: certified bounds of lambda_min / lambda_max / |lambda|_max of M on a box, polynomial in the joints
  (:func:`inertiaproof.bounds.taylor.certified_box_bound` for one box)
- ``time``: extremes over the parameter trajectory (Definition 3)
- ``constants``: alpha1, alpha2 (Theorems 2, 3) and the entry point for audits
- ``singular``: can M(q) become singular? A structural answer where one exists
"""
