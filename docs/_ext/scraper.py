"""sphinx-gallery's image scraper for uavcov's figures.

uavcov draws ``matplotlib.figure.Figure`` objects outside pyplot (no global figure list), so
sphinx-gallery's own matplotlib scraper does not see them: this one saves every figure an
example's code block has bound to a name since the previous block.

A plotly figure (:func:`uavcov.plotting.view`) bound to a name is embedded in the page as is,
interactive, with plotly.js inlined: the site, like ``uavcov view``'s files, fetches nothing.
"""

from __future__ import annotations

from typing import Any

_SEEN: dict[str, set[int]] = {}


def _is_plotly(value: Any) -> bool:
    return type(value).__module__.startswith("plotly.") and hasattr(value, "to_html") and hasattr(value, "layout")


def _embedded(fig: Any) -> str:
    """The figure as a raw-HTML block: one ``div`` (class ``uavcov-view``) with plotly.js inside."""
    html = fig.to_html(
        full_html=False,
        include_plotlyjs=True,
        auto_play=False,
        default_width="100%",
        default_height="720px",
        config={"displaylogo": False, "responsive": True},
    )
    body = "\n".join("    " + line for line in html.splitlines())
    return f'\n\n.. raw:: html\n\n    <div class="uavcov-view">\n{body}\n    </div>\n\n'


def figure_scraper(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    seen = _SEEN.setdefault(str(block_vars["src_file"]), set())
    names = []
    embedded = []
    for value in list(block_vars["example_globals"].values()):
        figures = value if isinstance(value, (list, tuple)) else [value]
        for fig in figures:
            if id(fig) in seen:
                continue
            if isinstance(fig, Figure):
                seen.add(id(fig))
                path = next(block_vars["image_path_iterator"])
                fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.1)  # legends outside the axes kept
                names.append(path)
            elif _is_plotly(fig):
                seen.add(id(fig))
                embedded.append(_embedded(fig))
    return figure_rst(names, gallery_conf["src_dir"]) + "".join(embedded)
