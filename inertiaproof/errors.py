"""Errors that reach the user as one line naming the problem (exit status 2)."""


class InputError(ValueError):
    """Bad input: a file, a field or an argument that cannot be used."""
