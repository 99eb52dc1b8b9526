"""``explore(program)``: sliders for a program's numeric globals and its step count."""

from __future__ import annotations

import dataclasses
import math

import ipywidgets as w

from ..errors import SylvaError
from ._view import PlantView

__all__ = ["Explorer", "explore", "slider_range"]

#: Numeric special variables that get a slider beside the user's globals (seed 001 §3.7).
SETTINGS = ("rot", "angle", "len", "thick", "reduction")


def slider_range(value: float) -> tuple[float, float, float]:
    """``(min, max, step)`` of a slider around ``value``: from 0 (or twice a negative
    value) to twice the value, in about 200 steps of a round size."""
    v = float(value)
    if v == 0:
        return -1.0, 1.0, 0.01
    lo, hi = (0.0, 2 * v) if v > 0 else (2 * v, -2 * v)
    raw = (hi - lo) / 200
    step = 10 ** math.floor(math.log10(raw))
    for k in (1, 2, 5):
        if k * step >= raw:
            step *= k
            break
    return lo, hi, step


class Explorer(w.VBox):
    """Sliders over a :class:`PlantView` (see :func:`explore`).

    Attributes
    ----------
    view : PlantView
    sliders : dict of str to ipywidgets slider
        One per global (and numeric special variable), plus ``"steps"``.
    message : ipywidgets.HTML
        Why the last change was refused, in red; empty when it was not.
    """

    def __init__(self, program, *, steps: int, max_steps: int, seed: int, limit: int,
                 height: int) -> None:  # fmt: skip
        from ..plant import is_2d

        self.program = program
        self.seed = seed
        self.limit = limit
        values = {k: float(v) for k, v in program.constants.items()
                  if isinstance(v, (int, float)) and not isinstance(v, bool)}  # fmt: skip
        settings = {k: float(program.settings[k]) for k in SETTINGS
                    if isinstance(program.settings.get(k), (int, float))}  # fmt: skip
        self.sliders: dict[str, w.Widget] = {}
        style = {"description_width": "initial"}
        layout = w.Layout(width="100%")
        for name, v in {**values, **settings}.items():
            lo, hi, step = slider_range(v)
            self.sliders[name] = w.FloatSlider(value=v, min=lo, max=hi, step=step,
                                               description=name, continuous_update=True,
                                               style=style, layout=layout)  # fmt: skip
        self.sliders["steps"] = w.IntSlider(value=steps, min=0, max=max_steps,
                                            description="steps", continuous_update=False,
                                            style=style, layout=layout)  # fmt: skip
        self._constants = set(values)
        self._last = (steps, {k: s.value for k, s in self.sliders.items() if k != "steps"})
        self.view = PlantView(self._build, step=steps, max_steps=max_steps,
                              camera="2d" if is_2d(program) else "perspective",
                              height=height)  # fmt: skip
        self.message = w.HTML("")
        self.view.observe(self._show_error, names="error")
        self.view.observe(self._follow_step, names="step")
        for s in self.sliders.values():
            s.observe(self._changed, names="value")
        super().__init__([*self.sliders.values(), self.message, self.view])

    # ------------------------------------------------------------------ changes
    def values(self) -> dict[str, float]:
        """The slider values of the globals (not ``steps``)."""
        return {k: s.value for k, s in self.sliders.items() if k != "steps"}

    def set(self, **values) -> None:
        """Move sliders from Python (``ex.set(angle=30, steps=4)``); a value a slider cannot
        take is refused with a :class:`SylvaError` naming the allowed range."""
        for name, v in values.items():
            s = self.sliders.get(name)
            if s is None:
                raise SylvaError(f"no slider {name!r}; expected one of "
                                 + ", ".join(self.sliders))  # fmt: skip
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise SylvaError(f"{name}: expected a number, got {v!r}")
            if not s.min <= v <= s.max:
                raise SylvaError(f"{name}: expected a value in {s.min:g}..{s.max:g}, got {v!r}")
            if name == "steps" and int(v) != v:
                raise SylvaError(f"steps: expected a whole number, got {v!r}")
        for name, v in values.items():
            self.sliders[name].value = int(v) if name == "steps" else float(v)

    def _changed(self, change) -> None:
        wanted = (self.sliders["steps"].value, self.values())
        if wanted != self._last:
            # a global's slider may be being dragged: a large plant previews as lines
            drag = change is not None and change.get("owner") is not self.sliders["steps"]
            self._last = wanted
            ask = self.view.request_preview if drag else self.view.request
            ask(wanted[0], **wanted[1])

    def _follow_step(self, change) -> None:  # the view's own step slider moved
        if self.sliders["steps"].value != change["new"] and not self.view.busy:
            self.sliders["steps"].value = change["new"]

    def _show_error(self, change) -> None:
        msg = change["new"]
        self.message.value = (f'<span style="color:#b00020">{_escape(msg)}</span>'
                              if msg else "")  # fmt: skip

    def _build(self, step: int, **values):
        from ..plant import grow_geometry

        return grow_geometry(self.program_with(values), step, seed=self.seed,
                             limit=self.limit)[-1]

    def program_with(self, values: dict[str, float]):
        """The program with these global and special-variable values."""
        consts = {k: v for k, v in values.items() if k in self._constants}
        sets = {k: v for k, v in values.items() if k not in self._constants}
        p = self.program
        return dataclasses.replace(p, constants={**p.constants, **consts},
                                   settings={**p.settings, **sets})  # fmt: skip

    def wait(self, timeout: float | None = 60.0) -> bool:
        """Wait for the derivations in flight."""
        return self.view.wait(timeout)


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def explore(source, steps: int | None = None, *, max_steps: int | None = None,
            seed: int | None = None, limit: int | None = None, height: int = 420) -> Explorer:
    """Sliders for a program's numeric globals (L-Py's scalars) and its step count over a
    live three.js view; moving one re-derives in a background thread (changes that come
    while it works are coalesced into the newest), so the kernel never waits.

    Parameters
    ----------
    source : Program, path, example name or L-system text
    steps : int, optional
        The starting step count (default: the program's, else 4).
    max_steps : int, optional
        The steps slider's end (default: twice ``steps``, at least 8).
    seed : int, optional
        As :func:`sylva.grow`.
    limit : int, optional
        The module limit; a change that would pass it is refused with its message.

    Examples
    --------
    >>> from sylva.widgets import explore
    >>> ex = explore("angle = 30\\naxiom = F\\nF -> F[+(angle)F]F", 2)
    >>> sorted(ex.sliders)
    ['angle', 'steps']
    >>> ex.set(angle=45); ex.wait()
    True
    >>> ex.view.error
    ''
    """
    from ..lsystem import DEFAULT_MODULE_LIMIT
    from ..plant import resolve

    if not isinstance(source, (str, bytes)) and not hasattr(source, "rules") and \
            not hasattr(source, "__fspath__"):
        raise SylvaError(f"explore: expected a Program, a path, an example name or L-system "
                         f"text, got {type(source).__name__}")  # fmt: skip
    program = resolve(source)
    n = steps if steps is not None else (program.steps if program.steps is not None else 4)
    for what, v in (("steps", n), ("max_steps", max_steps), ("height", height)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 0):
            raise SylvaError(f"{what}: expected a whole number >= 0, got {v!r}")
    top = max_steps if max_steps is not None else max(8, 2 * n)
    if top < n:
        raise SylvaError(f"max_steps: expected at least steps ({n}), got {top}")
    if seed is None:
        seed = program.seed if program.seed is not None else 1
    return Explorer(program, steps=n, max_steps=top, seed=seed,
                    limit=DEFAULT_MODULE_LIMIT if limit is None else limit,
                    height=height)  # fmt: skip
