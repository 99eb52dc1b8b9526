"""The Studio: an interactive L-system workbench in the browser.

``sylva studio [FILE]`` serves a local web app (Starlette on uvicorn, bound to 127.0.0.1)
whose front end ships in this package (three.js and CodeMirror bundled, nothing from a
CDN).  The server parses, derives and meshes in Python and sends binary glTF; the browser
edits, steps, views, traces rules and saves files inside the workspace.

>>> from sylva.studio import Limits
>>> Limits().max_modules > 0
True
"""

from ._limits import Limits
from .app import create_app, static_dir
from .server import serve

__all__ = ["Limits", "create_app", "serve", "static_dir"]
