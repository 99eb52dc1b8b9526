"""Published example systems of the seeds, as text, shared by the dialect tests."""

from __future__ import annotations

from collections import Counter

from sylva.lsystem.ast import Program

# --------------------------------------------------------------------------- seed 000 §3
BUSH_WITHOUT_LEAVES = """\
;number of iterations
iteration: 7

;default angle of rotation
angle: 22.5

;axiom
axiom: A

;production rules
rule: A -> [&FA]/////[&FA]////////[&FA]
rule: F -> S ///// F
rule: S -> F
"""

BUSH_WITH_LEAVES = """\
;počet iterací
iteration: 7

;default angle of rotation
angle: 22.5

;next piece's thickness will be 95% of current thickness
reduction: 0.95

;initial radius
radius: 0.3

;axiom
axiom: A

;production rules
rule: A -> [&FXA]///// [&FXA]//////// [&FXA]
rule: F -> S ///// F
rule: S -> FX
rule: X -> [^^L]
"""

BUSH_STOCHASTIC = """\
;number of iterations
iteration: 7

;default angle of rotation
angle: 22.5

;axiom
axiom: A

;production rules
rule: A -> ///// [&FXA]//////// [&FXA]
rule: A -> [&FXA]//////// [&FXA]
rule: A -> [&FXA]///// [&FXA]//////// [&FXA]
rule: A -> [&FXA]//////// [&FXA]////////
rule: F -> S ///// F
rule: S -> FX
rule: S -> F
rule: X -> [^^L]
rule: X -> [^^^L]
"""

HILBERT_3D = """\
; 3D Hilbert curve (seed 000 §3.2, ABOP Fig. 1.11)
iteration: 2
angle: 90
axiom: A
rule: A -> B - F + CFC + F - D &F ^ D - F + &&CFC + F + B //
rule: B -> A &F ^ CFB ^ F ^ D ^^ - F - D ^ | F ^ B | FC ^ F ^ A //
rule: C -> | D ^ | F ^ B - F + C ^ F ^ A &&FA &F ^ C + F + B ^ F ^ D //
rule: D -> | CFB - F + B | FA &F ^ A &&FB - F + B | FC //
"""

CLASSIC = {
    "bush_without_leaves": BUSH_WITHOUT_LEAVES,
    "bush_with_leaves": BUSH_WITH_LEAVES,
    "bush_stochastic": BUSH_STOCHASTIC,
    "hilbert_3d": HILBERT_3D,
}

# --------------------------------------------------------------------------- seed 004 §4.7-4.8
ACACIA = """\
45.0 45.0 0.8
# make sure the plant has splits
# random lenght stem - then split
^uA1S&F+F+F+F
U > uU
A > +uuE
A > -uE
A > +uE
A > -E
A > uuE
A > uE
# top of the plant
E > x[++++UE1S&F+F+F+F]+UE
E > x[++++++UE1S&F+F+F+F]++UE
E > x[++UE1S&F+F+F+F]-UE
"""

TEST_VECTOR = """\
0 90 0.7
X
X > U[&X][^X]UX
U > UU
"""

ENGINE = {"acacia": ACACIA, "test_vector": TEST_VECTOR}

# --------------------------------------------------------------------------- seed 001 §3, §8.3
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

LSYS = {
    "source_code_1": SOURCE_CODE_1,
    "source_code_2": SOURCE_CODE_2,
    "T1": "axiom = a\na -> b\nb -> aa",
    "T2": "axiom = a\na -> b\na ->(3) c",
    "T3": "axiom = baaaaa\nb < a -> ab\nb ->\naaaaa < b -> x",
    "T4": "ignore = i\naxiom = xia\nx < a -> b",
    "T5": "axiom = fk(3)la(8, 9, 10)m(4, 5)n\nk(x)l < a(y, z) -> b(x + y)c(x)d",
    "T6": "axiom = a(3)\na(x) -> a(x - 1)\na(x) : x == 0 -> c",
    "T8": "axiom = a[bc]d[e[f][g]h]i\ne -> x[y]z",
    "T9": "axiom = a[bc]d[e[f][g]h]i\na d e < h -> X",
    "T10": "axiom = a[bc]d[e[f][g]h]i\n"
    + "\n".join(
        [
            "a > di -> x",
            "a > [b] -> x",
            "a > [bc] -> x",
            "a > [b]d[e] -> x",
            "a > [b]d[e]i -> x",
            "a > d[eh]i -> x",
            "a > d[e[f][g]] -> x",
        ]
    ),
    "T11": "axiom = l\nl ->> [-F+F+F-|-F+F+F]",
    "T13": "x = 1\nfoo = 0\naxiom = A(1)\n"
    'H(x, foo) IJ < A(y) > K"el"(z) : x+y>0 || foo -> X(1)Y(y*sin(z))Z',
    "parametric": "a = 2\nb = a ** 2 - -1\nsteps = 4\nseed = 7\nturtle = abop\n"
    'consider = AB"leaf"\naxiom = A(b, -b)[B(a / 2)]\n'
    "A(x, y) > [B(z)] : x * 2 >= -y && !(z < 1) ->(x + 1) A(x - 1, -y)[+B(x ** -1)]\n"
    'B(z) ->> "leaf"(z % 3, pow(z, 2), sum(z, 1, 2))',
}


def rewrite(program: Program, steps: int) -> str:
    """Derive a deterministic context-free program without parameters (a test oracle)."""
    table: dict[str, str] = {}
    for rule in program.productions:
        assert not rule.has_context and rule.condition is None
        assert rule.predecessor.symbol not in table, "deterministic systems only"
        table[rule.predecessor.symbol] = "".join(m.symbol for m in rule.successor)
    word = "".join(m.symbol for m in program.axiom)
    for _ in range(steps):
        word = "".join(table.get(c, c) for c in word)
    return word


def counts(word: str) -> Counter:
    return Counter(word)
