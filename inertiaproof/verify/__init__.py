"""The independent checker: re-proves the claims of inertiaproof's certificates in ball arithmetic.

It imports nothing of inertiaproof and no numerical library but python-flint (arb balls, exact
rationals) and the standard library, so that a certified number can be trusted without trusting the
prover (the de Bruijn criterion; compare DRAT-trim for SAT proofs). ``inertiaproof verify --about``
prints its size.

- :mod:`.exact`: numbers of a certificate as exact rationals, and balls around them;
- :mod:`.kinematics`: a chain, and M(q, Theta) + shift I proved positive definite over a box of
  configurations by the pivots of its LDL^T from the tip (articulated-body inertias in the Loewner order);
- :mod:`.claims`: what each kind of claim means, and its proof by branch and bound over a box tree;
- :mod:`.cli`: ``inertiaproof verify PATH ...``.
"""
