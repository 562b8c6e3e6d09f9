"""Sphinx configuration of the tactilecal documentation site.

Build (what ``.ci/run`` does; warnings are errors, every gallery example runs)::

    python -m pip install -e ".[docs]"
    python -m sphinx -W --keep-going -b html docs docs/_build/html

The pages are MyST markdown (``docs/*.md``); the API reference is generated from each
subpackage's ``__all__`` (``docs/_api.py``) and the docstrings (numpydoc, autosummary); the
gallery runs the scripts of ``docs/examples`` (sphinx-gallery).
"""

import sys
from pathlib import Path

import matplotlib

import tactilecal

matplotlib.use("Agg")
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import _api  # noqa: E402  (docs/_api.py, beside this file)

project = "tactilecal"
author = "tactilecal developers"
copyright = "tactilecal developers, BSD 3-Clause"
release = version = tactilecal.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "examples/README.rst", "**/README.md"]
templates_path = ["_templates"]

# MyST: the pages stay plain markdown that renders on GitHub too
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]
suppress_warnings = ["myst.header"]

# autodoc, autosummary and numpydoc
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"
autodoc_default_options = {"member-order": "bysource"}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# the API pages, written from __all__ before Sphinx reads the sources
_api.write_pages(HERE / "api")

html_theme = "pydata_sphinx_theme"
html_title = f"tactilecal {version}"
html_theme_options = {"navigation_depth": 2, "show_toc_level": 2}
html_static_path = []


sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("_gallery.package_figures", "matplotlib"),
    "download_all_examples": False,
    "remove_config_comments": True,
    "reference_url": {"tactilecal": None},
    "show_memory": False,
}
