"""Symbolic re-derivations with SymPy (installed as inertiaproof.symbolic)."""
