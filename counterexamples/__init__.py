"""Hypothesis strategies, one module per kind of random object (installed as inertiaproof.counterexamples)."""
