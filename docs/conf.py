"""Sphinx configuration of the contactvib documentation.

Build: ``sphinx-build -W -n -b html docs docs/_build/html`` (warnings are errors, every
cross-reference must resolve). The API pages and the benchmarks page are generated at build time
(``docs/_ext/generate.py``) from the packages' ``__all__`` and the committed
``benchmarks/results_*.json``; the gallery is run by sphinx-gallery from ``docs/examples``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(DOCS.parent / "src"))  # the package of this checkout, installed or not

from generate import (  # noqa: E402
    write_api_pages,
    write_benchmarks_page,
    write_dataset_page,
    write_laws_page,
    write_statements_page,
)

import contactvib  # noqa: E402

project = "contactvib"
author = "the contactvib authors"
copyright = "contactvib authors"  # noqa: A001
release = version = contactvib.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.intersphinx",
    "sphinx_click",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_ext", "generated", "**/GALLERY_HEADER.rst"]
# equations: $...$, $$...$$ and amsmath environments, typeset by MathJax
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_dmath_double_inline = True
# no typographic replacements: `--pa` must stay two hyphens (docutils' smart quotes would make an
# en dash of it in the command-line reference, and a copied option would fail)
smartquotes = False
myst_heading_anchors = 3

html_theme = "pydata_sphinx_theme"
html_title = f"contactvib {version}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2, "header_links_before_dropdown": 4}

# numpydoc: the docstrings are numpydoc; no class members table (each class documents its own)
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()
# signatures without annotations: the parameters' types are in the numpydoc sections
autodoc_typehints = "none"
autodoc_member_order = "bysource"

intersphinx_mapping = {}  # offline build: no inventories are fetched
# third-party names in docstrings' prose (their projects' inventories are not fetched offline)
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|np|xarray|xr|matplotlib|scipy|dask|distributed|click|panel|pathlib)\..*"),
]

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("gallery_scraper", "matplotlib"),
    "matplotlib_animations": False,
    "reset_modules": ("matplotlib",),
}
os.environ.setdefault("MPLBACKEND", "Agg")


def setup(app):
    write_api_pages(DOCS / "api")
    write_benchmarks_page(DOCS.parent / "benchmarks", DOCS / "benchmarks.md")
    write_statements_page(DOCS.parent, DOCS / "generated" / "paper_statements.md")
    write_dataset_page(DOCS / "generated" / "dataset_variables.md")
    write_laws_page(DOCS / "generated" / "laws_table.md")
