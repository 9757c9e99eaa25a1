"""A sphinx-gallery image scraper for the package's figures.

contactvib's figure functions return :class:`matplotlib.figure.Figure` objects that pyplot does not
manage (so the matplotlib scraper, which reads pyplot's figures, does not see them): this scraper
saves every Figure bound to a name of the example's globals after a code block, once each.
"""

from __future__ import annotations

_SAVED: dict[str, set[int]] = {}


def _scraper(block, block_vars, gallery_conf):
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    seen = _SAVED.setdefault(block_vars["src_file"], set())
    pyplot = {id(plt.figure(n)) for n in plt.get_fignums()}  # the matplotlib scraper saves these
    paths = []
    for value in list(block_vars["example_globals"].values()):
        if isinstance(value, Figure) and id(value) in pyplot:
            seen.add(id(value))
        elif isinstance(value, Figure) and id(value) not in seen:
            seen.add(id(value))
            path = next(block_vars["image_path_iterator"])
            value.savefig(path, dpi=80)
            paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])


def _get_sg_image_scraper():
    return _scraper
