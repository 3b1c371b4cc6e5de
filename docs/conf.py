"""Sphinx configuration of uavcov's documentation site (``bash scripts/docs.sh``).

Built with warnings as errors (``-W --keep-going``, nitpicky): a broken cross-reference, a
docstring numpydoc cannot parse or a tutorial that raises fails the build. The API reference is
one page per public name (``docs/api/*.rst``, autosummary); ``tests/test_docs.py`` checks that
every name of every layer's ``__all__`` is listed there. Tutorials and the gallery are
sphinx-gallery scripts (``docs/tutorials``, ``docs/gallery``) run at every build.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # _ext: the gallery's scraper and the cross-reference resolver

import uavcov  # noqa: E402

project = "uavcov"
author = "uavcov contributors"
copyright = "uavcov contributors"
release = version = uavcov.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax served from the site itself: equations render offline
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "_ext.crossrefs",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "**.ipynb_checkpoints",
    "tutorials/README.rst",
    "gallery/README.rst",
    # reports written by the experiments beside their figures (each has a page that shows it)
    "figures/**/*.md",
]
nitpicky = True
# The docstrings' signatures are read from the numpydoc sections (types with shapes and units),
# not from the annotations, whose private aliases and typing forms have no page to link to.
autodoc_typehints = "none"
templates_path = ["_templates"]
autosummary_generate = True
autosummary_imported_members = True
autoclass_content = "class"

numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = True
numpydoc_xref_ignore = "all"  # only the words below become links: the rest are prose ("(n, 3)", "metres")
numpydoc_xref_aliases = {
    "ndarray": "numpy.ndarray",
    "array": "numpy.ndarray",
    "Generator": "numpy.random.Generator",
    "SeedSequence": "numpy.random.SeedSequence",
    "Path": "pathlib.Path",
    "Terrain": "uavcov.engine.Terrain",
    "Targets": "uavcov.engine.Targets",
    "Visibility": "uavcov.engine.Visibility",
    "Sensor": "uavcov.engine.Sensor",
    "Camera": "uavcov.engine.Camera",
    "Gimbal": "uavcov.engine.Gimbal",
    "MissionSettings": "uavcov.settings.MissionSettings",
    "MissionResult": "uavcov.mission.MissionResult",
    "Constraints": "uavcov.limits.Constraints",
    "CVTSettings": "uavcov.placement.CVTSettings",
    "StartSettings": "uavcov.placement.StartSettings",
    "CAOSettings": "uavcov.optim.CAOSettings",
    "GeoDem": "uavcov.terrain.GeoDem",
    "PlanSettings": "uavcov.field.PlanSettings",
    "FlightPlan": "uavcov.field.FlightPlan",
}

# No network at build time: the inventories are small local files (docs/_inventories, written by
# docs/_inventories/make_inventories.py) holding only the objects the site links to.
intersphinx_mapping = {
    "python": ("https://docs.python.org/3/", str(HERE / "_inventories" / "python.inv")),
    "numpy": ("https://numpy.org/doc/stable/", str(HERE / "_inventories" / "numpy.inv")),
    "scipy": ("https://docs.scipy.org/doc/scipy/", str(HERE / "_inventories" / "scipy.inv")),
}

myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3

sphinx_gallery_conf = {
    "examples_dirs": ["tutorials", "gallery"],
    "gallery_dirs": ["auto_tutorials", "auto_gallery"],
    "filename_pattern": r".*\.py$",  # every script runs at every build
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("_ext.scraper.figure_scraper",),
    "reset_modules": (),
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "show_memory": False,
    "plot_gallery": "True",
}

html_theme = "pydata_sphinx_theme"
html_title = f"uavcov {release}"
html_theme_options = {
    "navigation_depth": 2,
    # Every top-level page in the bar (short titles, set in index.md's toctree), none in "More".
    "header_links_before_dropdown": 7,
    "show_toc_level": 2,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
# Pages with no section below them get no (empty) section navigation on the left.
html_sidebars = {"index": [], "getting-started": [], "method": []}
html_static_path: list[str] = []
html_show_sourcelink = False
# The figures the Markdown pages show live in docs/figures and are copied with the pages.
suppress_warnings: list[str] = []
