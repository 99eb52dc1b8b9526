"""Sphinx configuration of sylva's documentation (``make docs``)."""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(HERE.parent / "src"))  # the checkout's sylva, installed or not

import sylva  # noqa: E402

project = "sylva"
author = "the sylva authors"
copyright = "the sylva authors, MIT licence"
version = release = sylva.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.viewcode",
    "sylvadocs",
]

exclude_patterns = ["_build", "README.md"]
templates_path = []
html_static_path = ["_static"]
html_css_files = ["sylva.css"]
html_theme = "furo"
html_title = f"sylva {release}"
html_theme_options = {"navigation_with_keys": True}
html_last_updated_fmt = None
html_copy_source = False
pygments_style = "default"

# numpydoc docstrings, read by napoleon (no extra package)
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True
napoleon_preprocess_types = False
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_format = "short"
autosummary_generate = False
add_module_names = False
default_role = "code"
nitpicky = False
