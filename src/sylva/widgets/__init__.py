"""sylva in Jupyter: an interactive three.js view and sliders that re-derive a program.

* :func:`view` — a plant (with a step slider), a tree (swaying in the wind), a world, a
  scene or a mesh in a three.js view: the studio's viewer (same lights and camera: orbit
  with the left button, pan with the right, zoom with the wheel, F4 frames it all), sent
  as binary glTF.  ``plant.show()`` is the same.
* :func:`explore` — sliders for a program's numeric globals (L-Py's scalars) and its
  step count over a view; changes re-derive in a background thread, newest first, and a
  value the program refuses leaves the last mesh with the reason in red.

Plants, trees and worlds also display as a PNG by themselves (``_repr_png_``), which is
what nbconvert and GitHub show.  Needs the ``notebook`` extra
(``pip install sylva[notebook]``: anywidget, ipywidgets).
"""

from ._explore import Explorer, explore, slider_range
from ._view import PlantView, esm, glb_bytes, view

__all__ = ["Explorer", "PlantView", "esm", "explore", "glb_bytes", "slider_range", "view"]
