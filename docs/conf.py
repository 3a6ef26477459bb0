"""Sphinx configuration for the balance documentation."""

import os
import sys

# Make the package at the repository root importable for autodoc.
sys.path.insert(0, os.path.abspath(".."))
sys.path.insert(0, os.path.abspath("_ext"))

project = "balance"
author = "The balance contributors"
copyright = "the balance contributors"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx.ext.mathjax",
    "gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]

numpydoc_show_class_members = False

autodoc_member_order = "bysource"

exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]

html_theme = "alabaster"
html_theme_options = {
    "description": "Engine balancing analyser",
    "fixed_sidebar": True,
}
html_static_path = ["_static"]
