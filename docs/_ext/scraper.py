"""sphinx-gallery's image scraper for uavcov's figures.

uavcov draws ``matplotlib.figure.Figure`` objects outside pyplot (no global figure list), so
sphinx-gallery's own matplotlib scraper does not see them: this one saves every figure an
example's code block has bound to a name since the previous block.
"""

from __future__ import annotations

from typing import Any

_SEEN: dict[str, set[int]] = {}


def figure_scraper(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    seen = _SEEN.setdefault(str(block_vars["src_file"]), set())
    names = []
    for value in list(block_vars["example_globals"].values()):
        figures = value if isinstance(value, (list, tuple)) else [value]
        for fig in figures:
            if isinstance(fig, Figure) and id(fig) not in seen:
                seen.add(id(fig))
                path = next(block_vars["image_path_iterator"])
                fig.savefig(path, dpi=90)
                names.append(path)
    return figure_rst(names, gallery_conf["src_dir"])
