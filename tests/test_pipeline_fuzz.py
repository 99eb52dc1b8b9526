"""Arbitrary programs through the whole pipeline raise nothing but SylvaError."""

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sylva.errors import SylvaError
from sylva.lsystem import loads
from sylva.plant import grow

ARGS = ["0", "1", "-2", "0.5", "1e6", "-1e-9", "90", "x", "x/0", "x*2", "x**400", "-x"]
SYMS = list("FfGg+-&^\\/|$!;',~.LUuxXS0123_%AB")


@st.composite
def words(draw, allow_args=True):
    out, depth = [], 0
    for _ in range(draw(st.integers(0, 8))):
        c = draw(st.sampled_from(SYMS + ["[", "]", "{", "}"]))
        if c in "]}":
            if depth == 0:
                continue
            depth -= 1
            c = "]"
        elif c in "[{":
            depth += 1
            c = "["
        elif allow_args and draw(st.booleans()) and draw(st.booleans()):
            c += "(" + draw(st.sampled_from(ARGS)) + ")"
        out.append(c)
    return "".join(out) + "]" * depth


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.sampled_from(["lsys", "abop", "classic", "engine"]),
    words(allow_args=False),
    st.lists(st.tuples(st.sampled_from(["F", "A(x)", "B", "A(x) : x > 1", "B < A(x)"]),
                       words()), min_size=1, max_size=3),
    st.integers(0, 2**31),
)
def test_any_program_grows_or_says_why(turtle, axiom, rules, seed):
    text = f"turtle = {turtle}\naxiom = {axiom}A(1)\n" + "\n".join(
        f"{p} -> {s}" for p, s in rules
    )
    try:
        plant = grow(loads(text), 3, seed=seed, limit=50_000)
    except SylvaError:
        return
    for mesh in plant.scene.meshes:
        assert mesh.indices.size == 0 or mesh.indices.max() < mesh.n_vertices
        assert np.isfinite(mesh.normals).all()
