"""The exceptions mx raises.

Every error from the interpreter or the engine is an :class:`MxError`; the
subclasses also derive from the matching built-in exception, so ``except
ValueError`` catches a wrong array shape and ``except OSError`` a missing file.
"""

from typing import Optional, Tuple


class MxError(Exception):
    """An mx diagnostic.

    ``str(e)`` is the rendered diagnostic (message, the source line with the
    offending span underlined, help). The parts are also attributes:

    - ``message``: the one-line message
    - ``diagnostic``: the rendered diagnostic (same as ``str(e)``)
    - ``kind``: ``"syntax"``, ``"type"``, ``"value"``, ``"motion"``, ``"io"``…
    - ``file``, ``line``, ``column``: where in the source (``None`` when the
      error concerns no mx source, e.g. a bad array passed from Python);
      lines and columns count from 1, columns in characters
    - ``end_line``, ``end_column``: where the offending part ends
    - ``span``: ``(start, end)``, the offending part as character offsets
      into the source text (``source[start:end]``)
    - ``help``: the advice line, if any
    """

    def __init__(
        self,
        diagnostic: str,
        message: Optional[str] = None,
        kind: str = "host",
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
        help: Optional[str] = None,
        end_line: Optional[int] = None,
        end_column: Optional[int] = None,
        span: Optional[Tuple[int, int]] = None,
    ):
        super().__init__(diagnostic)
        self.diagnostic = diagnostic
        self.message = message if message is not None else diagnostic
        self.kind = kind
        self.file = file
        self.line = line
        self.column = column
        self.help = help
        self.end_line = end_line
        self.end_column = end_column
        self.span = span


class MxSyntaxError(MxError, SyntaxError):
    """A script that does not parse."""

    def __str__(self) -> str:  # SyntaxError's own __str__ would drop the diagnostic
        return self.diagnostic


class MxNameError(MxError, NameError):
    """An unknown name (the diagnostic suggests the closest known one)."""


class MxTypeError(MxError, TypeError):
    """A value of the wrong type, a wrong number of arguments, a bad dtype."""


class MxValueError(MxError, ValueError):
    """A value out of its domain: wrong array shape, NaN input, a bad option."""


class MxMotionError(MxValueError):
    """Sampling where a motion is undefined or in conflict, a clip outside the span…"""


class MxIOError(MxError, OSError):
    """A file that cannot be read or written, or whose content is malformed."""


class MxLimitError(MxError, RuntimeError):
    """The step budget or the call-depth limit was exhausted."""


class MxCancelledError(MxError):
    """An evaluation cancelled from outside (KeyboardInterrupt is raised for Ctrl-C)."""


# mx error kinds (`ErrorKind::code` without `mx::`) → class.
_BY_KIND = {
    "syntax": MxSyntaxError,
    "unknown_name": MxNameError,
    "type": MxTypeError,
    "arity": MxTypeError,
    "value": MxValueError,
    "division_by_zero": MxValueError,
    "motion": MxMotionError,
    "io": MxIOError,
    "recursion": MxLimitError,
    "step_budget": MxLimitError,
    "cancelled": MxCancelledError,
    "host": MxError,
}


def _make(kind, diagnostic, message, at, help):
    """Called from Rust: the exception object for an mx diagnostic; ``at`` is
    ``(file, line, column, end_line, end_column, (start, end))`` or ``None``."""
    cls = _BY_KIND.get(kind, MxError)
    if at is None:
        return cls(diagnostic, message, kind, help=help)
    file, line, column, end_line, end_column, span = at
    return cls(diagnostic, message, kind, file, line, column, help, end_line, end_column, tuple(span))
