"""The HTML and LaTeX report (installed as inertiaproof.report)."""
