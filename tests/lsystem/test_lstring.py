"""ModuleString: text in and out, the compact layout, the bracket structure."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sylva.errors import LSystemSyntaxError, SylvaError
from sylva.lsystem.lstring import Alphabet, ModuleString


def test_seed001_t12_six_symbols():
    w = ModuleString.from_text('a"jmeno1"[b(5, 6)"dlouhe_jmeno"(9.5, -4)]')
    assert w.symbols() == ["a", "jmeno1", "[", "b", "dlouhe_jmeno", "]"]
    assert w[3] == ("b", (5.0, 6.0))
    assert w[4] == ("dlouhe_jmeno", (9.5, -4.0))
    assert w.nparams.tolist() == [0, 0, 0, 2, 2, 0]


def test_layout_is_compact_arrays():
    w = ModuleString.from_text("F(1)[+(30)F(0.5,2)]")
    assert w.ids.dtype == np.uint16
    assert w.offsets.tolist() == [0, 1, 1, 2, 4, 4]
    assert w.values.tolist() == [1.0, 30.0, 0.5, 2.0]


def test_text_round_trip_exact_numbers():
    text = 'A(0.1,-2.5e-07)"long"(3)[B]C(1.1428571428571428)'
    assert ModuleString.from_text(text).to_text() == text


def test_seed001_t7_tree_structure():
    # a[bc]d[e[f][g]h]i, Figure 1 of seed 001
    w = ModuleString.from_text("a[bc]d[e[f][g]h]i")
    s = w.symbols()
    par = {s[i]: (s[p] if p >= 0 else None) for i, p in enumerate(w.parent) if s[i] not in "[]"}
    assert par == {
        "a": None, "b": "a", "c": "b", "d": "a", "e": "d", "f": "e", "g": "e", "h": "e",
        "i": "d",
    }
    assert w.match[1] == 4 and w.match[4] == 1
    assert w.parent_vectorised().tolist() == w.parent.tolist()
    assert w.max_depth() == 2


@settings(max_examples=300, deadline=None)  # the first example compiles on a cold cache
@given(st.lists(st.sampled_from(list("ab[]")), max_size=60))
def test_compiled_tree_structure_equals_vectorised(chars):
    # keep only balanced prefixes: drop unmatched ']' and close what is open
    out, depth = [], 0
    for c in chars:
        if c == "]":
            if depth == 0:
                continue
            depth -= 1
        elif c == "[":
            depth += 1
        out.append(c)
    out += ["]"] * depth
    w = ModuleString.from_text("".join(out))
    assert w.match.tolist() == w.match_vectorised().tolist()
    assert w.parent.tolist() == w.parent_vectorised().tolist()


def test_unbalanced_brackets_are_reported():
    with pytest.raises(LSystemSyntaxError, match="never opened"):
        ModuleString.from_text("a]b").check_brackets()
    with pytest.raises(LSystemSyntaxError, match="open"):
        ModuleString.from_text("a[b").check_brackets()


def test_bad_text_names_line_and_column():
    with pytest.raises(LSystemSyntaxError) as e:
        ModuleString.from_text("ab\nc(1, x)", filename="w.txt")
    assert e.value.filename == "w.txt" and e.value.line == 2
    assert "expected a number" in str(e.value)


def test_slices_and_concat_keep_parameters():
    w = ModuleString.from_text("A(1)B(2,3)C")
    assert str(w[1:]) == "B(2,3)C"
    assert str(ModuleString.concat([w[2:], w[:2]])) == "CA(1)B(2,3)"


def test_alphabet_ids_are_stable_and_bounded():
    a = Alphabet(["F", "+"])
    assert (a.id("["), a.id("]"), a.id("F"), a.id("+")) == (0, 1, 2, 3)
    assert a.id("X") == 4 and a.get("nope") == -1
    with pytest.raises(SylvaError):
        big = Alphabet()
        for i in range(70000):
            big.id(f"s{i}")
