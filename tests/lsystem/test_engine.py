"""Derivation against the published examples of seeds 000, 001, 004 and ABOP."""

from collections import Counter

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sylva.data import find
from sylva.errors import GrowthLimitError, LSystemSemanticError
from sylva.lsystem import Derivation, ModuleString, derive, iterate, load, loads, render_word


def words(text, steps=None, seed=1):
    return [str(w) for w in iterate(loads(text), steps, seed=seed)]


# ----------------------------------------------------------------------------- seed 001
def test_t1_d0l():
    assert words("axiom = a\na -> b\nb -> aa", 4) == ["a", "b", "aa", "bb", "aaaa"]


def test_t2_weighted_choice_is_a_quarter_and_three_quarters():
    p = loads("axiom = " + "a" * 4000 + "\na -> b\na ->(3) c")
    c = derive(p, 1, seed=7).counts()
    assert c["b"] + c["c"] == 4000
    assert abs(c["c"] / 4000 - 0.75) < 0.03


def test_t3_context_sensitive_with_empty_successor():
    got = words("axiom = baaaaa\nb < a -> ab\nb ->\naaaaa < b -> x", 6)
    assert got == ["baaaaa", "abaaaa", "aabaaa", "aaabaa", "aaaaba", "aaaaab", "aaaaax"]


def test_t4_ignore():
    assert words("ignore = i\naxiom = xia\nx < a -> b", 1)[1] == "xib"


def test_t5_binding_and_extra_parameters():
    p = loads("axiom = fk(3)la(8, 9, 10)m(4, 5)n\nk(x)l < a(y, z) -> b(x + y)c(x)d")
    assert derive(p, 1) == ModuleString.from_text("fk(3)lb(11)c(3)dm(4, 5)n")


def test_t6_conditional_rule_has_priority():
    got = words("axiom = a(3)\na(x) -> a(x - 1)\na(x) : x == 0 -> c", 4)
    assert got == ["a(3)", "a(2)", "a(1)", "a(0)", "c"]


def test_t8_rewriting_in_a_tree():
    got = words("axiom = a[bc]d[e[f][g]h]i\ne -> x[y]z", 1)[1]
    assert got == "a[bc]d[x[y]z[f][g]h]i"


def test_t9_left_context_is_the_ancestor_path():
    got = words("axiom = a[bc]d[e[f][g]h]i\na d e < h -> X\nb < h -> Y", 1)[1]
    assert got == "a[bc]d[e[f][g]X]i"


@pytest.mark.parametrize(
    "rc", ["di", "[b]", "[bc]", "[b]d[e]", "[b]d[e]i", "d[eh]i", "d[e[f][g]]"]
)
def test_t10_right_contexts_on_the_tree(rc):
    got = words(f"axiom = a[bc]d[e[f][g]h]i\na > {rc} -> x", 1)[1]
    assert got == "x[bc]d[e[f][g]h]i"


def test_t11_render_rule_makes_a_separate_word():
    p = loads("axiom = Fl\nl ->> [-F+F+F-|-F+F+F]\nF -> FF")
    d = Derivation(p, seed=1)
    assert str(d.render_word()) == "F[-F+F+F-|-F+F+F]"
    d.advance()
    assert str(d.word) == "FFl"  # the render word never feeds back
    assert str(render_word(p, d.word)) == "FF[-F+F+F-|-F+F+F]"


def test_t14_source_code_2_lengths_and_render_words():
    p = load(find("seed001-source-code-2").path)
    d = Derivation(p, seed=1)
    table = [(1, 0, 1, 2, 1), (12, 2, 3, 15, 5), (47, 10, 9, 56, 19), (156, 38, 27, 183, 65),
             (491, 130, 81, 572, 211), (1512, 422, 243, 1755, 665)]
    for step, (n, f, x, rn, rf) in enumerate(table):
        r = d.render_word()
        assert (len(d.word), d.word.count("F"), d.word.count("X")) == (n, f, x), step
        assert (len(r), r.count("F")) == (rn, rf), step
        d.advance()
    p1 = Derivation(p, seed=1)
    p1.advance()
    assert str(p1.word) == "F[+X]F[-X]+(20)X"
    assert str(p1.render_word()) == "F[+;(0,0.7,0)F]F[-;(0,0.7,0)F]+(20);(0,0.7,0)F"


def test_t15_source_code_1():
    p = load(find("seed001-source-code-1").path)
    ws = list(iterate(p, 4))
    assert [(len(w), w.count("F")) for w in ws] == [(1, 1), (10, 4), (46, 16), (190, 64),
                                                  (766, 256)]
    assert str(ws[2]) == "F[+F][-F]F[+F[+F][-F]F][-F[+F][-F]F]F[+F][-F]F"


def test_binding_arity_rules():
    assert words("axiom = a(1)\na(x, y) -> b", 1)[1] == "a(1)"
    assert words("axiom = a(1, 2)\na(x) -> b(x)", 1)[1] == "b(1)"


def test_priority_conditional_over_context_over_free():
    rules = "a -> b\nx < a -> c\na(t) : t > 0 -> d"
    got = words("axiom = a x a(1) x a(0) a(0)\n" + rules, 1)[1]
    # plain a: free; a(1) after x: conditional wins; a(0) after x: context; last a(0): free
    assert got == "bxdxcb"


def test_globals_are_constants_in_rules():
    assert words("k = 2\nj = k * 3\naxiom = A(1)\nA(x) -> A(x * j + k)", 2)[2] == "A(50)"


def test_cut_removes_the_rest_of_the_branch():
    got = words("axiom = A[B%CD[E]F]G\nB -> B", 1)
    assert got[0] == "A[B%CD[E]F]G"  # step 0 is the axiom as written
    assert got[1] == "A[B]G"  # ABOP: % and the rest of its branch are gone after a step


# ----------------------------------------------------------------------------- seed 000
def test_seed000_anabaena_follows_the_printed_derivation():
    p = load(find("anabaena").path)
    got = [w.symbols() for w in iterate(p, 4)]
    assert got[:4] == [["ar"], ["al", "br"], ["bl", "ar", "ar"], ["al", "al", "br", "al", "br"]]
    assert got[4] == ["bl", "ar", "bl", "ar", "ar", "bl", "ar", "ar"]
    assert [len(w) for w in got] == [1, 2, 3, 5, 8]


def test_seed000_hilbert_3d():
    p = load(find("seed000-hilbert-3d").path)
    assert p.steps == 2
    for n, (length, f) in enumerate([(1, 0), (29, 7), (271, 63), (2155, 511)]):
        w = derive(p, n)
        assert (len(w), w.count("F")) == (length, f)


def test_seed000_bracketed_plant_table():
    p = loads("iteration: 7\nangle: 25.7\naxiom: X\nrule: X -> F[+X][-X]FX\nrule: F -> FF")
    table = [(1, 0), (11, 2), (43, 10), (143, 38), (451, 130), (1391, 422), (4243, 1330),
             (12863, 4118)]
    for w, (length, f) in zip(iterate(p), table, strict=True):
        assert (len(w), w.count("F")) == (length, f)
    assert (w.count("X"), w.count("[")) == (2187, 2186)


def test_seed000_bushes():
    w = derive(load(find("seed000-bush").path))
    assert (len(w), w.count("F"), w.count("A"), w.count("S"), w.count("[")) == (
        40888, 3891, 2187, 1284, 3279)
    w = derive(load(find("seed000-bush-leaves").path))
    assert (len(w), w.count("F"), w.count("L"), w.count("X"), w.count("[")) == (
        49915, 3891, 1284, 2607, 4563)


def test_seed000_stochastic_bush_is_uniform_and_varies_with_seed():
    p = load(find("seed000-bush-stochastic").path)
    fs = [derive(p, seed=s).count("F") for s in range(40)]
    assert len(set(fs)) > 10
    assert min(fs) >= 450 and max(fs) <= 1500  # seed 000's observed range is 462-1416
    assert 600 < np.mean(fs) < 880  # seed 000: mean about 738


def test_seed000_parametric_example_abop_p42():
    p = load(find("abop-2.10-parametric").path)
    got = [str(w) for w in iterate(p, 5)]
    assert got[:5] == ["B(2)A(4,4)", "B(1)B(4)A(1,0)", "B(0)B(3)A(2,1)", "CB(2)A(4,3)",
                       "CB(1)A(8,7)"]
    assert got[5].startswith("CB(0)B(8)A(1.142857")


# ----------------------------------------------------------------------------- seed 004
def test_seed004_parser_test_vector():
    p = loads("0 0 0.7\nX\nX > U[&X][^X]UX\nU > UU\n")
    assert words("0 0 0.7\nX\nX > U[&X][^X]UX\nU > UU\n", 2) == [
        "X", "U[&X][^X]UX", "UU[&U[&X][^X]UX][^U[&X][^X]UX]UUU[&X][^X]UX"]
    assert p.settings["turtle"] == "engine"


def test_seed004_acacia_choices_are_uniform():
    p = load(find("acacia").path)
    # A has 6 equiprobable successors: count them over many seeds after one step
    firsts = Counter()
    for s in range(600):
        w = str(derive(p, 1, seed=s))
        firsts[w[2:w.index("1")]] += 1
    assert len(firsts) == 6
    assert all(60 < k < 140 for k in firsts.values())


# ----------------------------------------------------------------------------- ABOP
def naive_step(word, rules, ignore=frozenset()):
    """An independent, obviously slow reference: one module at a time, on a list of chars."""
    match = {}
    stack = []
    for i, c in enumerate(word):
        if c == "[":
            stack.append(i)
        elif c == "]":
            j = stack.pop()
            match[i], match[j] = j, i

    def left_ok(i, ctx):
        k = i - 1
        for want in reversed(ctx):
            while True:
                if k < 0:
                    return False
                c = word[k]
                if c == "]":
                    k = match[k] - 1
                elif c == "[" or (c in ignore and c != want):
                    k -= 1
                elif c == want:
                    break
                else:
                    return False
            k -= 1
        return True

    def right_ok(i, ctx):
        k = i + 1
        for want in ctx:
            while True:
                if k >= len(word) or word[k] == "]":
                    return False
                c = word[k]
                if c == "[":
                    k = match[k] + 1
                elif c in ignore and c != want:
                    k += 1
                elif c == want:
                    break
                else:
                    return False
            k += 1
        return True

    out = []
    for i, c in enumerate(word):
        for lc, pred, rc, succ in rules:
            if pred == c and left_ok(i, lc) and right_ok(i, rc):
                out.append(succ)
                break
        else:
            out.append(c)
    return "".join(out)


def parse_ctx_rules(text):
    rules = []
    for line in text.splitlines():
        if "->" not in line or line.startswith("#"):
            continue
        lhs, succ = (s.strip() for s in line.split("->"))
        lc, rc = "", ""
        if "<" in lhs:
            lc, lhs = (s.strip() for s in lhs.split("<"))
        if ">" in lhs:
            lhs, rc = (s.strip() for s in lhs.split(">"))
        rules.append((lc.replace(" ", ""), lhs, rc.replace(" ", ""), succ.replace(" ", "")))
    return rules


@pytest.mark.parametrize("fig", ["1.31a", "1.31b", "1.31c", "1.31d", "1.31e"])
def test_abop_1_31_context_sensitive_plants_match_a_naive_reference(fig):
    ex = find(f"abop-{fig}-hogeweg")
    text = ex.path.read_text()
    p = load(ex.path)
    assert p.ignore == frozenset("+-F")
    rules = parse_ctx_rules(text)
    axiom = next(line.split("=")[1].strip() for line in text.splitlines()
                 if line.startswith("axiom"))
    ref = axiom
    for w in iterate(p):
        assert str(w) == ref
        ref = naive_step(ref, rules, ignore=frozenset("+-F"))
    assert w.count("[") > 5  # the signal produced branches


@pytest.mark.parametrize(
    "name, n, length",
    [("abop-1.6-quadratic", 3, None), ("abop-1.7b", 4, None), ("abop-1.8-islands", 2, None),
     ("abop-1.9a", 4, None), ("abop-1.10a", 10, None), ("abop-1.10b", 6, None),
     ("abop-1.11a", 4, None),
     ("abop-1.24a-plant", 5, None), ("abop-1.24b-plant", 5, None),
     ("abop-1.24c-plant", 4, None), ("abop-1.24d-plant", 7, None),
     ("abop-1.24e-plant", 7, 12863), ("abop-1.24f-plant", 5, None)],
)
def test_abop_d0l_figures_grow_as_their_rules_count(name, n, length):
    p = load(find(name).path)
    assert p.steps == n
    # word length obeys the counting recurrence of the rules (an independent check)
    rules = {r.predecessor.symbol: [m.symbol for m in r.successor] for r in p.productions}
    counts = Counter(m.symbol for m in p.axiom)
    for _ in range(n):
        new = Counter()
        for s, k in counts.items():
            for t in rules.get(s, [s]):
                new[t] += k
        counts = new
    w = derive(p)
    assert w.counts() == counts
    if length is not None:
        assert len(w) == length


@pytest.mark.parametrize(
    "name, expected",
    [("abop-1.6-quadratic-koch-island", "-".join(["F-F+F+FF-F-F+F"] * 4)),
     ("abop-1.10a-dragon-curve", None)],
)
def test_abop_koch_and_dragon(name, expected):
    p = load(find(name).path)
    if expected is not None:
        assert str(derive(p, 1)) == expected
    w = derive(p)
    assert w.count("F") == {"abop-1.6-quadratic-koch-island": 4 * 8**3,
                            "abop-1.10a-dragon-curve": 2**10}[name]


# ----------------------------------------------------------------------------- engine roads
def test_same_seed_same_word_and_different_seed_differs():
    p = load(find("abop-1.27-stochastic-plant").path)
    a, b, c = derive(p, seed=3), derive(p, seed=3), derive(p, seed=4)
    assert a == b and a != c


def _general(p, n, seed):
    from sylva.lsystem.engine import _Compiled

    d = Derivation(p, seed=seed)
    d._compiled = _Compiled(p)  # a private copy: the cached one stays fast
    d._compiled.productions.fast = False
    d._compiled.productions.ctx_fast = False
    assert d._compiled is not Derivation(p)._compiled
    for _ in range(n):
        d.advance(1)
    return d.word


rule_bodies = st.text(alphabet="AB+-", min_size=0, max_size=5).map(
    lambda s: s if "[" in s else s[:2] + ("[" + s[2:] + "]" if len(s) > 2 else "")
)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.tuples(st.sampled_from("AB"), rule_bodies, st.integers(1, 4)), min_size=1,
             max_size=5),
    st.integers(0, 2**32),
)
def test_fast_roads_equal_the_general_road(rules, seed):
    text = "axiom = A[B]A\n" + "\n".join(f"{a} ->({w}) {b}" for a, b, w in rules)
    p = loads(text)
    fast = derive(p, 4, seed=seed)
    assert fast == _general(p, 4, seed)
    stepwise = Derivation(p, seed=seed)
    for _ in range(4):
        stepwise.advance(1)
    assert fast == stepwise.word


contexts = st.sampled_from(["", "A <", "B <", "A B <", "[ <"])
rcontexts = st.sampled_from(["", "> A", "> B", "> [A]", "> [B]A", "> A[B]"])


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(contexts, st.sampled_from("AB"), rcontexts, rule_bodies, st.integers(1, 3)),
        min_size=1,
        max_size=6,
    ),
    st.integers(0, 2**32),
    st.booleans(),
)
def test_compiled_context_road_equals_the_general_road(rules, seed, ignore_plus):
    lines = [f"{lc.replace('[ <', '')} {a} {rc} ->({w}) {b}" for lc, a, rc, b, w in rules]
    text = ("ignore = +\n" if ignore_plus else "") + "axiom = A[B+A]+B[A]A\n" + "\n".join(lines)
    p = loads(text)
    assert derive(p, 4, seed=seed) == _general(p, 4, seed)


def test_d0l_block_expansion_equals_stepping():
    p = load(find("abop-1.24f-plant").path)
    d = Derivation(p)
    for _ in range(5):
        d.advance(1)
    assert derive(p) == d.word == _general(p, 5, 0)


def test_step_back_and_iterate_agree():
    p = load(find("abop-1.27-stochastic-plant").path)
    d = Derivation(p, seed=9)
    ws = [str(w) for w in iterate(p, 4, seed=9)]
    d.advance(4)
    for k in range(4, 0, -1):
        assert str(d.word) == ws[k]
        d.back()
    assert str(d.word) == ws[0] and d.step == 0


def test_growth_limit_stops_with_the_last_word_kept():
    p = loads("axiom = F\nF -> FF")
    with pytest.raises(GrowthLimitError) as e:
        derive(p, 30, limit=1000)
    assert "limit" in str(e.value) and len(e.value.word) <= 1000
    with pytest.raises(GrowthLimitError):
        derive(loads("axiom = A(1)\nA(x) -> A(x)A(x)"), 30, limit=1000)


def test_unknown_variable_in_a_rule_names_its_line():
    with pytest.raises(LSystemSemanticError) as e:
        derive(loads("axiom = A(1)\n\nA(x) -> A(y)"), 1)
    assert e.value.line == 3


def test_trace_names_the_rule_and_step_of_every_module():
    p = loads("axiom = X\nX -> F[+X]F[-X]+X\nF -> FF\nX ->> ;F")
    d = Derivation(p, trace=True, seed=1)
    assert d.origin(0) == (None, 0)
    d.advance(2)
    w = d.word
    # step 2 rewrote every F of step 1 into FF and every X into F[+X]F[-X]+X
    first = [(d.origin(i)[0].predecessor.symbol, d.origin(i)[1]) for i in range(5)]
    assert w.symbols()[:5] == ["F", "F", "[", "+", "F"]
    assert first == [("F", 2), ("F", 2), ("X", 1), ("X", 1), ("X", 2)]
    assert d.origin(2)[0].span.line == 2
    assert str(d.word) == str(Derivation(p, seed=1).advance(2))  # tracing changes nothing
    rw, src = d.render_word_sources()
    assert len(src) == len(rw) and rw.count("F") == w.count("F") + w.count("X")
    assert all(w.symbols()[s] == "X" for s, m in zip(src, rw.symbols()) if m == ";")
    d.back()
    assert d.step == 1 and len(d.origin_steps) == len(d.word)


def test_non_finite_parameter_names_the_rule(tmp_path):
    f = tmp_path / "div.lsys"
    f.write_text("axiom = F(1)\nF(x) -> F(x/0)\n")
    d = Derivation(load(f))
    with pytest.raises(LSystemSemanticError) as e:
        d.advance(1)
    assert e.value.line == 2 and "non-finite" in str(e.value) and "^" in str(e.value)
    assert d.step == 0 and str(d.word) == "F(1)"  # nothing lost
