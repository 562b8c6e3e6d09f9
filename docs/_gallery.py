"""The gallery's image scraper for the package's own figures (named in ``conf.py``)."""

#: ids of the figures already shown, per example file
_SHOWN = {}


def package_figures(block, block_vars, gallery_conf):
    """Scrape the figures the package draws without pyplot (``matplotlib.figure.Figure``).

    The package never uses pyplot state, so sphinx-gallery's matplotlib scraper cannot see
    its figures; this one saves every Figure (or an Axes' Figure) the example's code block
    left in a variable and has not shown yet. It runs before sphinx-gallery's matplotlib
    scraper, which shows (and closes) the figures pyplot manages.
    """
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    shown = _SHOWN.setdefault(block_vars["src_file"], set())
    found = []

    def collect(value):
        if isinstance(value, Axes):
            value = value.figure
        if isinstance(value, Figure) and id(value) not in shown:
            shown.add(id(value))  # pyplot's are still open here: the next scraper's
            if value.canvas.manager is None:
                found.append(value)
        elif isinstance(value, list | tuple):
            for item in value:
                if isinstance(item, Axes | Figure):
                    collect(item)

    for value in block_vars["example_globals"].values():
        collect(value)
    paths = []
    for figure, path in zip(found, block_vars["image_path_iterator"], strict=False):
        figure.savefig(path, dpi=90)
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])
