"""A sphinx-gallery image scraper for rocknroller's examples.

The package draws on pyplot-free :class:`matplotlib.figure.Figure` objects, and its paper modules return a
:class:`rocknroller.papers.output.Reproduction` listing the PNG files they wrote.  After each code block this
scraper collects, from the example's global variables, every Figure (saved as PNG) and every Reproduction (its
PNG files copied) it has not shown yet, and pyplot's open figures too.
"""

from __future__ import annotations

import shutil


class RocknrollerScraper:
    """Callable scraper ``(block, block_vars, gallery_conf) -> rST``; remembers what it has shown."""

    def __init__(self) -> None:
        self._shown: dict[int, object] = {}  # id -> object (kept alive, so that ids are not reused)

    def __repr__(self) -> str:  # sphinx-gallery hashes the configuration through repr
        return "RocknrollerScraper()"

    def __getstate__(self) -> dict:  # Sphinx pickles its configuration: the figures shown stay behind
        return {"_shown": {}}

    def _new(self, obj: object) -> bool:
        if id(obj) in self._shown:
            return False
        self._shown[id(obj)] = obj
        return True

    def __call__(self, block, block_vars, gallery_conf) -> str:
        import matplotlib.pyplot as plt
        from matplotlib.figure import Figure
        from sphinx_gallery.scrapers import figure_rst

        from rocknroller.papers.output import Reproduction

        paths = block_vars["image_path_iterator"]
        written = []
        for value in list(block_vars["example_globals"].values()):
            if isinstance(value, Figure) and self._new(value):
                path = next(paths)
                value.savefig(path, dpi=110, bbox_inches="tight")
                written.append(path)
            elif isinstance(value, Reproduction) and self._new(value):
                for png in (p for p in value.outputs if str(p).endswith(".png")):
                    path = next(paths)
                    shutil.copyfile(png, path)
                    written.append(path)
        for num in plt.get_fignums():
            fig = plt.figure(num)
            path = next(paths)
            fig.savefig(path, dpi=110, bbox_inches="tight")
            written.append(path)
        plt.close("all")
        return figure_rst(written, gallery_conf["src_dir"])
