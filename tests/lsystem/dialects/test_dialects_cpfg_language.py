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
        ("Lsystem: 1\nring L-system: on\n", 2, 1, "'ring lsystem' alone on its line"),
        ("Lsystem: 1\nAxiom: A\nStartEach: { x = ; }\n", 3, 18, "unexpected ';'"),
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
seed: 1
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


# ------------------------------------------------------------------------------ view files
KOCH = """Lsystem: koch
derivation length: 1
Axiom: F-F-F-F
F --> F-F+F+FF-F-F+F
endlsystem
"""


def test_the_view_file_beside_the_l_sets_angle_width_and_tropism(tmp_path):
    from sylva.errors import SylvaWarning

    (tmp_path / "koch.l").write_text(KOCH)
    (tmp_path / "koch.v").write_text(
        "angle increment: 60\nline style: cylinder\ninitial line width: 0.25\n"
        "tropism direction: 0 -3 0\ninitial elasticity: 0.2\nelasticity increment: 0.01\n"
        "viewpoint: 0,0,1\nview reference point: 0,0,0\n"
        "frobnicate: 1\n"
    )
    with pytest.warns(SylvaWarning) as record:
        p = load(tmp_path / "koch.l")
    assert p.settings["rot"] == 60.0 and p.settings["thick"] == 0.25
    assert p.settings["tropism"] == (0.0, -1.0, 0.0)  # normalised, as cpfg does
    assert (p.settings["elasticity"], p.settings["elasticity_step"]) == (0.2, 0.01)
    messages = [str(w.message) for w in record]
    # one warning per line that is not honoured, each naming its line; the camera lines
    # are the renderer's (Camera.from_view), not warned about
    assert len(messages) == 1
    assert ":9: unknown view setting 'frobnicate: 1'" in messages[0]
    # the turtle turns by the view file's 60 degrees: F++F++F is a closed equilateral
    # triangle of side 1 (width 1, height sqrt(3)/2), ABOP Fig. 1.10's snowflake axiom
    import numpy as np

    from sylva.turtle import interpret

    g = interpret("F++F++F", p.replace(settings={**p.settings, "elasticity": 0.0}))
    lo, hi = g.bounds()
    extent = sorted(hi - lo)
    assert np.allclose(extent, [0.0, 3**0.5 / 2, 1.0], atol=1e-9)


def test_view_file_angle_factor_pixel_widths_and_named_view(tmp_path):
    from sylva.errors import SylvaWarning

    other = tmp_path / "other.v"
    other.write_text("angle factor: 8\ninitial line width: 3 pixels\n")
    with pytest.warns(SylvaWarning, match=r"other.v:2: 'initial line width' is in pixels"):
        p = loads(KOCH, view=other)
    assert p.settings["rot"] == 45.0 and "thick" not in p.settings
    # a width without 'pixels' after it is in units: cpfg's reader makes the line style
    # polygon (and a later 'line style:' wins, as cpfg reads the lines in order)
    other.write_text("initial line width: 3\n")
    assert loads(KOCH, view=other).settings["thick"] == 3.0
    from sylva.lsystem.dialects._cpfg_view import read_camera

    assert read_camera(other)["line style"] == "polygon"
    other.write_text("line style: cylinder\ninitial line width: 2 p\n")
    assert read_camera(other)["line style"] == "pixel"
    other.write_text("initial line width: 2 pixels\nline style: cylinder\n")
    assert loads(KOCH, view=other).settings["thick"] == 2.0
    (tmp_path / "koch.l").write_text(KOCH)
    (tmp_path / "koch.v").write_text("angle increment: 60\n")
    assert load(tmp_path / "koch.l", view=False).settings.get("rot") is None
    assert load(tmp_path / "koch.l").settings["rot"] == 60.0
    (tmp_path / "koch.v").write_text("angle increment: ninety\n")
    # cpfg reports "Invalid parameters" and keeps its default: a warning naming the place
    with pytest.warns(SylvaWarning, match=r"koch.v:1:17: angle increment: the value 'ninety' "
                      "is not a number; the setting keeps its default"):  # fmt: skip
        assert load(tmp_path / "koch.l").settings.get("rot") is None


# ------------------------------------------------------------------------------ statements
STATEMENTS = """#define K 2
Lsystem: 1
Define: { array a[4]; }
Start: {
  n = 0;
  for (i = 0; i < 4; i++) {   /* a[i] = i^2 */
    a[i] = i^2;
    n += a[i];                 // 0 + 1 + 4 + 9 = 14
  }
  if (n > 10) big = 1; else big = 0;
  j = K; j *= 3; j -= 1; j /= 5; j++; ++j; j--;   // ((2*3-1)/5)+1+1-1 = 2
  k = 10; while (k > 3) k = k - 4;                // 10, 6, 2
  do { k += 1; } while (k < 5);                   // 3, 4, 5
  m = max(fabs(-3), min(7, 9)) + sign(-2) + trunc(2.7) + floor(-0.5);  // 7 - 1 + 2 - 1
}
derivation length: 2
Axiom: A(0)
A(x) : big && x < n --> F(x) A(x + n/7)
End: { done = 1; }
endlsystem
"""


def test_define_and_start_blocks_set_the_globals_the_productions_read():
    p = loads(STATEMENTS, filename="plant.l")
    c = dict(p.constants)
    assert (c["n"], c["big"], c["i"], c["K"]) == (14.0, 1.0, 4.0, 2.0)
    assert (c["j"], c["k"], c["m"]) == (2.0, 5.0, 7.0)
    # Start runs before the first step: n = 14, so A(x) grows by 14/7 = 2 while x < 14
    assert str(derive(p, 2)) == "F(0)F(2)A(4)"
    assert "done" not in c  # End: runs after the last step; it cannot change the word


def test_random_functions_follow_the_seed_and_srand():
    text = (
        "Lsystem: 1\nseed: {}\nStart: {{ {} r = ran(10); s = nran(0, 1); }}\nAxiom: A\nendlsystem\n"
    )
    a = dict(loads(text.format(3, "")).constants)
    b = dict(loads(text.format(3, "")).constants)
    c = dict(loads(text.format(4, "")).constants)
    d = dict(loads(text.format(4, "srand(3);")).constants)
    assert a == b and a != c and {k: d[k] for k in "rs"} == {k: a[k] for k in "rs"}
    assert 0.0 <= a["r"] < 10.0


def test_a_statement_block_that_never_ends_stops_at_the_budget():
    from sylva.errors import SylvaError
    from sylva.lsystem.dialects._cpfg_statements import STEP_BUDGET

    text = "Lsystem: 1\nAxiom: A\nStart: {\n  x = 0;\n  while (1) x++;\n}\nendlsystem\n"
    with pytest.raises(SylvaError, match=rf"plant.l:3 \(Start: block\): .*{STEP_BUDGET:,} steps"):
        loads(text, filename="plant.l")


def test_a_bad_statement_names_its_line_and_column_inside_a_multi_line_block():
    text = "Lsystem: 1\nStart: {\n  x = 1;\n  y = (x + ;\n}\nAxiom: A\nendlsystem\n"
    with pytest.raises(LSystemSyntaxError) as e:
        loads(text, filename="plant.l")
    err = e.value
    assert (err.line, err.column, err.source_line) == (4, 12, "  y = (x + ;")


def test_errors_after_a_block_and_a_define_keep_their_columns():
    # a derivation length and a #define value that are wrong, after a multi-line block
    text = "#define N (1 +\nLsystem: 1\nStart: {\n x = 1;\n}\nderivation length: 2 +\n"
    with pytest.raises(LSystemSyntaxError) as e:
        loads(text, filename="plant.l")
    assert (e.value.line, e.value.source_line) == (6, "derivation length: 2 +")


def test_a_blank_line_ends_a_production_and_a_directive_continues_with_a_backslash():
    text = ("#define BRANCH(a) [+(a) \\\n   F]\nLsystem: 1\nderivation length: 1\n"
            "Axiom: A#\nA --> BRANCH(20) B\n\nstray words\nendlsystem\n")
    with pytest.raises(LSystemSyntaxError) as e:
        loads(text, filename="p.l")
    assert e.value.line == 8  # not read as more of the successor above the blank line
    p = loads(text.replace("stray words\n", ""))
    assert str(derive(p, 1)) == '[+(20)F]B"#"'  # the axiom's '#' is a module too


EACH = """Lsystem: 1
Start: { t = 1; }
StartEach: { t = t * 2; }   /* before each step */
EndEach: {
  c++;                      // after each step: c counts the steps done
}
derivation length: 3
Axiom: A
A : c < 2 --> F(t) A
A : c >= 2 --> G(t) A
endlsystem
"""


def test_starteach_and_endeach_run_around_every_step():
    from sylva.lsystem import Derivation

    p = loads(EACH, filename="plant.l")
    # step 1: t = 2, c = 0 -> F(2) A, then c = 1; step 2: t = 4, c = 1 -> F(4); then c = 2;
    # step 3: t = 8, c = 2 -> G(8)
    assert str(derive(p)) == "F(2)F(4)G(8)A"
    d = Derivation(p)
    d.advance(3)
    assert str(d.back()) == "F(2)F(4)A"  # the globals step back with the word
    assert str(d.advance()) == "F(2)F(4)G(8)A"
    assert str(derive(p, 3)) == str(derive(p, 3))  # a fresh copy of the globals per run
    assert dict(p.constants) == {"t": 1.0, "c": 0.0}  # c is first set between steps: 0
    with pytest.raises(ValueError, match="no .lsys form"):
        dumps(p)
    assert loads(EACH) == p


def test_an_endeach_loop_that_never_ends_stops_with_the_step_it_ran_after():
    from sylva.errors import SylvaError

    text = "Lsystem: 1\nEndEach: { while (1) x = 1; }\nAxiom: A\nA --> AA\nendlsystem\n"
    p = loads(text, filename="plant.l")
    with pytest.raises(SylvaError, match=r"plant.l:2 \(EndEach: block\), after step 1: .* steps"):
        derive(p, 2)


def test_a_start_block_after_the_productions_still_runs_before_the_first_step():
    text = "Lsystem: 1\nAxiom: A\nA : go --> B\nStart: { go = 1; }\nendlsystem\n"
    assert str(derive(loads(text), 1)) == "B"
