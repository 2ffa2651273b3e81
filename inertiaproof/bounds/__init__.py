"""Section 4: extremes of M(q, Theta), QJ and the skew partials over configurations and time, and the constants
of Theorems 2-5.

- ``domain``: the configuration box and where certification stops
- ``lengths``: what the link lengths bound for every q (columns of QJ), and unit bodies (Z = I)
- ``spectral``: spectral functions and their convexity
- ``extremes``: two-sided brackets of an extreme (a certified side and a side attained at a witness)
- ``configuration``: brackets over configurations (a-priori bounds, Taylor bounds, branch and bound)
- ``taylor``: certified bounds of lambda_min / lambda_max / |lambda|_max of M on a box, polynomial in the joints
  (:func:`inertiaproof.bounds.taylor.certified_box_bound` for one box)
- ``time``: extremes over the parameter trajectory (Definition 3)
- ``constants``: alpha1, alpha2 (Theorems 2, 3) and the entry point for audits
- ``singular``: can M(q) become singular? A structural answer where one exists
"""
