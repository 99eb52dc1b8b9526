"""Error messages for the dialect parsers: locations, carets and what was expected.

Lark reports the *terminals* it expected (``LPAR``, ``NEG_NUMBER`` …); :func:`describe_expected`
turns such a set into the words a user understands ("an expression or ')'").
"""

from __future__ import annotations

from collections.abc import Iterable

from ...errors import LSystemSemanticError, LSystemSyntaxError

__all__ = ["Where", "describe_expected", "join_words"]

_OPERATORS = frozenset(
    {"OROR", "ANDAND", "EQ", "NE", "LE", "GE", "SHL", "SHR"}
    | {"PLUS", "MINUS", "POW", "STAR", "SLASH", "PERCENT"}
)
_OPERAND = frozenset({"NUMBER", "NEG_NUMBER", "NAME"})

# (terminal, words), in the order the words are listed in a message
_WORDS: tuple[tuple[str, str], ...] = (
    ("SYMBOL", "a module"),
    ("LSQB", "'['"),
    ("RSQB", "']'"),
    ("LPAR", "'('"),
    ("NAME", "a parameter name"),
    ("COMMA", "','"),
    ("RPAR", "')'"),
    ("LT", "'<'"),
    ("GT", "'>'"),
    ("COLON", "':'"),
    ("ARROW", "an arrow '->' or '->>'"),
    ("$END", "the end of the line"),
)


def join_words(words: Iterable[str]) -> str:
    """``a, b or c``."""
    words = list(dict.fromkeys(words))
    if not words:
        return "nothing"
    if len(words) == 1:
        return words[0]
    return ", ".join(words[:-1]) + " or " + words[-1]


def describe_expected(expected: Iterable[str]) -> str:
    """Human words for a set of expected Lark terminal names.

    >>> describe_expected({"NUMBER", "NEG_NUMBER", "NAME", "LPAR", "MINUS", "BANG", "RPAR"})
    "an expression or ')'"
    >>> describe_expected({"PLUS", "MINUS", "STAR", "COMMA", "RPAR", "LT", "POW"})
    "an operator, ',' or ')'"
    """
    exp = set(expected)
    words: list[str] = []
    operand = bool(exp & _OPERAND) and "NUMBER" in exp
    if operand:
        words.append("an expression")
        exp -= _OPERAND | {"MINUS", "BANG", "PLUS", "LPAR"}
    elif exp & _OPERATORS:
        words.append("an operator")
        exp -= _OPERATORS
        # '<' and '>' are comparison operators in an expression
        if "COMMA" in exp or "RPAR" in exp or "ARROW" in exp:
            exp -= {"LT", "GT"}
    exp.discard("QUERY")
    if "LONGNAME" in exp:
        exp.discard("LONGNAME")
        exp.add("SYMBOL")
    if "RARROW" in exp:
        exp.discard("RARROW")
        exp.add("ARROW")
    for term, text in _WORDS:
        if term in exp:
            words.append(text)
            exp.discard(term)
    words.extend(sorted(f"'{t}'" if len(t) == 1 else t.lower() for t in exp))
    return join_words(words)


class Where:
    """The place a parser is reading: text, line number and file name.

    Builds errors that quote the line and put a caret under the column.
    """

    __slots__ = ("filename", "line", "lineno")

    def __init__(self, line: str, lineno: int, filename: str | None = None) -> None:
        self.line = line
        self.lineno = lineno
        self.filename = filename

    def error(self, message: str, column: int, *, semantic: bool = False) -> LSystemSyntaxError:
        cls = LSystemSemanticError if semantic else LSystemSyntaxError
        return cls(
            message,
            filename=self.filename,
            line=self.lineno,
            column=max(int(column), 1),
            source_line=self.line,
        )

    def semantic(self, message: str, column: int) -> LSystemSemanticError:
        err = self.error(message, column, semantic=True)
        assert isinstance(err, LSystemSemanticError)
        return err

    def end_column(self) -> int:
        """The column just after the last character that is not a comment or a space."""
        return content_length(self.line) + 1


def content_length(line: str, comment: str = "#") -> int:
    """Length of ``line`` without its comment (outside double quotes) and trailing spaces."""
    quoted = False
    end = len(line)
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == comment and not quoted:
            end = i
            break
    return len(line[:end].rstrip())


def char_symbols(
    text: str, offset: int, where: Where, what: str, comment: str, dialect: str = "this"
) -> list[tuple[str, int]]:
    """The one-character symbols of ``text`` (spaces dropped) with their 1-based columns.

    Used by the one-character dialects (seed 000 and seed 004); ``comment`` is the
    dialect's comment character, named in the error for a character that cannot be a
    symbol.  Brackets must balance.  ``?P`` ``?H`` ``?U`` ``?L`` ``?E`` written together
    are query and communication modules, which these dialects do not have: an error naming
    ``dialect``.
    """
    out = []
    depth: list[int] = []
    for i, ch in enumerate(text):
        if ch.isspace():
            continue
        col = offset + i + 1
        if ch == '"' or not ch.isprintable():
            raise where.error(
                f"{ch!r} cannot be a symbol; expected a printable character other than "
                f"'\"' and '{comment}'",
                col,
            )
        if ch == "?" and text[i + 1 : i + 2] in ("P", "H", "U", "L", "E"):
            raise where.error(
                f"{text[i:i + 2]!r} is a "
                + ("communication module (open L-systems)" if text[i + 1] == "E"
                   else "query module")
                + f" of cpfg and .lsys, which the {dialect} "
                "format does not have; expected one-character symbols (write "
                f"'? {text[i + 1]}' for the two symbols, or use the .lsys or cpfg language)",
                col,
            )
        if ch == "[":
            depth.append(col)
        elif ch == "]":
            if not depth:
                raise where.semantic(f"unmatched ']' in {what}; expected a '[' before it", col)
            depth.pop()
        out.append((ch, col))
    if depth:
        raise where.semantic(f"unclosed '[' in {what}; expected a matching ']'", depth[-1])
    return out
