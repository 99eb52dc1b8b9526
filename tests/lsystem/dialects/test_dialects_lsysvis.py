"""The LSysVis language against the examples of seed 001 (§2–§3, §8.3 test cases T1–T15)."""

from __future__ import annotations

import pytest

from sylva.errors import LSystemSemanticError, LSystemSyntaxError
from sylva.lsystem.ast import Binary, Call, Module, Num, Pattern, Program, Span, Unary, Var
from sylva.lsystem.dialects import loads, parse_expr, parse_rule, parse_word
from sylva.lsystem.dialects.lsysvis import parse

SOURCE_CODE_1 = """\
# priklad jednoducheho L-systemu

rot = 30          # prirazeni hodnoty promenne
axiom = F        # prirazeni hodnoty promenne

F -> F[+F][-F]F  # prepisovaci pravidlo
"""

SOURCE_CODE_2 = """\
bg = 1, 1, 1
rot = 35
color = 0.4, 0.2, 0.1

axiom = X

X -> F[+X]F[-X]+(20)X
F -> FF

X ->> ; (0,0.7,0)F
"""

# Theory examples of §8.3 in LSysVis syntax: (text, predecessors in order).
THEORY = {
    "T1": "axiom = a\na -> b\nb -> aa",
    "T2": "axiom = a\na -> b\na ->(3) c",
    "T3": "axiom = baaaaa\nb < a -> ab\nb ->\naaaaa < b -> x",
    "T4": "ignore = i\naxiom = xia\nx < a -> b",
    "T5": "axiom = fk(3)la(8, 9, 10)m(4, 5)n\nk(x)l < a(y, z) -> b(x + y)c(x)d",
    "T6": "axiom = a(3)\na(x) -> a(x - 1)\na(x) : x == 0 -> c",
    "T8": "axiom = a[bc]d[e[f][g]h]i\ne -> x[y]z",
    "T9": "axiom = a[bc]d[e[f][g]h]i\na d e < h -> X",
    "T11": "axiom = l\nl ->> [-F+F+F-|-F+F+F]",
    "T15": "rot = 30\naxiom = F\nF -> F[+F][-F]F",
}

T10_RULES = [
    "a > di -> x",
    "a > [b] -> x",
    "a > [bc] -> x",
    "a > [b]d[e] -> x",
    "a > [b]d[e]i -> x",
    "a > d[eh]i -> x",
    "a > d[e[f][g]] -> x",
]


def M(symbol, *args):
    return Module(symbol, tuple(Num(float(a)) for a in args))


def P(symbol, *params):
    return Pattern(symbol, tuple(params))


def V(name):
    return Var(name)


def symbols(word):
    return [m.symbol for m in word]


# --------------------------------------------------------------------------- file structure
def test_source_code_1():
    p = parse(SOURCE_CODE_1, "source1.lsys")
    assert p.settings == {"rot": 30.0}
    assert p.axiom == (M("F"),)
    (rule,) = p.rules
    assert rule.predecessor == P("F")
    assert symbols(rule.successor) == list("F[+F][-F]F")
    assert rule.span == Span(6, 1, "source1.lsys")
    assert p.name == "source1" and p.filename == "source1.lsys" and p.dialect == "lsys"


def test_source_code_2_t14():
    p = parse(SOURCE_CODE_2)
    assert p.settings == {"bg": (1.0, 1.0, 1.0), "rot": 35.0, "color": (0.4, 0.2, 0.1)}
    assert p.axiom == (M("X"),)
    x, f, render = p.rules
    assert symbols(x.successor) == list("F[+X]F[-X]+X")
    assert x.successor[10] == M("+", 20)
    assert f.successor == (M("F"), M("F"))
    assert render.render and not x.render
    assert render.successor == (M(";", 0, 0.7, 0), M("F"))
    assert p.productions == (x, f) and p.render_rules == (render,)
    assert [r.span.line for r in p.rules] == [7, 8, 10]


@pytest.mark.parametrize("case", sorted(THEORY))
def test_theory_examples_parse(case):
    p = loads(THEORY[case])
    assert isinstance(p, Program) and p.axiom


def test_t2_weight_and_t3_empty_successor_and_contexts():
    t2 = loads(THEORY["T2"])
    assert [r.weight for r in t2.rules] == [Num(1.0), Num(3.0)]
    t3 = loads(THEORY["T3"])
    assert t3.rules[0].left == (P("b"),) and t3.rules[0].predecessor == P("a")
    assert t3.rules[1].successor == ()
    assert t3.rules[2].left == tuple(P("a") for _ in range(5))
    assert [r.tier for r in t3.rules] == [1, 2, 1]


def test_t4_ignore_and_t5_bindings():
    assert loads(THEORY["T4"]).ignore == {"i"}
    t5 = loads(THEORY["T5"])
    assert t5.axiom[1] == M("k", 3) and t5.axiom[3] == M("a", 8, 9, 10)
    (r,) = t5.rules
    assert r.left == (P("k", "x"), P("l")) and r.predecessor == P("a", "y", "z")
    assert r.successor == (
        Module("b", (Binary("+", V("x"), V("y")),)),
        Module("c", (V("x"),)),
        Module("d"),
    )


def test_t6_condition():
    r = loads(THEORY["T6"]).rules[1]
    assert r.condition == Binary("==", V("x"), Num(0.0)) and r.tier == 0


def test_t9_left_context_with_spaces():
    assert loads(THEORY["T9"]).rules[0].left == (P("a"), P("d"), P("e"))


@pytest.mark.parametrize("rule", T10_RULES)
def test_t10_right_contexts_with_lateral_subtrees(rule):
    r = parse_rule(rule)
    assert r.predecessor == P("a") and r.successor == (M("x"),)
    assert "".join(p.symbol for p in r.right) == rule.split(">")[1].split("-")[0].strip()


def test_t12_parses_to_six_symbols():
    word = parse_word('a"jmeno1"[b(5, 6)"dlouhe_jmeno"(9.5, -4)]')
    assert word == (
        M("a"),
        M("jmeno1"),
        M("["),
        M("b", 5, 6),
        M("dlouhe_jmeno", 9.5, -4),
        M("]"),
    )


def test_t13_exact_structure():
    r = parse_rule('H(x, foo) IJ < A(y) > K"el"(z) : x+y>0 || foo -> X(1)Y(y*sin(z))Z')
    assert r.left == (P("H", "x", "foo"), P("I"), P("J"))
    assert r.predecessor == P("A", "y")
    assert r.right == (P("K"), P("el", "z"))
    assert r.condition == Binary("||", Binary(">", Binary("+", V("x"), V("y")), Num(0.0)), V("foo"))
    assert r.successor == (
        M("X", 1),
        Module("Y", (Binary("*", V("y"), Call("sin", (V("z"),))),)),
        M("Z"),
    )
    assert r.weight == Num(1.0) and not r.render and r.tier == 0


@pytest.mark.parametrize(
    ("line", "left", "pred", "right", "succ", "has_condition"),
    [
        ("A ->", "", "A", "", "", False),
        ('A -> BC"modul_XY"', "", "A", "", "B C modul_XY", False),
        ("L < A -> B", "L", "A", "", "B", False),
        ("A > P -> B", "", "A", "P", "B", False),
        ("L < A > P -> B", "L", "A", "P", "B", False),
        ("A(x) : x<=0 -> B", "", "A", "", "B", True),
        ("A(x) > P : x<=0 -> B", "", "A", "P", "B", True),
    ],
)
def test_extra_parsing_rules(line, left, pred, right, succ, has_condition):
    r = parse_rule(line)
    assert "".join(p.symbol for p in r.left) == left
    assert r.predecessor.symbol == pred
    assert "".join(p.symbol for p in r.right) == right
    assert [m.symbol for m in r.successor] == succ.split()
    assert (r.condition is not None) == has_condition


def test_extra_parsing_assignments():
    p = loads('var_1 = 42.1\nbg = 0.6, 0.7, 0.8\nignore = AB"modul_XY"C\naxiom = AB(3)C(5)\n')
    assert p.constants == {"var_1": 42.1}
    assert p.settings == {"bg": (0.6, 0.7, 0.8)}
    assert p.ignore == {"A", "B", "modul_XY", "C"}
    assert p.axiom == (M("A"), M("B", 3), M("C", 5))


def test_bg_and_color_are_clamped_but_not_color_delta():
    p = loads("bg = 2, -1, 0.5\ncolor = 1.5, 0.5, -3\ncolor_delta = -0.1, 2, 0\naxiom = F")
    assert p.settings["bg"] == (1.0, 0.0, 0.5)
    assert p.settings["color"] == (1.0, 0.5, 0.0)
    assert p.settings["color_delta"] == (-0.1, 2.0, 0.0)


def test_only_axiom_is_a_valid_file():
    p = loads("axiom = F")
    assert p.axiom == (M("F"),) and p.rules == () and p.settings == {} and p.constants == {}


def test_missing_axiom_is_an_error():
    with pytest.raises(LSystemSemanticError, match="no axiom") as info:
        loads("rot = 30\nF -> FF\n", filename="plant.lsys")
    assert info.value.filename == "plant.lsys" and info.value.line == 2
    with pytest.raises(LSystemSemanticError, match="no axiom"):
        loads("# nothing here\n\n")


def test_assignment_after_rule_is_an_error():
    with pytest.raises(LSystemSyntaxError, match="after the rules") as info:
        loads("axiom = F\nF -> FF\n\nrot = 30\n")
    assert (info.value.line, info.value.column) == (4, 1)
    assert "line 2" in info.value.message


# --------------------------------------------------------------------------- variables
def test_table_1_special_variables():
    p = loads(
        "detail = 7.8\nlen = 2\nthick = 0.3\nrot = 25.7\nlen_delta = -0.2\n"
        "thick_delta = -0.05\nrot_delta = 5\ncolor = 0, 0.5, 0\naxiom = F"
    )
    assert p.settings == {
        "detail": 7.8,
        "len": 2.0,
        "thick": 0.3,
        "rot": 25.7,
        "len_delta": -0.2,
        "thick_delta": -0.05,
        "rot_delta": 5.0,
        "color": (0.0, 0.5, 0.0),
    }


def test_user_variables_use_earlier_ones_and_booleans():
    p = loads("a = 2\nb = a * 3 + 1\nflag = True\nno = False\nc = sqrt(b + 0) ** 2\naxiom = F(b)")
    assert p.constants == {"a": 2.0, "b": 7.0, "flag": 1.0, "no": 0.0, "c": pytest.approx(7.0)}
    assert list(p.constants) == ["a", "b", "flag", "no", "c"]
    assert p.axiom == (M("F", 7),)


def test_axiom_parameters_are_evaluated_against_earlier_constants():
    p = loads("w = 0.5\naxiom = A(w * 4, -w)[B(True)]")
    assert p.axiom == (M("A", 2, -0.5), M("["), M("B", 1), M("]"))


def test_rules_may_read_global_variables_and_parameters_shadow_them():
    p = loads("r = 1.5\nx = 3\naxiom = A(1)\nA(x) -> A(x * r)")
    assert p.rules[0].successor[0].args[0] == Binary("*", V("x"), V("r"))


def test_extensions_seed_steps_consider_turtle_and_other_dialect_settings():
    p = loads(
        "seed = 42\nsteps = 5\nconsider = +-F\nturtle = abop\nreduction = 0.9\n"
        "radius = 0.3\nthickness = 2\nyaw = 45\npitch = 30\nshrink = 0.7\naxiom = F"
    )
    assert p.seed == 42 and p.steps == 5
    assert p.consider == {"+", "-", "F"}
    assert p.turtle == "abop"
    assert p.settings == {
        "turtle": "abop",
        "reduction": 0.9,
        "radius": 0.3,
        "thickness": 2.0,
        "yaw": 45.0,
        "pitch": 30.0,
        "shrink": 0.7,
    }
    assert loads("consider =\naxiom = F").consider == frozenset()


def test_detail_is_kept_as_written():
    assert loads("detail = 2.9\naxiom = F").settings["detail"] == 2.9


# --------------------------------------------------------------------------- symbols
def test_abop_characters_are_one_character_modules():
    word = parse_word("{.'%!;,@$|~&^\\/+-}F0")
    assert symbols(word) == list("{.'%!;,@$|~&^\\/+-}F0")


def test_comma_is_a_module_outside_parentheses_and_syntax_inside():
    assert parse_word("F(1, 2),G") == (M("F", 1, 2), M(","), M("G"))


def test_syntax_characters_are_written_quoted():
    word = parse_word('"<"">"":""=""(""#"')
    assert symbols(word) == ["<", ">", ":", "=", "(", "#"]
    assert parse_word('"F"') == parse_word("F")
    r = parse_rule('"<" < ">" -> "="(1)')
    assert r.left == (P("<"),) and r.predecessor == P(">")


def test_an_arrow_is_one_token():
    with pytest.raises(LSystemSyntaxError, match="unexpected '>'") as info:
        parse_rule("a(x) : x > 1 - > b")
    assert info.value.column == 16


def test_whitespace_anywhere_with_a_real_arrow():
    r = parse_rule("  k ( x ) l  <  a ( y , z )  >  m  :  x  >  1  ->(  2  )  b ( x + y ) [ c ]")
    assert r.left == (P("k", "x"), P("l")) and r.predecessor == P("a", "y", "z")
    assert r.right == (P("m"),) and r.weight == Num(2.0)
    assert r.successor == (
        Module("b", (Binary("+", V("x"), V("y")),)),
        M("["),
        M("c"),
        M("]"),
    )


def test_render_rule_with_weight_and_expression_weights():
    r = parse_rule("A ->>(2) B")
    assert r.render and r.weight == Num(2.0)
    r = parse_rule("A(x) ->(x * 2) B")
    assert r.weight == Binary("*", V("x"), Num(2.0))


def test_comment_hash_inside_quotes_is_a_name():
    p = loads('axiom = "a#b" # real comment')
    assert p.axiom == (M("a#b"),)


# --------------------------------------------------------------------------- expressions
@pytest.mark.parametrize(
    ("text", "tree"),
    [
        ("1 + 2 * 3", Binary("+", Num(1.0), Binary("*", Num(2.0), Num(3.0)))),
        ("2 ** 3 ** 2", Binary("**", Num(2.0), Binary("**", Num(3.0), Num(2.0)))),
        ("-x ** 2", Binary("**", Unary("-", V("x")), Num(2.0))),
        ("-2 ** 2", Binary("**", Num(-2.0), Num(2.0))),
        ("- 2", Unary("-", Num(2.0))),
        ("-(2)", Unary("-", Num(2.0))),
        ("x - -1", Binary("-", V("x"), Num(-1.0))),
        ("x -1", Binary("-", V("x"), Num(1.0))),
        ("+x", V("x")),
        ("!a && b || c", Binary("||", Binary("&&", Unary("!", V("a")), V("b")), V("c"))),
        ("a == b < c", Binary("==", V("a"), Binary("<", V("b"), V("c")))),
        ("a << 1 + 2", Binary("<<", V("a"), Binary("+", Num(1.0), Num(2.0)))),
        ("a - b - c", Binary("-", Binary("-", V("a"), V("b")), V("c"))),
        ("a % b / c", Binary("/", Binary("%", V("a"), V("b")), V("c"))),
        (
            "a >= b != c <= d",
            Binary("!=", Binary(">=", V("a"), V("b")), Binary("<=", V("c"), V("d"))),
        ),
        ("(1 + 2) * 3", Binary("*", Binary("+", Num(1.0), Num(2.0)), Num(3.0))),
        (
            "pow(2, sum(1, 2, 3))",
            Call("pow", (Num(2.0), Call("sum", (Num(1.0), Num(2.0), Num(3.0))))),
        ),
        ("True + False", Binary("+", Num(1.0), Num(0.0))),
        (".5e1 + 1. + 2e-3", Binary("+", Binary("+", Num(5.0), Num(1.0)), Num(0.002))),
    ],
)
def test_expression_precedence(text, tree):
    assert parse_expr(text) == tree


def test_variable_spans_point_at_the_name():
    r = parse_rule("A(x) -> B(x + 1)", filename="f.lsys")
    var = r.successor[0].args[0].left
    assert var.span == Span(1, 11, "f.lsys")


# --------------------------------------------------------------------------- size
def test_a_thousand_rules():
    text = "k = 2\naxiom = A(1)\n" + "\n".join(
        f'"A{i}"(x) B(y) < C > [D]E : x + y > k ->(2) F(x * k)[+G(y / 3)]"leaf"(sin(x))'
        for i in range(1000)
    )
    p = parse(text)
    assert len(p.rules) == 1000
    assert p.rules[-1].span.line == 1002
    assert p.rules[-1].left == (P("A999", "x"), P("B", "y"))
