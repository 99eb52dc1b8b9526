"""cpfg's preprocessor and its multi-line productions: small models of our own, each
derived by hand from what the cpfg manual says the construct means."""

from __future__ import annotations

import pytest

from sylva.errors import LSystemSyntaxError
from sylva.lsystem import derive, load, loads
from sylva.lsystem.dialects import dumps


def _word(text, steps=None, **kw):
    p = loads(text, filename="plant.l", **kw)
    return str(derive(p, p.steps if steps is None else steps))


def test_define_with_parameters_expressions_and_trailing_comments():
    text = """#define ANGLE 30 /* degrees */
#define LEN (2*ANGLE/30) // an expression over another constant
#define BRANCH(a, l) [+(a)F(l)]
#define LEAF [~]
Lsystem: 1
derivation length: 1
Axiom: A
A --> F(LEN) BRANCH(ANGLE, LEN+1) LEAF A
endlsystem
"""
    p = loads(text, filename="plant.l")
    assert dict(p.constants) == {"ANGLE": 30.0, "LEN": 2.0}  # numbers stay named constants
    # BRANCH(ANGLE, LEN+1) is [+(ANGLE)F(LEN+1)]: +(30) F(3); LEAF is [~]
    assert str(derive(p, 1)) == "F(2)[+(30)F(3)][~]A"


def test_a_hash_inside_a_production_is_the_width_module_not_a_comment():
    # the known bug: "A --> F#F" read as "A --> F"
    text = "#define W 1\nLsystem: 1\nderivation length: 1\nAxiom: A\nA --> F#F # F\nendlsystem\n"
    p = loads(text)
    assert [m.symbol for m in p.rules[0].successor] == ["F", "#", "F", "#", "F"]
    assert str(derive(p, 1)).count("#") == 2
    assert loads(dumps(p)) == p


def test_ifdef_ifndef_else_and_if_with_constant_expressions():
    text = """#define TREE
#define N 3
#ifdef TREE
#define STEM F
#else
#define STEM G
#endif
#ifndef BUSH
#define X 1
#endif
#if N*2 > 5 && defined(TREE)
#define Y 10
#elif N > 1
#define Y 20
#else
#define Y 30
#endif
#if UNDEFINED_NAME
#define Z 1
#else
#define Z 2
#endif
Lsystem: 1
derivation length: 1
Axiom: A
A --> STEM(X) STEM(Y) STEM(Z)
endlsystem
"""
    assert _word(text) == "F(1)F(10)F(2)"


def test_include_is_relative_to_the_file_and_errors_keep_the_included_line(tmp_path):
    (tmp_path / "inc").mkdir()
    (tmp_path / "inc" / "params.h").write_text('#define R 0.5\n#include "more.h"\n')
    (tmp_path / "inc" / "more.h").write_text("#define GROW(x) F(x*R)\n")
    main = tmp_path / "plant.l"
    main.write_text(
        '#include "inc/params.h"\nLsystem: 1\nderivation length: 2\n'
        "Axiom: A(4)\nA(x) --> GROW(x) A(x*R)\nendlsystem\n"
    )
    # step 1: F(4*0.5) A(2); step 2: F(2) F(2*0.5) A(1)
    assert str(derive(load(main), 2)) == "F(2)F(1)A(1)"
    (tmp_path / "inc" / "more.h").write_text("\n#define GROW(x) F(x*R\n")
    (tmp_path / "bad.l").write_text(
        '#include "inc/params.h"\nLsystem: 1\nAxiom: A(4)\nA(x) --> GROW(x) A(x)\nendlsystem\n'
    )
    with pytest.raises(LSystemSyntaxError) as e:
        load(tmp_path / "bad.l")
    # the unbalanced parenthesis is reported where the user wrote the macro's use
    assert e.value.filename == str(tmp_path / "bad.l") and e.value.line == 4


def test_a_missing_include_and_a_self_include_are_clear_errors(tmp_path):
    main = tmp_path / "a.l"
    main.write_text('Lsystem: 1\n  #include "nowhere.h"\n')
    with pytest.raises(LSystemSyntaxError) as e:
        load(main)
    assert (e.value.line, e.value.column) == (2, 13) and "nowhere.h" in str(e.value)
    loop = tmp_path / "loop.h"
    loop.write_text('#include "loop.h"\n')
    main.write_text('#include "loop.h"\nLsystem: 1\n')
    with pytest.raises(LSystemSyntaxError, match="nested deeper than 16"):
        load(main)


def test_an_error_in_an_included_file_names_that_file(tmp_path):
    (tmp_path / "rules.h").write_text("\n\nA --> F(x*)\n")
    main = tmp_path / "p.l"
    main.write_text('Lsystem: 1\nAxiom: A\n#include "rules.h"\nendlsystem\n')
    with pytest.raises(LSystemSyntaxError) as e:
        load(main)
    err = e.value
    assert (err.filename, err.line, err.column) == (str(tmp_path / "rules.h"), 3, 11)
    assert err.source_line == "A --> F(x*)"


@pytest.mark.parametrize(
    "text, line, column, words",
    [
        ("#if 1\nLsystem: 1\n", 1, 1, "#if without #endif"),
        ("#endif\n", 1, 1, "#endif without #if"),
        ("#if 1\n#else\n#else\n#endif\n", 3, 1, "#else after #else"),
        ("#define M(a) F(a)\nLsystem: 1\nAxiom: M(1, 2)\n", 3, 8, "takes 1 argument"),
        ("#define N 2\n#define N 3\n", 2, 9, "again with another value"),
        ("#if 1 +\n#endif\n", 1, 5, "constant expression"),
        ("Lsystem: 1\nring L-system: on\n", 2, 1, "ring l-system"),
        ("Lsystem: 1\nAxiom: A\nStart: { x = 1; }\n", 3, 1, "start:"),
    ],
)
def test_bad_directives_and_unsupported_constructs(text, line, column, words):
    with pytest.raises(LSystemSyntaxError) as e:
        loads(text, filename="plant.l")
    err = e.value
    assert (err.filename, err.line, err.column) == ("plant.l", line, column)
    assert words in str(err).lower() or words in str(err)


def test_multi_line_productions():
    text = """Lsystem: 1
derivation length: 1
Axiom: A(1)
A(x) : x > 0 --> F(x)
                 [+F(x/2)]
                 [-F(x/2)] A(x+1) : 0.5
A(x) : x > 0 --> G(x) \\
                 [+F] : 0.5
endlsystem
"""
    p = loads(text)
    first, second = p.rules
    assert "".join(m.symbol for m in first.successor) == "F[+F][-F]A"
    assert first.weight.value == 0.5
    assert "".join(m.symbol for m in second.successor) == "G[+F]"
    # F(1) [+F(0.5)] [-F(0.5)] A(2) or G(1) [+F], by the seeded choice
    assert str(derive(p, 1, seed=3)) in ("F(1)[+F(0.5)][-F(0.5)]A(2)", "G(1)[+F]")
    with pytest.raises(LSystemSyntaxError) as e:
        loads("Lsystem: 1\nAxiom: A\nA --> F(\n  1 +\n  )\n", filename="p.l")
    assert e.value.line == 5  # the error is on the continuation line where it is


def test_consider_and_ignore_in_either_case_and_seed():
    base = "Lsystem: 1\nderivation length: 1\nseed: 7\n{}\nAxiom: B A C\nB < A --> X\nendlsystem\n"
    for key in ("Consider: AB", "consider: AB", "CONSIDER: AB"):
        p = loads(base.format(key))
        assert p.consider == frozenset("AB") and p.seed == 7
        assert str(derive(p, 1)) == "BXC"
    for key in ("Ignore: +", "ignore: +"):
        assert loads(base.format(key)).ignore == frozenset("+")


def test_stochastic_productions_choose_by_their_probabilities():
    text = (
        "Lsystem: 1\nderivation length: 1\nseed: 1\nAxiom: {}\n"
        "A --> B : 0.25\nA --> C : 0.75\nendlsystem\n"
    ).format("A" * 4000)
    w = _word(text)
    assert w.count("B") + w.count("C") == 4000
    assert 0.21 < w.count("B") / 4000 < 0.29
