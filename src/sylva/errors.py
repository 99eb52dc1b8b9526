"""Errors raised by sylva.

Every error a user can cause derives from :class:`SylvaError`.  Errors about text carry the
file name, the 1-based line and column, the offending source line and a caret, and say what
was expected, so that the command line can print them without a traceback.
"""

from __future__ import annotations

__all__ = [
    "GrowthLimitError",
    "LSystemSemanticError",
    "LSystemSyntaxError",
    "StepsError",
    "SylvaError",
    "SylvaWarning",
]


class SylvaError(Exception):
    """Root of every error sylva raises on bad input or exhausted limits."""

    def _render_traceback_(self) -> list[str]:
        # IPython and Jupyter show this instead of a traceback: bad input is the user's to
        # fix, and the message says what was expected (as the command line's one line does)
        return [f"\x1b[31m{type(self).__name__}\x1b[0m: {self}"]


def _located(
    message: str,
    filename: str | None,
    line: int | None,
    column: int | None,
    source_line: str | None,
) -> str:
    """``file:line:column: message``, then the source line and a caret under the column."""
    where = filename or "<string>"
    if line is not None:
        where += f":{line}"
        if column is not None:
            where += f":{column}"
    text = f"{where}: {message}"
    if source_line is not None:
        src = source_line.rstrip("\r\n").expandtabs(1)
        text += "\n    " + src
        if column is not None:
            text += "\n    " + " " * max(column - 1, 0) + "^"
    return text


class LSystemSyntaxError(SylvaError, ValueError):
    """Text that does not parse, with its location.

    Parameters
    ----------
    message : str
        What went wrong and what was expected.
    filename : str, optional
        The file the text came from (``"<string>"`` when it came from a string).
    line, column : int, optional
        1-based position of the error.
    source_line : str, optional
        The text of the line, shown with a caret under ``column``.
    """

    def __init__(
        self,
        message: str,
        *,
        filename: str | None = None,
        line: int | None = None,
        column: int | None = None,
        source_line: str | None = None,
    ) -> None:
        self.message = message
        self.filename = filename or "<string>"
        self.line = line
        self.column = column
        self.source_line = source_line
        super().__init__(self._format())

    def _format(self) -> str:
        return _located(self.message, self.filename, self.line, self.column, self.source_line)

    @classmethod
    def at(
        cls,
        message: str,
        text: str,
        line: int,
        column: int,
        filename: str | None = None,
    ) -> LSystemSyntaxError:
        """Build an error at ``line``/``column`` of ``text``, quoting that line."""
        lines = text.splitlines()
        src = lines[line - 1] if 0 < line <= len(lines) else None
        return cls(message, filename=filename, line=line, column=column, source_line=src)


class LSystemSemanticError(LSystemSyntaxError):
    """Text that parses but means nothing valid (an unknown variable, a missing axiom …)."""


class GrowthLimitError(SylvaError):
    """A derivation would pass the module or memory limit.

    The word derived before the limit was hit is kept in :attr:`word` (it may be ``None``
    when the very first step is too large), and :attr:`step` says how many steps it holds.
    """

    def __init__(self, message: str, *, word=None, step: int | None = None) -> None:
        self.word = word
        self.step = step
        super().__init__(message)


class StepsError(GrowthLimitError):
    """A number of derivation steps refused before any step is derived.

    Either more than :data:`~sylva.lsystem.ast.MAX_STEPS`, or more steps than the word can
    take before it passes the module limit.  :attr:`fits` is an upper bound on the steps that
    can be derived under the limit (``None`` when only the maximum was passed).  When the
    count came from a file, the message names its file, line and column.
    """

    def __init__(
        self,
        message: str,
        *,
        fits: int | None = None,
        filename: str | None = None,
        line: int | None = None,
        column: int | None = None,
        source_line: str | None = None,
    ) -> None:
        self.message = message
        self.fits = fits
        self.filename = filename
        self.line = line
        self.column = column
        if line is not None:
            message = _located(message, filename, line, column, source_line)
        super().__init__(message, word=None, step=0)


class SylvaWarning(UserWarning):
    """Input that sylva reads but cannot honour in full (a setting it does not draw)."""
