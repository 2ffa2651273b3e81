"""Errors that reach the user as one line naming the problem (exit status 2)."""

import codecs

__all__ = ["InputError", "LARGEST", "numbers", "open_text", "read_text"]

# |x| <= 1e60 keeps every product of five inputs (M(q) sums m |c|^2 terms) finite in float64
LARGEST = 1e60

_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"), (codecs.BOM_UTF8, "utf-8-sig"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"))


class InputError(ValueError):
    """Bad input: a file, a field or an argument that cannot be used."""


def numbers(value, where, shape=None):
    """A float array of finite numbers (of ``shape`` if given), or InputError naming ``where``."""
    import numpy as np

    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: not a list of numbers: {value!r}") from None
    if shape is not None and a.shape != tuple(shape):
        raise InputError(f"{where}: needs shape {tuple(shape)}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{where}: not finite: {a.tolist()}")
    return a


def read_text(path, what="file"):
    """The text of a file: UTF-8, or UTF-8/16/32 with a byte-order mark (which is not part of the text); any other
    bytes are an InputError naming the file and the place."""
    from pathlib import Path

    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read {what}: {exc.strerror or exc}") from None
    encoding = _encoding(data)
    try:
        text = data.decode(encoding)
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise InputError(f"{path}:{line}: not {encoding.upper().removesuffix('-SIG')} text: byte "
                         f"0x{data[exc.start]:02x} at column {column} (save the {what} as UTF-8)") from None
    return text


def open_text(path, what="file"):
    """A text handle on a file for reading as it goes (universal newlines left to the reader: ``newline=""``), in
    the encoding its byte-order mark names (else UTF-8). A decoding error met while reading is located by
    :func:`read_text` (call it on the UnicodeDecodeError)."""
    from pathlib import Path

    path = Path(path)
    try:
        with path.open("rb") as handle:
            head = handle.read(4)
        return path.open(encoding=_encoding(head), newline="")
    except OSError as exc:
        raise InputError(f"{path}: cannot read {what}: {exc.strerror or exc}") from None


def _encoding(head):
    """The encoding a file's first bytes name by their byte-order mark, else UTF-8."""
    return next((name for bom, name in _BOMS if head.startswith(bom)), "utf-8")
