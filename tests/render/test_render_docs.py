"""The examples in the render modules' docstrings run."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "sylva.render.animate",
    "sylva.render.camera",
    "sylva.render.context",
    "sylva.render.lights",
    "sylva.render.offscreen",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0


def test_public_api_is_sorted_and_complete():
    import sylva.render as render

    assert render.__all__ == sorted(render.__all__)
    for name in render.__all__:
        assert getattr(render, name) is not None
