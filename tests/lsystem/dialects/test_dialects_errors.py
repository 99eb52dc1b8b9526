"""Broken inputs: each error names the file, line and column, quotes the line with a caret and
says what was expected."""

from __future__ import annotations

import pytest

from sylva.errors import LSystemSemanticError, LSystemSyntaxError, SylvaError
from sylva.lsystem.dialects import load, loads, parse_expr, parse_rule, parse_word

# (dialect, text, line, column, exception class, words the message must hold)
CASES = [
    ("lsys", "axiom = F\nF -> F[+F", 2, 7, LSystemSemanticError, "unclosed '['"),
    ("lsys", "axiom = F]", 1, 10, LSystemSemanticError, "unmatched ']' in the axiom"),
    ("lsys", "axiom = F\nA[B] < C -> D", 2, 2, LSystemSemanticError, "left context cannot"),
    ("lsys", "axiom = F\n[ -> F", 2, 1, LSystemSemanticError, "cannot be a predecessor"),
    ("lsys", "axiom = F\nF -> [(2)F]", 2, 7, LSystemSemanticError, "cannot have parameters"),
    ("lsys", "axiom = F\n[(x) -> F", 2, 1, LSystemSemanticError, "cannot be a predecessor"),
    ("lsys", "axiom = F\nA -> B(x)", 2, 8, LSystemSemanticError, "unknown variable 'x'"),
    ("lsys", "rot = 30\n\nbg = 1, 0", 3, 9, LSystemSemanticError, "expected 3 components"),
    ("lsys", "rot = 30\nF -> FF", 2, 1, LSystemSemanticError, "no axiom"),
    ("lsys", "axiom = F\nF -> FF\nrot = 3", 3, 1, LSystemSyntaxError, "after the rules"),
    ("lsys", "axiom = F\nA -> B(1,", 2, 10, LSystemSyntaxError, "expected an expression"),
    ("lsys", "axiom = F\nF -> F<", 2, 7, LSystemSyntaxError, "unexpected '<'; expected a module"),
    ("lsys", "axiom = F\nF(x : x > 1 -> G", 2, 5, LSystemSyntaxError, "expected ',' or ')'"),
    ("lsys", "axiom = F\n  A(x) : x >> -> B", 2, 16, LSystemSyntaxError, "expected an expression"),
    ("lsys", 'axiom = F\nA -> "leaf', 2, 6, LSystemSyntaxError, "unterminated quoted name"),
    ("lsys", "a = 1\na = 2\naxiom = F", 2, 1, LSystemSemanticError, "already assigned on line 1"),
    ("lsys", "axiom = F\nA(x) -> B(foo(x))", 2, 11, LSystemSemanticError, "unknown function 'foo'"),
    ("lsys", "axiom = F\nA(x) -> B(sqrt(x, 2))", 2, 11, LSystemSemanticError, "1 argument"),
    ("lsys", "axiom = F\nA(x, x) -> B", 2, 6, LSystemSemanticError, "bound twice"),
    ("lsys", "turtle = logo\naxiom = F", 1, 10, LSystemSemanticError, "expected lsys, abop"),
    ("lsys", "steps = 2.5\naxiom = F", 1, 9, LSystemSemanticError, "whole number"),
    ("lsys", "axiom = F\nAB -> C", 2, 2, LSystemSyntaxError, "predecessor is one module"),
    ("lsys", "axiom = F\nA(1) -> C", 2, 3, LSystemSyntaxError, "expected a parameter name"),
    ("lsys", "x = rot\naxiom = F", 1, 5, LSystemSemanticError, "special variable"),
    ("lsys", "y = 1\nx = y + z\naxiom = F", 2, 9, LSystemSemanticError, "known here: y"),
    ("lsys", "ignore = [\naxiom = F", 1, 10, LSystemSemanticError, "cannot be ignored"),
    ("lsys", "axiom =", 1, 8, LSystemSyntaxError, "the axiom is empty"),
    ("lsys", "axiom = F\nA > -> B", 2, 3, LSystemSyntaxError, "empty right context"),
    ("lsys", "axiom = F\n< A -> B", 2, 1, LSystemSyntaxError, "empty left context"),
    ("lsys", "axiom = F\nA -> B\nA", 3, 2, LSystemSyntaxError, "an arrow '->'"),
    ("lsys", "x = 1/0\naxiom = F", 1, 5, LSystemSemanticError, "expected a finite number"),
    ("lsys", "axiom = F\nA ->(2 B", 2, 8, LSystemSyntaxError, "expected an operator or ')'"),
    ("lsys", "axiom = F\nA -> B=C", 2, 7, LSystemSyntaxError, 'write it quoted, "="'),
    ("lsys", 'axiom = ""', 1, 9, LSystemSyntaxError, "empty quoted name"),
    ("lsys", "axiom = F\n A -> B )", 2, 9, LSystemSyntaxError, "unexpected ')'"),
    ("lsys", "axiom = F\nA => B", 2, 3, LSystemSyntaxError, "'=>' is not an arrow"),
    ("lsys", "axiom F", 1, 7, LSystemSyntaxError, "expected '=' after 'axiom'"),
    ("lsys", "axiom: F", 1, 6, LSystemSyntaxError, "expected '=' after 'axiom'"),
    ("lsys", "axiom = F\nA(x) : x = 1 -> B", 2, 10, LSystemSyntaxError, "'=='"),
    ("lsys", "axiom = F(1  # comment", 1, 12, LSystemSyntaxError, "expected ',' or ')'"),
    ("lsys", "axiom = F\nA(x y) -> B", 2, 5, LSystemSyntaxError, "expected ',' or ')'"),
    (
        "classic",
        "iteration: 2\nangle: 90\naxiom: A\nrule: A => B",
        4,
        9,
        LSystemSyntaxError,
        "expected '->'",
    ),
    ("classic", "iteration: two", 1, 12, LSystemSyntaxError, "whole number"),
    ("classic", "angle: 1\nangle: 2\naxiom: A", 2, 1, LSystemSemanticError, "already given"),
    ("classic", "axiom: A\nrule A -> B", 2, 5, LSystemSyntaxError, "expected ':' after 'rule'"),
    ("classic", "axiom: A\nrules: A -> B", 2, 1, LSystemSyntaxError, "unknown keyword 'rules'"),
    ("classic", "axiom: A\nrule: A -> B]", 2, 13, LSystemSemanticError, "unmatched ']'"),
    ("classic", "angle: 9O\naxiom: A", 1, 8, LSystemSyntaxError, "expected a number"),
    ("classic", "iteration: 3", 1, 1, LSystemSemanticError, "no axiom"),
    ("engine", "45 45 0.8\nX\nX > F]", 3, 6, LSystemSemanticError, "unmatched ']'"),
    ("engine", "# only\nX\n", 2, 1, LSystemSyntaxError, "expected a header line"),
    ("engine", "1 2 3\n1 2 3\n", 2, 1, LSystemSyntaxError, "expected the axiom"),
    ("engine", "1 2 3\nX\nX = F", 3, 1, LSystemSyntaxError, "expected a production"),
    ("engine", "1 2 3\n", 1, 1, LSystemSemanticError, "ends before the axiom"),
    ("engine", "1 2 3\nX\n[ > F", 3, 1, LSystemSemanticError, "cannot be a predecessor"),
]


@pytest.mark.parametrize(("dialect", "text", "line", "column", "cls", "words"), CASES)
def test_error_location_and_message(dialect, text, line, column, cls, words):
    with pytest.raises(cls) as info:
        loads(text, dialect=dialect, filename="broken.txt")
    e = info.value
    assert isinstance(e, SylvaError) and isinstance(e, ValueError)
    assert (e.filename, e.line, e.column) == ("broken.txt", line, column)
    assert words in e.message
    assert "expected" in e.message or "no axiom" in e.message or "cannot" in e.message
    # the message quotes the line and puts a caret under the column
    src = text.splitlines()[line - 1]
    shown = str(e).splitlines()
    assert shown[0].startswith(f"broken.txt:{line}:{column}: ")
    assert shown[1] == "    " + src
    assert shown[2] == "    " + " " * (column - 1) + "^"


def test_error_without_filename_says_string():
    with pytest.raises(LSystemSyntaxError) as info:
        loads("axiom = F\nF -> F[")
    assert str(info.value).startswith("<string>:2:7: ")


def test_errors_from_a_file_carry_its_path(tmp_path):
    path = tmp_path / "plant.lsys"
    path.write_text("axiom = F\nF -> F[+F\n", encoding="utf-8")
    with pytest.raises(LSystemSemanticError) as info:
        load(path)
    assert info.value.filename == str(path) and info.value.line == 2
    with pytest.raises(LSystemSemanticError) as info:
        load(str(path))
    assert info.value.filename == str(path)


def test_helpers_raise_located_errors():
    with pytest.raises(LSystemSyntaxError) as info:
        parse_expr("1 +", filename="cli")
    assert (info.value.line, info.value.column, info.value.filename) == (1, 4, "cli")
    assert "expected an expression" in info.value.message
    with pytest.raises(LSystemSyntaxError, match="expected a rule"):
        parse_rule("x = 1")
    with pytest.raises(LSystemSemanticError, match="unknown variable 'y'"):
        parse_rule("A(x) -> B(y)", constants={"z": 1.0})
    assert parse_rule("A(x) -> B(y)").successor[0].args[0].name == "y"  # unchecked
    with pytest.raises(LSystemSemanticError, match="unclosed"):
        parse_word("F[")
    with pytest.raises(LSystemSyntaxError, match="one line"):
        parse_word("F\nG")
    with pytest.raises(LSystemSemanticError, match="unknown variable"):
        parse_word("F(x)", evaluate=True)


def test_deep_nesting_is_an_error_not_a_crash():
    with pytest.raises(LSystemSemanticError, match="nested too deeply") as info:
        loads("x = " + "-" * 5000 + "1\naxiom = F")
    assert (info.value.line, info.value.column) == (1, 5)
    deep = loads("x = " + "(" * 3000 + "1" + ")" * 3000 + "\naxiom = F")
    assert deep.constants == {"x": 1.0}
