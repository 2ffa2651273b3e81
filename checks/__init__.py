"""One module per result family of the paper; each registers its checks (installed as inertiaproof.checks)."""
