"""The examples in the dialect modules' docstrings run."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "sylva.lsystem.dialects",
    "sylva.lsystem.dialects.lsysvis",
    "sylva.lsystem.dialects.classic",
    "sylva.lsystem.dialects.engine",
    "sylva.lsystem.dialects._writer",
    "sylva.lsystem.dialects._diagnostics",
    "sylva.lsystem.dialects.cpfg",
    "sylva.lsystem.dialects._cpfg_view",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0
